"""Ignore pairs an SRDF sync must not add: the XRDF's mask held a joint between their links.

An XRDF's mask is computed over its c-space with every other joint held at its default
position. MoveIt checks collisions with every joint of the robot where it is: a pair the XRDF
ignores because a joint outside its c-space never moved (the other arm of a dual-arm robot
converted for one arm) may collide once MoveIt plans a group that moves that joint. Adding such
a pair to the SRDF would switch that check off for every group, so the sync leaves it out (a
warning counts them and names the joints). Adjacent pairs (the path between them passes only
through frames without spheres and at most two joints that move, :mod:`xrdf_tools.robot.adjacency`)
are ignored whatever the joints do, so they are added as before.

Pure: names in, names out; used by :func:`xrdf_tools.export.srdf.sync_srdf`.
"""

from __future__ import annotations

from collections.abc import Collection, Sequence
from dataclasses import dataclass

from ..diagnostics import Diagnostic, Severity
from ..robot.adjacency import adjacent_across, joint_moves
from ..robot.tree import RobotTree
from ..util.text import name_list, pair_text
from ..xrdf.model import Xrdf

__all__ = ["RULE_HELD", "HeldPairs", "held_pairs"]

#: Ignore pairs not added to the SRDF: a joint MoveIt moves was held when the mask was made.
RULE_HELD = "export-srdf-held-joint"

Pair = frozenset[str]
_UNMODELLED = ("floating", "planar")  # held at identity by the mask's kinematics


@dataclass(frozen=True)
class HeldPairs:
    """Pairs (``link1``, ``link2``, held joints between them) in the XRDF's order."""

    pairs: tuple[tuple[str, str, tuple[str, ...]], ...]

    def keys(self) -> frozenset[Pair]:
        return frozenset(frozenset((a, b)) for a, b, _ in self.pairs)

    def diagnostic(self, path: str, wanted: Collection[Pair]) -> Diagnostic | None:
        """The warning for the held pairs among ``wanted`` (those the sync would have added)."""
        left = [p for p in self.pairs if frozenset(p[:2]) in wanted]
        if not left:
            return None
        joints = sorted({j for _, _, js in left for j in js})
        a, b, _ = left[0]
        msg = (
            f"{len(left)} ignore pair(s) not added (first {pair_text(a, b)}): the XRDF's mask held "
            f"joint(s) {name_list(joints)} at their default position, so it cannot say whether "
            "these links collide when MoveIt moves them; to sync them, convert with those "
            "joints in the c-space (--group for each planning group that moves them), or "
            "disable them in the SRDF by hand once checked over those joints' range"
        )
        return Diagnostic(path, None, None, RULE_HELD, Severity.WARNING, msg, "")


def held_pairs(x: Xrdf, tree: RobotTree, pairs: Sequence[tuple[str, str]]) -> HeldPairs:
    """The ``pairs`` (URDF links) whose tree path crosses a joint the XRDF's mask held still,
    adjacent pairs aside."""
    moved = _moved_joints(x, tree)
    spheres = {f for f, s in x.self_collision_spheres().items() if s}
    out: list[tuple[str, str, tuple[str, ...]]] = []
    for a, b in pairs:
        if a not in tree.links or b not in tree.links:
            continue
        path_links, path_joints = _tree_path(tree, a, b)
        held = tuple(
            dict.fromkeys(
                _driver(tree, j) for j in path_joints if _can_move(tree, j) and j not in moved
            )
        )
        moving = sum(joint_moves(tree.joints[j]) for j in path_joints)
        if held and not adjacent_across(path_links, moving, spheres):
            out.append((a, b, held))
    return HeldPairs(tuple(out))


def _moved_joints(x: Xrdf, tree: RobotTree) -> set[str]:
    """The c-space joints and the mimic followers they drive (transitively)."""
    moved = set(x.cspace.joint_names) if x.cspace is not None else set()
    grew = True
    while grew:
        followers = {
            j.name for j in tree.joints.values() if j.mimic_joint in moved and j.name not in moved
        }
        moved |= followers
        grew = bool(followers)
    return moved


def _driver(tree: RobotTree, joint: str) -> str:
    """The joint that moves ``joint``: its mimic leader (transitively), else itself."""
    seen = {joint}
    lead = tree.joints[joint].mimic_joint
    while lead is not None and lead in tree.joints and lead not in seen:
        seen.add(lead)
        joint = lead
        lead = tree.joints[joint].mimic_joint
    return joint


def _can_move(tree: RobotTree, joint: str) -> bool:
    j = tree.joints[joint]
    return (j.is_movable and not j.is_held) or j.type in _UNMODELLED


def _tree_path(tree: RobotTree, a: str, b: str) -> tuple[list[str], list[str]]:
    """Links strictly between ``a`` and ``b`` on the tree path, and the joints of that path."""
    up_a = [a, *tree.ancestors(a)]
    up_b = [b, *tree.ancestors(b)]
    common = next((link for link in up_a if link in set(up_b)), None)
    if common is None:  # disconnected parts: no path, nothing held between them
        return [], []
    side_a = up_a[: up_a.index(common)]
    side_b = up_b[: up_b.index(common)]
    joints = [tree.parent_joint[link] for link in side_a + side_b]
    between = [*side_a[1:], *side_b[1:]]
    if common not in (a, b):
        between.append(common)
    return between, joints
