"""Adjacent frames: the pairs a self-collision mask ignores whatever the joints do.

The MoveIt Setup Assistant's rule, bounded: collapse the frames without geometry; two frames
with geometry are *adjacent* when the tree path between them crosses only frames without
geometry (none at all: parent and child; one: siblings under a bare palm, links either side of
a visual-only elbow) **and** at most :data:`MAX_ADJACENT_MOVING_JOINTS` joints on it move. Such
parts touch at their joint by construction. Further apart, the chain between them moves them
against each other like any other pair: Drake's dual iiwa14 has geometry only on the two
``link_7`` frames, 14 revolute joints apart, and the unbounded rule ignored the only pair the
robot has.

A joint *moves* unless it is ``fixed`` or held still by equal lower and upper limits (Toyota
HSR's force-torque sensor frame; :attr:`JointInfo.is_held`, as the default c-space and the
tool-frame guess read it): a mimic follower moves, and so do the floating and planar joints
the kinematics hold still, because the limit is about the robot, not the c-space.

The one implementation of adjacency: the report and ``convert``'s mask
(:func:`xrdf_tools.report.adjacent_frame_pairs`), ``xrdf spheres``' drafted mask
(:func:`xrdf_tools.spheres.ignore_adjacent`) and ``export srdf``'s held-joint check use it.
Pure: names in, names out.
"""

from __future__ import annotations

from collections.abc import Collection, Iterable, Mapping

from .urdf_joints import JointInfo

__all__ = [
    "MAX_ADJACENT_MOVING_JOINTS",
    "Edges",
    "adjacent_across",
    "adjacent_pairs",
    "edges_of_joints",
    "joint_moves",
]

#: Most joints that move on the tree path between two adjacent frames. Two keeps a gripper's
#: fingers under a palm without geometry, and the links either side of a visual-only elbow,
#: adjacent; three or more joints move the two parts against each other.
MAX_ADJACENT_MOVING_JOINTS = 2

#: The tree as child frame → (parent frame, whether the joint between them moves).
Edges = Mapping[str, tuple[str, bool]]


def joint_moves(joint: JointInfo) -> bool:
    """Whether a joint counts as moving: any but a ``fixed`` one or one its limits hold."""
    return joint.type != "fixed" and not joint.is_held


def edges_of_joints(joints: Iterable[JointInfo]) -> dict[str, tuple[str, bool]]:
    """The :data:`Edges` of URDF ``joints``."""
    return {j.child: (j.parent, joint_moves(j)) for j in joints}


def adjacent_across(between: Iterable[str], moving: int, geometry: Collection[str]) -> bool:
    """Whether two geometry frames are adjacent when the tree path between them crosses the
    frames ``between`` (strictly between) and ``moving`` joints that move."""
    return moving <= MAX_ADJACENT_MOVING_JOINTS and not any(f in geometry for f in between)


def adjacent_pairs(edges: Edges, geometry_frames: Iterable[str]) -> frozenset[frozenset[str]]:
    """Pairs of ``geometry_frames`` that are adjacent in the tree ``edges``.

    A walk from each geometry frame through frames without geometry, given up once more than
    :data:`MAX_ADJACENT_MOVING_JOINTS` moving joints lie behind it."""
    geo = set(geometry_frames)
    nbrs: dict[str, list[tuple[str, bool]]] = {}
    for child, (parent, moves) in edges.items():
        nbrs.setdefault(child, []).append((parent, moves))
        nbrs.setdefault(parent, []).append((child, moves))
    out: set[frozenset[str]] = set()
    for g in geo:
        seen = {g}
        stack = [(g, 0)]
        while stack:
            v, moving = stack.pop()
            for u, moves in nbrs.get(v, ()):
                n = moving + moves
                if u in seen or n > MAX_ADJACENT_MOVING_JOINTS:
                    continue
                seen.add(u)
                if u in geo:
                    out.add(frozenset((g, u)))
                else:
                    stack.append((u, n))
    return frozenset(out)
