"""The c-space without an SRDF group: ``--joints``, ``--chain``, or the default chain.

``--joints j1,j2`` takes the actuated joints as given, in the given order. ``--chain BASE:TIP``
walks up from ``TIP`` to ``BASE`` like an SRDF chain (``BASE``'s own parent joint excluded)
and keeps the actuated joints in tree order, but for a joint whose limits hold it still
(lower = upper, as the default chain leaves it out); several chains are joined in the given order
(a dual-arm c-space). Tool frames are the tips: each chain's ``TIP``, or for ``--joints`` the
tool frame guessed below every joint with no other c-space joint below it.

With none of them and no group: :func:`apply_default_cspace` takes the longest serial arm
chain (:func:`xrdf_tools.robot.chains.default_cspace`) and reports the choice. A planar or
floating joint an SRDF group names cannot be a c-space coordinate in any reader:
:func:`report_unplannable_joints` names each one left out.
"""

from __future__ import annotations

from collections.abc import Collection, Sequence
from typing import TYPE_CHECKING

from ...robot.chains import default_cspace
from ...robot.tool_frame import ToolFrameGuess, guess_tool_frame
from ...util.errors import SourceError, did_you_mean
from ...util.text import name_list
from . import Draft, Reporter, RobotTree

if TYPE_CHECKING:
    from .srdf_parse import Srdf

__all__ = [
    "apply_cspace_choice",
    "apply_default_cspace",
    "chain_joints",
    "guessed_tool_frames",
    "parse_chain",
    "report_unplannable_joints",
    "unplannable_joints",
]


def parse_chain(spec: str) -> tuple[str, str]:
    """``BASE:TIP`` from the command line."""
    base, sep, tip = spec.partition(":")
    if not sep or not base or not tip:
        raise SourceError(f"--chain expects BASE_LINK:TIP_LINK, got '{spec}'")
    return base, tip


def _link(tree: RobotTree, name: str) -> str:
    if name not in tree.links:
        raise SourceError(
            f"--chain: '{name}' is not a link of the URDF{did_you_mean(name, tree.links)}",
            path=tree.path,
        )
    return name


def chain_joints(tree: RobotTree, base: str, tip: str) -> list[str]:
    """Joints from ``base`` down to ``tip`` (fixed ones included) in tree order."""
    cur = _link(tree, tip)
    _link(tree, base)
    out: list[str] = []
    while cur != base:
        if cur not in tree.parent_joint:
            raise SourceError(f"--chain: '{base}' is not an ancestor of '{tip}'", path=tree.path)
        jn = tree.parent_joint[cur]
        out.append(jn)
        cur = tree.joints[jn].parent
    return out[::-1]


def _checked_joints(tree: RobotTree, joints: Sequence[str]) -> list[str]:
    out: list[str] = []
    for j in joints:
        if j not in tree.joints:
            raise SourceError(
                f"--joints: '{j}' is not a joint of the URDF{did_you_mean(j, tree.joints)}",
                path=tree.path,
            )
        if not tree.is_actuated(j):
            kind = "a mimic" if tree.joints[j].is_mimic else f"a {tree.joints[j].type}"
            raise SourceError(
                f"--joints: '{j}' is {kind} joint; the c-space holds actuated joints only",
                path=tree.path,
            )
        if j not in out:
            out.append(j)
    return out


def apply_cspace_choice(
    tree: RobotTree,
    draft: Draft,
    *,
    joints: Sequence[str] = (),
    chains: Sequence[tuple[str, str]] = (),
    collision_links: Collection[str] | None = None,
) -> bool:
    """Set ``draft.cspace`` from ``joints`` or ``chains``, and the tool frames: each chain's
    tip; none for ``joints`` (they are guessed and reported where the XRDF is built).

    Returns whether a choice was given. Raises :class:`SourceError` for unknown or
    non-actuated joints, unknown links, a base that is not above its tip, or both options.
    """
    if joints and chains:
        raise SourceError("give either --joints or --chain, not both")
    if chains:
        names = [j for base, tip in chains for j in chain_joints(tree, base, tip)]
        cspace = [j for j in dict.fromkeys(names) if tree.is_actuated(j) and not tree.is_held(j)]
        tips = [tip for _, tip in chains]
        what = "--chain " + ", ".join(f"{b}:{t}" for b, t in chains)
    elif joints:
        cspace = _checked_joints(tree, joints)
        tips = []  # guessed at the end of each branch and reported, as for the default c-space
        what = "--joints"
    else:
        return False
    if not cspace:
        raise SourceError(f"{what}: no actuated joint in the chosen c-space", path=tree.path)
    draft.cspace = cspace
    draft.tool_frames = list(dict.fromkeys(tips))
    draft.group = None
    return True


