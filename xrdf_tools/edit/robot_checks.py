"""What an edit may not bring into the document of a given robot: what ``xrdf lint --urdf``
would call an error in the saved file.

A frame the robot does not have (sphere frames, buffers, the mask, tool frames:
``unknown-frame``), a c-space joint it cannot move (unknown, fixed, a mimic joint, removed by
``set_base_frame``: ``cspace-joint``), a default position for such a joint or outside its
joint's limits (``default-position``). Only what the edit brings in is checked: a file that
had such an entry already can still be edited (and lint still says so). Nor may an edit leave
the c-space without a joint or the file without a tool frame (the page's refusals too).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING

from ..util.errors import did_you_mean
from .checks import EditError

if TYPE_CHECKING:
    from ..robot.kinematics import KinematicModel
    from ..xrdf.model import Xrdf

__all__ = ["check_edited"]


def check_edited(kin: KinematicModel, before: Xrdf, after: Xrdf) -> None:
    """:class:`EditError` when ``after`` names a frame or joint of the robot ``kin`` lacks,
    or has a default position outside its joint's limits, that ``before`` did not, or has
    lost its last c-space joint or its last tool frame."""
    _check_not_emptied(before, after)
    _check_frames(kin, _named_frames(after) - _named_frames(before))
    old = set(before.cspace.joint_names if before.cspace is not None else ())
    for joint in after.cspace.joint_names if after.cspace is not None else ():
        why = "" if joint in old else kin.cspace_reason(joint)
        if why:
            raise EditError(f"c-space joint '{joint}' {why}")
    was: Mapping[str, float] = before.default_joint_positions or {}
    for joint, value in (after.default_joint_positions or {}).items():
        if was.get(joint) != value:
            _check_default(kin, joint, value)


def _check_not_emptied(before: Xrdf, after: Xrdf) -> None:
    """The last c-space joint and the last tool frame stay: an empty c-space is valid XRDF
    but gives a planner nothing to move, and cuRobo and cuMotion take the first tool frame as
    the end effector and refuse a file without one."""
    joints = before.cspace.joint_names if before.cspace is not None else ()
    if joints and (after.cspace is None or not after.cspace.joint_names):
        raise EditError(f"{joints[0]} is the last c-space joint; take another in first")
    tools = before.tool_frames or ()
    if tools and not after.tool_frames:
        raise EditError(
            f"{tools[0]} is the last tool frame (cuRobo and cuMotion take the first as the end "
            "effector and refuse a file without one); add another first"
        )


def _named_frames(x: Xrdf) -> set[str]:
    """Every frame ``x`` names: sphere frames, buffers, the mask, tool frames."""
    names = set(x.tool_frames or ())
    for group in (x.geometry or {}).values():
        names.update(group.spheres)
    for section in (x.world_collision, x.self_collision):
        if section is not None:
            names.update(section.buffer_distance)
    if x.self_collision is not None:
        for a, bs in x.self_collision.ignore.items():
            names.update((a, *bs))
    return names


def _check_frames(kin: KinematicModel, frames: set[str]) -> None:
    known = set(kin.frame_names)
    for frame in sorted(frames - known):
        if frame in kin.pruned_frames:
            why = f"was removed by set_base_frame '{kin.base_frame}'"
        else:
            why = "is not a frame of the robot" + did_you_mean(frame, kin.frame_names)
        raise EditError(f"frame '{frame}' {why}")


def _check_default(kin: KinematicModel, joint: str, value: float) -> None:
    why = kin.cspace_reason(joint)
    if why:
        raise EditError(f"no default position for '{joint}': it {why}")
    outside = kin.outside_limits(joint, value)
    if outside:
        raise EditError(f"default position {value:g} of '{joint}' {outside}")
