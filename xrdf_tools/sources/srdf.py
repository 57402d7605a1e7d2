"""MoveIt SRDF: parse it, expand planning groups the way MoveIt does, map it onto a Draft.

Group expansion (MoveIt ``RobotModel``, see docs/convert.md, "Sources"): a ``chain`` walks up
from ``tip_link`` adding each parent joint and stops at ``base_link`` (whose own parent joint is
not included); a ``joint`` is itself; a ``link`` contributes its parent joint; a subgroup
contributes all of its joints. Joints are ordered depth-first in URDF tree order (siblings by
name). The c-space is the group's joints minus fixed, mimic and passive joints.
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from typing import Any

from ..diagnostics import Severity
from ..errors import SourceError, did_you_mean
from ..fileio import read_input_bytes
from ..graph import nodes_on_cycles, postorder, reachable, show_path
from ..model import Sphere
from . import Draft, Reporter, RobotTree, known_frame

__all__ = [
    "EndEffector",
    "GroupState",
    "Srdf",
    "SrdfGroup",
    "choose_group",
    "cspace_of",
    "group_joints",
    "load_srdf",
    "parse_srdf",
    "read_srdf",
]

PREFERRED_STATES = ("home", "ready", "default")


@dataclass(frozen=True)
class SrdfGroup:
    name: str
    links: tuple[str, ...] = ()
    joints: tuple[str, ...] = ()
    chains: tuple[tuple[str, str], ...] = ()
    subgroups: tuple[str, ...] = ()
    line: int | None = None


@dataclass(frozen=True)
class GroupState:
    name: str
    group: str | None
    values: tuple[tuple[str, float], ...]
    line: int | None = None


@dataclass(frozen=True)
class EndEffector:
    name: str
    parent_link: str
    group: str | None
    parent_group: str | None
    line: int | None = None


@dataclass(frozen=True)
class Srdf:
    path: str
    robot_name: str
    groups: dict[str, SrdfGroup] = field(default_factory=dict)
    group_states: tuple[GroupState, ...] = ()
    end_effectors: tuple[EndEffector, ...] = ()
    virtual_joints: tuple[tuple[str, str, int | None], ...] = ()  # name, type, line
    passive_joints: tuple[str, ...] = ()
    disable_collisions: tuple[tuple[str, str, str, int | None], ...] = ()  # l1, l2, reason, line
    disable_default: tuple[tuple[str, int | None], ...] = ()
    enable_collisions: tuple[tuple[str, str, int | None], ...] = ()
    spheres: tuple[tuple[str, tuple[Sphere, ...], int | None], ...] = ()


def load_srdf(path: str | os.PathLike[str]) -> Srdf:
    """Read an SRDF file; raises :class:`SourceError` (with the line) when it cannot be used."""
    p = os.fspath(path)
    return parse_srdf(read_input_bytes(p, what="SRDF file", error=SourceError), p)


def parse_srdf(data: bytes | str, path: str = "<srdf>") -> Srdf:
    from lxml import etree

    raw = data.encode("utf-8") if isinstance(data, str) else data
    parser = etree.XMLParser(resolve_entities=False, no_network=True, remove_comments=True)
    try:
        root = etree.fromstring(raw, parser)
    except etree.XMLSyntaxError as e:
        line = e.position[0] if e.position else None
        msg = (e.msg or "not well-formed").splitlines()[0]
        raise SourceError(f"malformed SRDF XML: {msg}", path=path, line=line) from None
    if root is None or root.tag != "robot":
        raise SourceError("the root element of an SRDF must be <robot>", path=path, line=1)

    def req(el: Any, attr: str) -> str:
        v = el.get(attr)
        if not v:
            raise SourceError(
                f"<{el.tag}> needs a '{attr}' attribute", path=path, line=el.sourceline
            )
        return str(v)

    def num(el: Any, attr: str) -> float:
        raw_v = req(el, attr)
        try:
            return float(raw_v.split()[0])
        except (ValueError, IndexError):
            raise SourceError(
                f"<{el.tag}> {attr}='{raw_v}' is not a number", path=path, line=el.sourceline
            ) from None

    groups: dict[str, SrdfGroup] = {}
    states: list[GroupState] = []
    ees: list[EndEffector] = []
    vjs: list[tuple[str, str, int | None]] = []
    passive: list[str] = []
    disabled: list[tuple[str, str, str, int | None]] = []
    disable_default: list[tuple[str, int | None]] = []
    enabled: list[tuple[str, str, int | None]] = []
    spheres: list[tuple[str, tuple[Sphere, ...], int | None]] = []
    for el in root:
        if not isinstance(el.tag, str):
            continue
        tag = el.tag
        if tag == "group":
            name = req(el, "name")
            links, joints, chains, subs = [], [], [], []
            for c in el:
                if c.tag == "link":
                    links.append(req(c, "name"))
                elif c.tag == "joint":
                    joints.append(req(c, "name"))
                elif c.tag == "chain":
                    chains.append((req(c, "base_link"), req(c, "tip_link")))
                elif c.tag == "group":
                    subs.append(req(c, "name"))
            if name in groups:
                raise SourceError(
                    f"group '{name}' is defined twice (first on line {groups[name].line})",
                    path=path,
                    line=el.sourceline,
                )
            groups[name] = SrdfGroup(
                name, tuple(links), tuple(joints), tuple(chains), tuple(subs), el.sourceline
            )
        elif tag == "group_state":
            values = tuple((req(j, "name"), num(j, "value")) for j in el if j.tag == "joint")
            states.append(GroupState(req(el, "name"), el.get("group"), values, el.sourceline))
        elif tag == "end_effector":
            ees.append(
                EndEffector(
                    req(el, "name"),
                    req(el, "parent_link"),
                    el.get("group"),
                    el.get("parent_group"),
                    el.sourceline,
                )
            )
        elif tag == "virtual_joint":
            vjs.append((req(el, "name"), el.get("type") or "", el.sourceline))
        elif tag == "passive_joint":
            passive.append(req(el, "name"))
        elif tag == "disable_collisions":
            disabled.append(
                (req(el, "link1"), req(el, "link2"), el.get("reason") or "", el.sourceline)
            )
        elif tag == "disable_default_collisions":
            disable_default.append((req(el, "link"), el.sourceline))
        elif tag == "enable_collisions":
            enabled.append((req(el, "link1"), req(el, "link2"), el.sourceline))
        elif tag == "link_sphere_approximation":
            ss = []
            for s in el:
                if s.tag != "sphere":
                    continue
                c = req(s, "center").split()
                try:
                    center = (float(c[0]), float(c[1]), float(c[2]))
                except (ValueError, IndexError):
                    raise SourceError(
                        f"sphere center '{' '.join(c)}' must be three numbers",
                        path=path,
                        line=s.sourceline,
                    ) from None
                ss.append(Sphere(center, num(s, "radius")))
            spheres.append((req(el, "link"), tuple(ss), el.sourceline))
    return Srdf(
        path=path,
        robot_name=root.get("name") or "",
        groups=groups,
        group_states=tuple(states),
        end_effectors=tuple(ees),
        virtual_joints=tuple(vjs),
        passive_joints=tuple(passive),
        disable_collisions=tuple(disabled),
        disable_default=tuple(disable_default),
        enable_collisions=tuple(enabled),
        spheres=tuple(spheres),
    )


def _group(srdf: Srdf, name: str) -> SrdfGroup:
    if name not in srdf.groups:
        raise SourceError(
            f"no group '{name}' in the SRDF{did_you_mean(name, srdf.groups)} "
            f"(groups: {', '.join(srdf.groups) or 'none'})",
            path=srdf.path,
        )
    return srdf.groups[name]


def _virtual_joints(srdf: Srdf) -> set[str]:
    return {name for name, _type, _line in srdf.virtual_joints}


def _own_problems(srdf: Srdf, g: SrdfGroup, tree: RobotTree) -> list[str]:
    """What is wrong with the elements of group ``g`` itself (subgroups not followed)."""
    virtual = _virtual_joints(srdf)
    joints = [j for j in g.joints if j not in tree.joints and j not in virtual]
    links = [n for n in g.links if n not in tree.links]
    chain_links = [n for c in g.chains for n in c if n not in tree.links]
    subs = [s for s in g.subgroups if s not in srdf.groups]
    out = []
    for what, names, pool in (
        ("joint", joints, tree.joints),
        ("link", links, tree.links),
        ("chain link", chain_links, tree.links),
        ("subgroup", subs, srdf.groups),
    ):
        if names:
            out.append(_unknown(what, names, pool))
    for base, tip in g.chains:
        if base in tree.links and tip in tree.links and base not in (tip, *tree.ancestors(tip)):
            out.append(f"chain base '{base}' is not an ancestor of tip '{tip}'")
    return out


def _unknown(what: str, names: list[str], pool: Iterable[str]) -> str:
    shown = ", ".join(f"'{n}'" for n in names[:6])
    more = f" and {len(names) - 6} more" if len(names) > 6 else ""
    plural = "s" if len(names) > 1 else ""
    hint = did_you_mean(names[0], pool).removeprefix("; ").removesuffix("?")
    hint = f" ({hint} for '{names[0]}'?)" if hint else ""
    return f"unknown {what}{plural} {shown}{more}{hint}"


def check_groups(srdf: Srdf, tree: RobotTree) -> None:
    """Raise :class:`SourceError` when any group names joints, links or subgroups that do
    not exist (virtual joints are known), or has a chain whose base is not above its tip.

    Every broken group is named with its unknown names, whether or not it is the group
    being converted: a broken group is a broken SRDF, never silently skipped.
    """
    broken = [(g, _own_problems(srdf, g, tree)) for g in srdf.groups.values()]
    broken = [(g, p) for g, p in broken if p]
    if not broken:
        return
    parts = [f"group '{g.name}' (line {g.line}): {'; '.join(p)}" for g, p in broken]
    raise SourceError(
        f"{len(broken)} SRDF group(s) do not match the URDF: " + " | ".join(parts),
        path=srdf.path,
        line=broken[0][0].line,
    )


def _own_joints(srdf: Srdf, gname: str, tree: RobotTree) -> set[str]:
    """Joints that group ``gname`` names itself (joints, links, chains; not its subgroups)."""
    g = _group(srdf, gname)
    found: set[str] = set()

    def fail(msg: str) -> SourceError:
        return SourceError(f"group '{g.name}': {msg}", path=srdf.path, line=g.line)

    virtual = _virtual_joints(srdf)
    for j in g.joints:
        if j in virtual:
            continue  # a virtual joint is not a URDF joint: it contributes nothing
        if j not in tree.joints:
            raise fail(f"unknown joint '{j}'{did_you_mean(j, tree.joints)}")
        found.add(j)
    for link in g.links:
        if link not in tree.links:
            raise fail(f"unknown link '{link}'{did_you_mean(link, tree.links)}")
        if link in tree.parent_joint:
            found.add(tree.parent_joint[link])
    for base, tip in g.chains:
        for link in (base, tip):
            if link not in tree.links:
                raise fail(
                    f"chain link '{link}' is not in the URDF{did_you_mean(link, tree.links)}"
                )
        chain = tree.chain_joints(base, tip)
        if chain is None:
            raise fail(f"chain base '{base}' is not an ancestor of tip '{tip}'")
        found.update(chain)
    return found


def group_joints(srdf: Srdf, name: str, tree: RobotTree) -> list[str]:
    """All joints of group ``name`` (fixed ones included) in MoveIt's order.

    Virtual joints (``<virtual_joint>``) are not URDF joints and contribute nothing. Raises
    :class:`SourceError` for names that are not in the URDF, a chain whose base is not an
    ancestor of its tip, or subgroups that include each other.
    """
    # subgroups: each visited once, without recursion (1,000s of nested groups are fine)
    members, cycle = reachable(name, lambda gname: _group(srdf, gname).subgroups)
    if cycle is not None:
        raise SourceError(
            f"groups include each other: {show_path(cycle)}",
            path=srdf.path,
            line=srdf.groups[cycle[0]].line,
        )
    found: set[str] = set()
    for gname in members:
        found |= _own_joints(srdf, gname, tree)
    return [j for j in tree.dfs_joints() if j in found]


def _cspace_sizes(srdf: Srdf, tree: RobotTree) -> dict[str, int]:
    """``len(cspace_of(g))`` of every group, 0 when it does not resolve, in one pass over the
    groups (children first), so thousands of nested groups stay linear."""
    groups = srdf.groups

    def subs(g: str) -> list[str]:
        return list(groups[g].subgroups) if g in groups else []

    cyclic = nodes_on_cycles(groups, subs)
    joints: dict[str, frozenset[str] | None] = {}
    for g in postorder(groups, subs):
        if g not in groups or g in cyclic:
            joints[g] = None
            continue
        try:
            own = frozenset(_own_joints(srdf, g, tree))
        except SourceError:
            own = None
        parts = [joints.get(s) for s in groups[g].subgroups]
        known = [p for p in parts if p is not None]
        joints[g] = None if own is None or len(known) < len(parts) else own.union(*known)
    passive = set(srdf.passive_joints)
    return {
        g: 0 if js is None else sum(1 for j in js if tree.is_actuated(j) and j not in passive)
        for g, js in joints.items()
        if g in groups
    }


def cspace_of(srdf: Srdf, name: str, tree: RobotTree) -> list[str]:
    """C-space of group ``name``: its joints minus fixed, mimic and passive joints."""
    passive = set(srdf.passive_joints)
    return [j for j in group_joints(srdf, name, tree) if tree.is_actuated(j) and j not in passive]


def _path_joints(tree: RobotTree, link: str) -> set[str]:
    """Joints between the root and ``link``."""
    return {tree.parent_joint[n] for n in (link, *tree.ancestors(link)) if n in tree.parent_joint}


def _is_gripper(srdf: Srdf, ee: EndEffector, tree: RobotTree) -> bool:
    """``ee.group`` is the end effector itself (MoveIt's meaning): none of its joints moves
    the parent link. Many SRDFs instead name the arm there (Panda, Talos): not a gripper."""
    if ee.group is None or ee.group not in srdf.groups or ee.parent_link not in tree.links:
        return False
    return not set(group_joints(srdf, ee.group, tree)) & _path_joints(tree, ee.parent_link)


def _carries(srdf: Srdf, g: str, ee: EndEffector, tree: RobotTree, gripper: bool) -> bool:
    """Group ``g`` carries end effector ``ee``: named as its parent group, named as its
    group (not a gripper), or it holds the last joint moving the parent link and not the
    gripper's joints."""
    if ee.parent_group is not None:
        return ee.parent_group == g
    if ee.group == g:
        return not gripper
    last = _nearest_actuated(tree, ee.parent_link)
    if last is None:
        return False
    joints = set(group_joints(srdf, g, tree))
    own = set(group_joints(srdf, ee.group, tree)) if gripper and ee.group else set()
    return last in joints and not joints & own


def _nearest_actuated(tree: RobotTree, link: str) -> str | None:
    """The first actuated joint above ``link`` (the one that moves it last)."""
    for n in (link, *tree.ancestors(link)):
        jn = tree.parent_joint.get(n)
        if jn is not None and tree.is_actuated(jn):
            return jn
    return None


def choose_group(srdf: Srdf, tree: RobotTree) -> tuple[str | None, str]:
    """The default planning group and why it was chosen (``None`` when the SRDF has none).

    Candidates are the groups without subgroups that are not an end effector's gripper (all
    groups when none of those has a movable joint); the one with the most actuated joints
    wins, ties going to the group carrying the earliest end effector, then SRDF order.
    """
    order = list(srdf.groups)
    sizes = _cspace_sizes(srdf, tree)
    grippers = {ee.name: _is_gripper(srdf, ee, tree) for ee in srdf.end_effectors}
    excluded = {ee.group for ee in srdf.end_effectors if grippers[ee.name]}
    plain = [g for g in order if not srdf.groups[g].subgroups and g not in excluded]
    cands = [g for g in plain if sizes[g] > 0] or [g for g in order if sizes[g] > 0]
    if not cands:
        return None, "the SRDF has no group with movable joints"

    def ee_rank(g: str) -> tuple[int, str]:
        for i, ee in enumerate(srdf.end_effectors):
            if _carries(srdf, g, ee, tree, grippers[ee.name]):
                return i, ee.name
        return len(srdf.end_effectors), ""

    best = min(cands, key=lambda g: (-sizes[g], ee_rank(g)[0], order.index(g)))
    kind = "group without subgroups" if best in plain else "group"
    why = f"the {kind} with the most actuated joints ({sizes[best]})"
    ee_name = ee_rank(best)[1]
    if ee_name:
        why += f", carrying end effector '{ee_name}'"
    return best, why


def group_sizes(srdf: Srdf, tree: RobotTree) -> dict[str, int]:
    """Actuated joints per group (for messages listing the alternatives)."""
    return _cspace_sizes(srdf, tree)


def choose_state(
    srdf: Srdf, group: str | None, cspace: list[str], requested: str | None
) -> tuple[GroupState | None, str]:
    """The group state giving default positions, and why it was chosen."""
    if requested is not None:
        for s in srdf.group_states:
            if s.name == requested and (group is None or s.group in (group, None)):
                return s, "requested"
        for s in srdf.group_states:
            if s.name == requested:
                return s, "requested"
        names = [s.name for s in srdf.group_states]
        raise SourceError(
            f"no group_state '{requested}'{did_you_mean(requested, names)} "
            f"(states: {', '.join(names) or 'none'})",
            path=srdf.path,
        )
    own = [s for s in srdf.group_states if group is not None and s.group == group]
    covering = [
        s for s in srdf.group_states if s not in own and set(cspace) <= {n for n, _ in s.values}
    ]
    for cands, why in ((own, f"of group '{group}'"), (covering, "covering the c-space")):
        for pref in PREFERRED_STATES:
            for s in cands:
                if s.name == pref:
                    return s, f"the state named '{pref}' {why}"
        if cands:
            return cands[0], f"the first state {why}"
    return None, ""


def read_srdf(
    srdf: Srdf,
    tree: RobotTree,
    *,
    group: str | Sequence[str] | None = None,
    state: str | None = None,
    draft: Draft | None = None,
    choose: bool = True,
) -> Draft:
    """Map an SRDF onto a :class:`Draft` (mapping: docs/convert.md, "Sources").

    ``group`` is one group or several (their union, in the given order: a dual-arm c-space);
    none chooses one (see :func:`choose_group`) unless ``choose`` is false (the c-space is
    given otherwise). Every group is checked first (:func:`check_groups`).
    """
    d = draft or Draft()
    rep = Reporter(srdf.path)
    check_groups(srdf, tree)
    groups = [group] if isinstance(group, str) else list(dict.fromkeys(group or ()))
    for g in groups:
        _group(srdf, g)
    if not groups and choose:
        groups = _choose(srdf, tree, rep)
    d.group = "+".join(groups) or None
    d.passive_joints |= set(srdf.passive_joints)
    if groups:
        cspace = [j for g in groups for j in cspace_of(srdf, g, tree)]
        d.cspace = list(dict.fromkeys(cspace))
    _defaults(srdf, tree, groups, state, d, rep)
    if groups:
        d.tool_frames = _tool_frames(srdf, tree, groups, rep)

    # self-collision mask
    for l1, l2, _reason, line in srdf.disable_collisions:
        ok1 = known_frame(l1, tree.links, rep, "", "disable_collisions link1", line=line)
        ok2 = known_frame(l2, tree.links, rep, "", "disable_collisions link2", line=line)
        if ok1 and ok2:
            d.add_ignore(l1, l2)
    for link, line in srdf.disable_default:
        if known_frame(link, tree.links, rep, "", "disable_default_collisions", line=line):
            for other in tree.links:
                d.add_ignore(link, other)
    for l1, l2, line in srdf.enable_collisions:
        rep.report(
            "convert-dropped-key",
            f"enable_collisions {l1}/{l2} re-enables a pair; XRDF has no override, so the pair "
            "is checked unless disabled above",
            severity=Severity.INFO,
            line=line,
        )
        if l2 in d.ignore.get(l1, []):
            d.ignore[l1].remove(l2)
        if l1 in d.ignore.get(l2, []):
            d.ignore[l2].remove(l1)
    for name, vtype, line in srdf.virtual_joints:
        rep.report(
            "convert-virtual-joint",
            f"virtual_joint '{name}' ({vtype}) is not represented: XRDF is relative to the "
            "URDF root",
            severity=Severity.INFO,
            line=line,
        )

    # spheres
    if srdf.spheres:
        spheres: dict[str, list[Sphere]] = {}
        for link, ss, line in srdf.spheres:
            if not known_frame(link, tree.links, rep, "", "link_sphere_approximation", line=line):
                continue
            kept = [s for s in ss if s.radius > 0]
            if len(kept) < len(ss) and kept:
                rep.report(
                    "convert-placeholder-spheres",
                    f"{len(ss) - len(kept)} sphere(s) of radius ≤ 0 on '{link}' dropped",
                    severity=Severity.INFO,
                    line=line,
                )
            if kept:
                spheres.setdefault(link, []).extend(kept)
        d.spheres = spheres
    d.diagnostics.extend(rep.diagnostics)
    return d


def _choose(srdf: Srdf, tree: RobotTree, rep: Reporter) -> list[str]:
    group, why = choose_group(srdf, tree)
    if group is None:
        return []
    sizes = group_sizes(srdf, tree)
    others = [f"{g} ({sizes[g]})" for g in srdf.groups if g != group]
    rep.report(
        "convert-chosen-group",
        f"planning group '{group}' chosen: {why}"
        + (f"; others (actuated joints): {', '.join(others)}" if others else "")
        + "; use --group (repeatable for several groups)",
        line=srdf.groups[group].line,
    )
    return [group]


def _defaults(
    srdf: Srdf,
    tree: RobotTree,
    groups: list[str],
    state: str | None,
    d: Draft,
    rep: Reporter,
) -> None:
    """Default positions from one group_state per group (the first group wins a conflict)."""
    chosen: list[GroupState] = []
    targets: list[str | None] = [*groups] or [None]
    for g in targets:
        cspace = cspace_of(srdf, g, tree) if g is not None else (d.cspace or [])
        st, why = choose_state(srdf, g, cspace, state)
        if st is None or st in chosen:
            continue
        chosen.append(st)
        if why != "requested":
            rep.report(
                "convert-chosen-state",
                f"default positions from group_state '{st.name}' ({why})",
                line=st.line,
            )
    for st in chosen:
        for jname, value in st.values:
            if _state_value_ok(srdf, tree, st, jname, rep) and jname not in d.defaults:
                d.defaults[jname] = value


def _state_value_ok(srdf: Srdf, tree: RobotTree, st: GroupState, jname: str, rep: Reporter) -> bool:
    j = tree.joints.get(jname)
    if j is None:
        rep.report(
            "convert-unknown-joint",
            f"group_state '{st.name}' sets '{jname}', which is not a joint of the "
            f"URDF{did_you_mean(jname, tree.joints)}; dropped",
            line=st.line,
        )
        return False
    if not j.is_actuated or jname in srdf.passive_joints:
        kind = "a mimic" if j.is_mimic else ("passive" if j.is_movable else j.type)
        rep.report(
            "convert-dropped-joint-value",
            f"group_state '{st.name}' sets '{jname}', which is {kind} joint; "
            "XRDF default positions hold only actuated joints; dropped",
            severity=Severity.INFO,
            line=st.line,
        )
        return False
    return True


def _tool_frames(srdf: Srdf, tree: RobotTree, groups: list[str], rep: Reporter) -> list[str]:
    """Per group in order: end effectors attached to it (or its subgroups), then chain tips."""
    frames: list[str] = []
    for group in groups:
        members = _subgroups(srdf, group)
        for ee in srdf.end_effectors:
            owner = ee.parent_group or ee.group
            if owner in members and known_frame(
                ee.parent_link, tree.links, rep, "", f"end effector '{ee.name}'", line=ee.line
            ):
                frames.append(ee.parent_link)
        for gname in members:
            for _, tip in srdf.groups[gname].chains:
                frames.append(tip)
    return list(dict.fromkeys(frames))


def _subgroups(srdf: Srdf, name: str) -> list[str]:
    out: list[str] = []
    seen: set[str] = set()
    stack = [name]
    while stack:
        g = stack.pop()
        if g in seen or g not in srdf.groups:
            continue
        seen.add(g)
        out.append(g)
        stack.extend(reversed(srdf.groups[g].subgroups))
    return out