def apply_default_cspace(
    tree: RobotTree,
    draft: Draft,
    rep: Reporter,
    collision_links: Collection[str] | None = None,
    *,
    srdf_given: bool = False,
) -> ToolFrameGuess | None:
    """Set ``draft.cspace`` to the default chain and return the tool frame at its end.

    Reports the choice (``convert-chosen-group``) with what was left out and the flags that
    change it; the tool frame is reported where it is used (:func:`guessed_tool_frames`).
    ``srdf_given``: an SRDF was read and has no group that can be used (it is not the flag
    to suggest).
    """
    choice = default_cspace(tree, draft.passive_joints, collision_links)
    draft.cspace = list(choice.joints)
    why = "no planning group in the SRDF" if srdf_given else "no planning group given"
    if not choice.joints:
        rep.report(
            "convert-chosen-group",
            f"{why} and {choice.describe(srdf_given)} in the URDF "
            f"(--joints, --chain or {'an SRDF group' if srdf_given else '--srdf'} choose one)",
        )
        return None
    rep.report("convert-chosen-group", f"{why}: {choice.describe(srdf_given)}")
    return choice.tool


def guessed_tool_frames(
    tree: RobotTree,
    cspace: Sequence[str],
    rep: Reporter,
    collision_links: Collection[str] | None = None,
    guess: ToolFrameGuess | None = None,
) -> list[str]:
    """``guess``, else a tool frame below each c-space joint that has no c-space joint below
    it (one per branch: a group of two fingers or two arms given as joints gets two), in tree
    order; each reported."""
    guesses = [guess] if guess is not None else []
    if guess is None:
        order = tree.joint_order()
        for tip in sorted(_branch_ends(tree, cspace), key=lambda j: order.get(j, -1)):
            guesses.append(guess_tool_frame(tree, tip, collision_links))
    for g in guesses:
        _report_tool(rep, g.frame, g.reason, g.candidates)
    return list(dict.fromkeys(g.frame for g in guesses))


def _branch_ends(tree: RobotTree, cspace: Sequence[str]) -> list[str]:
    """The c-space joints with no other c-space joint below them (each link above a c-space
    joint is marked once: a long chain costs its length, not its length squared)."""
    above: set[str] = set()
    for name in cspace:
        link: str | None = tree.joints[name].parent
        while link is not None and link not in above:
            above.add(link)
            up = tree.parent_joint.get(link)
            link = tree.joints[up].parent if up is not None else None
    return [j for j in cspace if tree.joints[j].child not in above]


def _report_tool(rep: Reporter, frame: str, reason: str, candidates: Sequence[str]) -> None:
    others = [c for c in candidates if c != frame]
    shown = name_list(others, 6)
    rep.report(
        "convert-chosen-tool-frame",
        f"no tool frame in the inputs: using '{frame}' ({reason})"
        + (f"; also rigidly attached: {shown}" if others else "")
        + "; set --tool-frame",
    )


def report_unplannable_joints(srdf: Srdf, groups: Sequence[str], tree: RobotTree) -> Reporter:
    """Warn about each planar or floating joint of ``groups`` (left out of the c-space)."""
    rep = Reporter(srdf.path)
    for group, joint, kind in unplannable_joints(srdf, groups, tree):
        rep.report(
            "convert-unplannable-joint",
            f"group '{group}' holds the {kind} joint '{joint}': left out of the c-space (an "
            "XRDF c-space holds revolute, continuous and prismatic joints only); plan the base "
            "separately or model it as prismatic/revolute joints in the URDF",
            at=srdf.at(srdf.groups[group]),
        )
    return rep


def unplannable_joints(
    srdf: Srdf, groups: Sequence[str], tree: RobotTree
) -> list[tuple[str, str, str]]:
    """``(group, joint, type)`` of the planar and floating joints the groups (or their
    subgroups) name: URDF joints and SRDF virtual joints, each once, in group order."""
    virtual = {vj.name: vj.type for vj in srdf.virtual_joints}
    out: list[tuple[str, str, str]] = []
    seen: set[str] = set()
    for top in groups:
        stack, visited = [top], set()
        while stack:
            gname = stack.pop()
            g = srdf.groups.get(gname)
            if g is None or gname in visited:
                continue
            visited.add(gname)
            stack.extend(reversed(g.subgroups))
            named = [*g.joints, *(tree.parent_joint.get(link, "") for link in g.links)]
            for base, tip in g.chains:
                named += reversed(tree.chain_joints(base, tip) or [])
            for j in named:
                info = tree.joints.get(j)
                kind = info.type if info is not None else virtual.get(j)
                if kind in ("planar", "floating") and j not in seen:
                    seen.add(j)
                    out.append((gname, j, kind))
    return out
