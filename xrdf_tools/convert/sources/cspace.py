"""The c-space chosen on the command line, without an SRDF: ``--joints`` and ``--chain``.

``--joints j1,j2`` takes the actuated joints as given, in the given order. ``--chain BASE:TIP``
walks up from ``TIP`` to ``BASE`` like an SRDF chain (``BASE``'s own parent joint excluded)
and keeps the actuated joints in tree order; several chains are joined in the given order
(a dual-arm c-space). Tool frames are the tips: each chain's ``TIP``, or for ``--joints`` the
child link of every joint with no other c-space joint below it.
"""

from __future__ import annotations

from collections.abc import Sequence

from ...util.errors import SourceError, did_you_mean
from . import Draft, RobotTree

__all__ = ["apply_cspace_choice", "chain_joints", "parse_chain"]


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


def _tip(tree: RobotTree, link: str) -> str:
    """``link`` followed down a single chain of fixed joints (a flange, a tool frame)."""
    while True:
        kids = [tree.joints[j] for j in tree.child_joints.get(link, ())]
        if len(kids) != 1 or kids[0].type != "fixed":
            return link
        link = kids[0].child


def _leaf_tips(tree: RobotTree, cspace: list[str]) -> list[str]:
    chosen = set(cspace)
    tips = []
    for j in cspace:
        below = tree.descendants(tree.joints[j].child)
        if not any(tree.parent_joint.get(n) in chosen for n in below):
            tips.append(_tip(tree, tree.joints[j].child))
    return tips


def apply_cspace_choice(
    tree: RobotTree,
    draft: Draft,
    *,
    joints: Sequence[str] = (),
    chains: Sequence[tuple[str, str]] = (),
) -> bool:
    """Set ``draft.cspace`` (and its tool frames) from ``joints`` or ``chains``.

    Returns whether a choice was given. Raises :class:`SourceError` for unknown or
    non-actuated joints, unknown links, a base that is not above its tip, or both options.
    """
    if joints and chains:
        raise SourceError("give either --joints or --chain, not both")
    if chains:
        names = [j for base, tip in chains for j in chain_joints(tree, base, tip)]
        cspace = [j for j in dict.fromkeys(names) if tree.is_actuated(j)]
        tips = [tip for _, tip in chains]
        what = "--chain " + ", ".join(f"{b}:{t}" for b, t in chains)
    elif joints:
        cspace = _checked_joints(tree, joints)
        tips = _leaf_tips(tree, cspace)
        what = "--joints"
    else:
        return False
    if not cspace:
        raise SourceError(f"{what}: no actuated joint in the chosen c-space", path=tree.path)
    draft.cspace = cspace
    draft.tool_frames = list(dict.fromkeys(tips))
    draft.group = None
    return True
