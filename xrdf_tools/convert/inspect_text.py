"""The text form of :class:`~xrdf_tools.convert.inspect.Inspection`: a summary line, the tree of
joints and links, the chains to the leaves, the SRDF groups and the default choice."""

from __future__ import annotations

from collections.abc import Sequence

from .inspect import Inspection, JointView, chain_summary

__all__ = ["MAX_TREE_INDENT", "render_inspection"]

#: Levels of indentation the tree grows to; below that, a serial chain continues at the same
#: depth (a line without a connector is the child of the line above), so the text of a chain
#: of n joints grows with n, not n².
MAX_TREE_INDENT = 24

#: What a line's connector leaves for the lines below it.
_CARRIED = {"└─ ": "   ", "├─ ": "│  "}


def render_inspection(ins: Inspection) -> str:
    """Every section of ``ins`` as text lines (ending with a newline)."""
    lines = [_summary(ins), "", *_tree(ins), "", *_chains(ins)]
    if ins.frames:
        lines += ["", *_frames(ins)]
    if ins.srdf is not None:
        lines += ["", *_groups(ins)]
    lines += ["", *_default(ins)]
    return "\n".join(lines) + "\n"


def _summary(ins: Inspection) -> str:
    with_col = sum(1 for lk in ins.links if lk.collision)
    kinds: dict[str, int] = {}
    for j in ins.joints:
        kind = "mimic" if j.mimic_joint is not None else j.type
        kinds[kind] = kinds.get(kind, 0) + 1
    joints = ", ".join(f"{n} {k}" for k, n in kinds.items())
    return (
        f"robot '{ins.name}' ({ins.path}): {len(ins.links)} links ({with_col} with collision "
        f"geometry), {len(ins.joints)} joints ({joints or 'none'}), "
        f"{sum(1 for j in ins.joints if j.actuated)} actuated"
    )


def _limits(j: JointView) -> str:
    """`` [lower, upper]`` of a joint that moves between limits (a fixed joint's <limit>,
    which Kinova writes, limits nothing)."""
    if j.type in ("continuous", "fixed", "floating", "planar") or (
        j.lower is None and j.upper is None
    ):
        return ""
    lo = "?" if j.lower is None else f"{j.lower:g}"
    hi = "?" if j.upper is None else f"{j.upper:g}"
    return f" [{lo}, {hi}]"


def _joint_label(j: JointView, cspace_index: dict[str, int]) -> str:
    parts = [j.type + _limits(j)]
    if j.mimic_joint is not None:
        parts.append(f"mimic of {j.mimic_joint} ×{j.mimic_multiplier:g} {j.mimic_offset:+g}")
    if j.name in cspace_index:
        parts.append(f"c-space #{cspace_index[j.name] + 1}")
    elif j.role is not None:
        parts.append(f"left out: {j.role}")
    return f"{j.name} ({', '.join(parts)})"


def _tree(ins: Inspection) -> list[str]:
    """The tree from the root: one line per joint, ``joint (type …) → child link``."""
    joints = {j.name: j for j in ins.joints}
    collision = {lk.name: lk.collision for lk in ins.links}
    children: dict[str, list[str]] = {}
    for j in ins.joints:
        children.setdefault(j.parent, []).append(j.name)
    cspace_index = {n: i for i, n in enumerate(ins.default.cspace)}
    out = [
        "tree (joint (type [limits], …) → child link; '·' marks a link without collision geometry):"
    ]
    seen: set[str] = set()
    for root in ins.roots or (ins.root,):
        if root != ins.root:
            out.append(
                f"{root}{'' if collision.get(root) else ' ·'}  (not connected to '{ins.root}')"
            )
        else:
            out.append(root + ("" if collision.get(root) else " ·"))
        out += _subtree(root, joints, children, collision, cspace_index, seen)
    return out


def _subtree(
    root: str,
    joints: dict[str, JointView],
    children: dict[str, list[str]],
    collision: dict[str, int],
    cspace_index: dict[str, int],
    seen: set[str],
) -> list[str]:
    out: list[str] = []
    stack: list[tuple[str, str, str]] = [
        (name, "", "└─ " if i == 0 else "├─ ")
        for i, name in enumerate(reversed(sorted(children.get(root, []))))
    ]
    while stack:
        name, prefix, connector = stack.pop()
        if name in seen:
            continue
        seen.add(name)
        j = joints[name]
        mark = "" if collision.get(j.child) else " ·"
        out.append(f"{prefix}{connector}{_joint_label(j, cspace_index)} → {j.child}{mark}")
        below = sorted(children.get(j.child, []))
        carried = _CARRIED.get(connector, connector)
        if len(below) == 1 and len(prefix) >= 3 * MAX_TREE_INDENT:
            stack.append((below[0], prefix, carried))
            continue
        inner = prefix + carried
        stack.extend((n, inner, "└─ " if i == 0 else "├─ ") for i, n in enumerate(reversed(below)))
    return out


def _short(names: Sequence[str], n: int = 3) -> str:
    if len(names) <= 2 * n:
        return ", ".join(names)
    return f"{', '.join(names[:n])} … {', '.join(names[-n:])}"


def _chains(ins: Inspection) -> list[str]:
    actuated = {j.name for j in ins.joints if j.actuated}
    rows = chain_summary(ins.chains, actuated)
    out = [
        f"chains from '{ins.root}' (actuated joints on the way; leaves with the same joints "
        "on one line):"
    ]
    for joints, leaves in rows:
        out.append(f"  {len(joints):>2}  {_short(joints)}  →  {_short(leaves, 2)}")
    if not rows:
        out.append("  none: no actuated joint")
    return out


def _frames(ins: Inspection) -> list[str]:
    """Drake's ``<frame>`` elements: poses on links that are no links themselves."""
    out = [
        "Drake frames (<frame>: no links, so no XRDF reader sees them; `xrdf convert "
        "--tool-frame NAME` says how to make one a link):"
    ]
    for f in ins.frames:
        line = f", line {f.at[1]}" if f.at[1] else ""
        name, link = f.name or "(no name)", f.link or "(no link)"
        out.append(f"  {name} on {link} (xyz {f.xyz}, rpy {f.rpy}{line})")
    return out


def _groups(ins: Inspection) -> list[str]:
    out = [f"SRDF groups ({ins.srdf}):"]
    for g in ins.groups:
        if g.problem is not None:
            out.append(f"  {g.name}: does not resolve: {g.problem}")
            continue
        subs = f" [subgroups: {', '.join(g.subgroups)}]" if g.subgroups else ""
        odd = f" (left out, planar/floating: {', '.join(g.unplannable)})" if g.unplannable else ""
        joints = f": {_short(g.cspace)}" if g.cspace else ""
        out.append(f"  {g.name}: {len(g.cspace)} c-space joint(s){subs}{joints}{odd}")
    if not ins.groups:
        out.append("  none")
    return out


def _default(ins: Inspection) -> list[str]:
    d = ins.default
    head = (
        f"what `xrdf convert {' '.join(d.flags)}` picks"
        if d.flags
        else "what `xrdf convert` picks without --group/--chain/--joints"
    )
    if d.error is not None:
        return [f"{head}: nothing, it fails: {d.error}"]
    out = [f"{head}:"]
    out.append(f"  c-space ({len(d.cspace)}): {', '.join(d.cspace) or 'empty'}")
    out.append(f"  tool frame(s): {', '.join(d.tool_frames) or 'none'}")
    if d.chain_flag is not None:
        out.append(f"  the same with a flag: {d.chain_flag}")
    out += [f"  why: {n}" for n in d.notes]
    return out
