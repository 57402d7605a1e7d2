"""Where an XRDF meets its URDF: every name the XRDF takes from the URDF must be there.

A name the URDF does not have is the XRDF's mistake (or the wrong URDF was given), so these
errors point into the XRDF — its path, line and column — and name the URDF file they were
checked against. Used by every command that reads both (``report``, ``viz``, ``export``,
``convert`` from a cuRobo config); ``lint --urdf`` reports the same problems as findings.
"""

from __future__ import annotations

from pathlib import PurePath
from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt

from ..util.errors import UrdfError

if TYPE_CHECKING:
    from ..xrdf.model import Xrdf
    from .kinematics import KinematicModel
    from .tree import RobotTree

__all__ = ["check_belongs", "cspace_indices", "cspace_joints", "unreachable_frames"]


def _mismatch(x: Xrdf, key_path: str, urdf_path: str, message: str) -> UrdfError:
    """An error at ``key_path`` of ``x`` saying that the URDF does not match it."""
    name = PurePath(urdf_path.replace("\\", "/")).name or "the URDF"
    return UrdfError(f"{name} does not match this XRDF: {message}", **x.source.locate(key_path))


def cspace_joints(kin: KinematicModel, x: Xrdf) -> tuple[str, ...]:
    """The joints a configuration gives: the XRDF c-space, else every actuated joint."""
    if x.cspace is not None and x.cspace.joint_names:
        return x.cspace.joint_names
    return kin.actuated_joints


def cspace_indices(kin: KinematicModel, x: Xrdf) -> tuple[tuple[str, ...], npt.NDArray[np.intp]]:
    """:func:`cspace_joints` and their indices in the model's ``q``; an error located at the
    c-space entry that names no coordinate of the URDF (unknown, fixed, mimic or pruned) or
    one whose limits no position fits."""
    names = cspace_joints(kin, x)
    for i, name in enumerate(names):
        why = kin.cspace_reason(name)
        if why:
            raise _mismatch(
                x, f"cspace.joint_names[{i}]", kin.source_path, f"c-space joint '{name}' {why}"
            )
    return names, np.array([kin.actuated_index(n) for n in names], dtype=np.intp)


def check_belongs(x: Xrdf, tree: RobotTree) -> None:
    """An error unless every joint and frame ``x`` uses is in the URDF below its base: inputs
    that describe another robot, or a base that cuts parts off."""
    if x.cspace is not None:
        for i, joint in enumerate(x.cspace.joint_names):
            if joint not in tree.joints:
                raise _mismatch(
                    x,
                    f"cspace.joint_names[{i}]",
                    tree.path,
                    f"c-space joint '{joint}' is not one of its joints; the XRDF and the URDF "
                    "describe different robots",
                )
    for frame, key_path in unreachable_frames(x, tree):
        what = (
            "is not one of its links"
            if frame not in tree.links
            else f"cannot be reached from the base '{tree.root}'"
        )
        raise _mismatch(x, key_path, tree.path, f"frame '{frame}' {what}")


def unreachable_frames(x: Xrdf, tree: RobotTree) -> list[tuple[str, str]]:
    """Frames ``x`` uses (tool frames, sphere frames, mask, c-space joint children) that are
    not below the root of ``tree`` nor added by a modifier, each with the key path naming it,
    in document order."""
    reach = {tree.root, *tree.descendants(tree.root)}
    reach |= {m.frame_name for m in x.added_frames()}
    return [(f, kp) for f, kp in _used_frames(x, tree) if f not in reach]


def _used_frames(x: Xrdf, tree: RobotTree) -> list[tuple[str, str]]:
    """Frames ``x`` names, each with the key path that names it."""
    used = [(f, f"tool_frames[{i}]") for i, f in enumerate(x.tool_frames or ())]
    if x.world_collision is not None:
        key = "collision" if x.format_version == "1.0" else "world_collision"
        used += [(f, f"{key}.geometry") for f in x.world_collision_spheres()]
    if x.self_collision is not None:
        for a, bs in x.self_collision.ignore.items():
            used.append((a, f"self_collision.ignore.{a}#key"))
            used += [(b, f"self_collision.ignore.{a}[{k}]") for k, b in enumerate(bs)]
    for i, j in enumerate(x.cspace.joint_names if x.cspace else ()):
        used.append((tree.joints[j].child, f"cspace.joint_names[{i}]"))
    return used
