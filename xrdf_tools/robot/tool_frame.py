"""The tool frame a robotics engineer would pick below the last joint of a c-space.

:func:`guess_tool_frame` takes a link below the last c-space joint reached through fixed (or
held) joints only, preferring ``tool0``, then ``tcp``, ``tool``, ``ee``/``eef``/
``end_effector``, ``flange``, ``grasp`` names, then a frame without collision geometry at the
end of a fixed branch (one named like a gripper first: SO-101's ``gripper_frame_link`` over
its ``d405_link``), then the link where a single chain of fixed joints ends; never a frame
named like a sensor or a camera (``d435i_link``). How names are read into words:
:mod:`.names`. A pure function of the :class:`~xrdf_tools.robot.tree.RobotTree`.
"""

from __future__ import annotations

from collections.abc import Collection
from dataclasses import dataclass

from .names import TOOL_RANKS, name_words, says_gripper, says_sensor
from .tree import RobotTree

__all__ = ["ToolFrameGuess", "fixed_below", "guess_tool_frame", "tool_named"]


@dataclass(frozen=True)
class ToolFrameGuess:
    """A tool frame below a c-space joint and why it was chosen."""

    frame: str
    reason: str
    #: Other links reached from the same joint through fixed joints (the alternatives).
    candidates: tuple[str, ...] = ()
    #: Whether the frame was chosen for its tool-like name.
    named: bool = False


def fixed_below(tree: RobotTree, link: str) -> list[tuple[str, int]]:
    """``link`` and the links below it reached through fixed (or held) joints only, with
    their depth."""
    out = [(link, 0)]
    stack = [(link, 0)]
    while stack:
        cur, depth = stack.pop()
        for jn in reversed(tree.child_joints.get(cur, ())):
            j = tree.joints[jn]
            if tree.is_held(jn):
                out.append((j.child, depth + 1))
                stack.append((j.child, depth + 1))
    return out


def _single_fixed_tip(tree: RobotTree, link: str) -> str:
    """``link`` followed down a single chain of fixed (or held) joints (a flange, a tool
    frame)."""
    while True:
        kids = tree.child_joints.get(link, ())
        if len(kids) != 1 or not tree.is_held(kids[0]):
            return link
        link = tree.joints[kids[0]].child


def tool_named(below: list[tuple[str, int]]) -> list[tuple[str, str]]:
    """The frames of ``below`` (name, depth: :func:`fixed_below`) named like a tool frame, best
    first, each with what its name says: ``tool0``, then by :data:`TOOL_RANKS` and depth
    (never a sensor's or a camera's frame)."""
    out = [(n, "tool0") for n, _ in below if n == "tool0"]
    seen = {n for n, _ in out}
    for rank, words in TOOL_RANKS:
        hits = sorted(
            (d, n)
            for n, d in below
            if n not in seen and set(name_words(n)) & words and not says_sensor(n)
        )
        out += [(n, rank) for _, n in hits]
        seen.update(n for _, n in hits)
    return out


def guess_tool_frame(
    tree: RobotTree, last_joint: str, collision_links: Collection[str] | None = None
) -> ToolFrameGuess:
    """The tool frame below ``last_joint`` (see the module doc for the preferences).

    ``collision_links`` (links with collision geometry) lets a collision-less leaf frame such
    as a gripper's TCP frame win over the link it hangs from; None skips that preference.
    """
    start = tree.joints[last_joint].child
    below = fixed_below(tree, start)
    names = tuple(n for n, _ in below)
    named = tool_named(below)
    if named:
        frame, rank = named[0]
        why = f"named like {rank} frame, below '{last_joint}'"
        why = "named tool0" if frame == "tool0" else why
        return ToolFrameGuess(frame, why, names, named=True)
    if collision_links is not None:
        frames = [
            (not says_gripper(n), d, n)  # a gripper's frame first, then the shallowest
            for n, d in below
            if d > 0 and n not in collision_links and not tree.child_joints.get(n)
        ]
        if frames := [f for f in frames if not says_sensor(f[2])]:
            frame = min(frames)[2]
            return ToolFrameGuess(
                frame, f"a frame without geometry at the end of '{last_joint}'", names
            )
    tip = _single_fixed_tip(tree, start)
    return ToolFrameGuess(tip, f"the tip of the chain after '{last_joint}'", names)
