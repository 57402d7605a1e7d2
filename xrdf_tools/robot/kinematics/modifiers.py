"""The XRDF ``modifiers`` applied to a URDF's frames and joints, in list order.

* ``add_frame`` attaches a new fixed frame to a link or to an earlier added frame;
* ``set_base_frame`` makes a frame the root and prunes every frame and joint outside its
  subtree (remembering which modifier removed what, for later messages);
* ``remove_mimic_attributes`` turns a mimic follower into an independent joint with the given
  limits.

Each modifier is one function on an :class:`Edit`; a modifier that cannot be applied is a
:class:`UrdfError` located at its key in the XRDF.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from ...util.arrays import FloatArray
from ...util.errors import UrdfError, did_you_mean
from ...util.graph import reachable
from ...util.rotations import Quat, matrix_from_quat
from ...util.text import name_list
from ...xrdf.model import AddFrame, RemoveMimicAttributes, SetBaseFrame, Xrdf
from ..urdf_source import JointInfo

XrdfError = Callable[[str, str], UrdfError]
"""``(message, key path in the XRDF) -> UrdfError`` located at that key when it can be."""


@dataclass
class Edit:
    """The robot's frames and joints while the modifiers apply, and what they removed.

    ``frames``/``joints`` are what is kept now (frames in insertion order); ``all_frames``/
    ``all_joints`` every name ever used (a pruned name is still taken); ``*_removed_by`` maps a
    pruned name to the ``set_base_frame`` frame that removed it.
    """

    file_name: str
    urdf_joints: Mapping[str, JointInfo]
    frames: dict[str, None]
    joints: dict[str, JointInfo]
    all_frames: set[str]
    all_joints: set[str]
    added: list[str] = field(default_factory=list)
    pruned_frames: list[str] = field(default_factory=list)
    pruned_joints: list[str] = field(default_factory=list)
    frame_removed_by: dict[str, str] = field(default_factory=dict)
    joint_removed_by: dict[str, str] = field(default_factory=dict)

    @classmethod
    def of_urdf(
        cls, file_name: str, links: Sequence[str], urdf_joints: Mapping[str, JointInfo]
    ) -> Edit:
        """The unmodified URDF: every link a frame, every joint kept."""
        return cls(
            file_name=file_name,
            urdf_joints=urdf_joints,
            frames=dict.fromkeys(links),
            joints=dict(urdf_joints),
            all_frames=set(links),
            all_joints=set(urdf_joints),
        )

    def missing_frame(self, name: str, what: str) -> str:
        """Why ``name`` is not a frame now: pruned by a ``set_base_frame``, or never one."""
        if name in self.frame_removed_by:
            base = self.frame_removed_by[name]
            return f"{what} '{name}' was removed by set_base_frame '{base}'"
        return f"{what} '{name}' is not a frame of {self.file_name}" + did_you_mean(
            name, self.frames
        )


def apply_modifiers(edit: Edit, xrdf: Xrdf | None, urdf_path: str) -> None:
    """Apply ``xrdf.modifiers`` to ``edit`` in list order (nothing when ``xrdf`` is None).

    Errors point at the modifier's key in the XRDF when it was read from a file, else at the
    URDF (``urdf_path``).
    """
    if xrdf is None:
        return

    def xerr(msg: str, key_path: str) -> UrdfError:
        if xrdf.source.path:
            line, col = xrdf.source.position(key_path)
            return UrdfError(msg, path=xrdf.source.path, line=line, col=col)
        return UrdfError(msg, path=urdf_path)

    for i, mod in enumerate(xrdf.modifiers):
        if isinstance(mod, AddFrame):
            add_frame(edit, mod, f"modifiers[{i}].add_frame", xerr)
        elif isinstance(mod, SetBaseFrame):
            set_base_frame(edit, mod, f"modifiers[{i}].set_base_frame", xerr)
        elif isinstance(mod, RemoveMimicAttributes):
            key = f"modifiers[{i}].remove_mimic_attributes.joint_name"
            remove_mimic_attributes(edit, mod, key, xerr)


def add_frame(edit: Edit, mod: AddFrame, key: str, xerr: XrdfError) -> None:
    """Attach ``mod.frame_name`` to its parent frame by a new fixed joint."""
    if mod.joint_type.lower() != "fixed":
        raise xerr(
            f"add_frame '{mod.frame_name}': joint_type must be FIXED, not '{mod.joint_type}'",
            f"{key}.joint_type",
        )
    if mod.frame_name in edit.all_frames:
        where = (
            "an earlier add_frame"
            if mod.frame_name in edit.added
            else f"a link of {edit.file_name}"
        )
        raise xerr(
            f"add_frame: frame '{mod.frame_name}' already exists ({where}); frame "
            "names must be unique",
            f"{key}.frame_name",
        )
    if mod.joint_name in edit.all_joints:
        where = (
            f"a joint of {edit.file_name}"
            if mod.joint_name in edit.urdf_joints
            else "used by an earlier add_frame"
        )
        raise xerr(
            f"add_frame '{mod.frame_name}': joint name '{mod.joint_name}' already "
            f"exists ({where}); joint names must be unique",
            f"{key}.joint_name",
        )
    if mod.parent_frame_name not in edit.frames:
        raise xerr(
            f"add_frame '{mod.frame_name}': "
            + edit.missing_frame(mod.parent_frame_name, "parent frame"),
            f"{key}.parent_frame_name",
        )
    edit.joints[mod.joint_name] = JointInfo(
        name=mod.joint_name,
        type="fixed",
        parent=mod.parent_frame_name,
        child=mod.frame_name,
        origin=_pose(mod.position, mod.orientation.as_wxyz()),
    )
    edit.frames[mod.frame_name] = None
    edit.all_frames.add(mod.frame_name)
    edit.all_joints.add(mod.joint_name)
    edit.added.append(mod.frame_name)


def set_base_frame(edit: Edit, mod: SetBaseFrame, key: str, xerr: XrdfError) -> None:
    """Make ``mod.frame`` the root: prune every frame and joint outside its subtree."""
    if mod.frame not in edit.frames:
        raise xerr("set_base_frame: " + edit.missing_frame(mod.frame, "frame"), key)
    children: dict[str, list[str]] = {}
    for j in edit.joints.values():
        children.setdefault(j.parent, []).append(j.child)
    keep = set(reachable(mod.frame, lambda f: children.get(f, ()))[0])
    for f in list(edit.frames):
        if f not in keep:
            del edit.frames[f]
            edit.pruned_frames.append(f)
            edit.frame_removed_by[f] = mod.frame
    for jn, j in list(edit.joints.items()):
        if j.parent not in keep or j.child not in keep:
            del edit.joints[jn]
            edit.pruned_joints.append(jn)
            edit.joint_removed_by[jn] = mod.frame


def remove_mimic_attributes(
    edit: Edit, mod: RemoveMimicAttributes, key: str, xerr: XrdfError
) -> None:
    """Make the mimic follower ``mod.joint_name`` independent, with the modifier's limits
    (the URDF joint's own where the modifier gives none)."""
    jn = mod.joint_name
    if jn not in edit.joints:
        if jn in edit.joint_removed_by:
            raise xerr(
                f"remove_mimic_attributes: joint '{jn}' was removed by set_base_frame "
                f"'{edit.joint_removed_by[jn]}'",
                key,
            )
        raise xerr(
            f"remove_mimic_attributes: joint '{jn}' is not a joint of {edit.file_name}"
            + did_you_mean(jn, edit.joints),
            key,
        )
    j = edit.joints[jn]
    if not j.is_mimic:
        mimics = [n for n, x in edit.joints.items() if x.is_mimic]
        hint = did_you_mean(jn, mimics) or (
            f" (mimic joints: {name_list(mimics)})" if mimics else " (it has none)"
        )
        raise xerr(
            f"remove_mimic_attributes: joint '{jn}' has no <mimic> in {edit.file_name}{hint}",
            key,
        )
    lo, hi = mod.position_limits if mod.position_limits is not None else (j.lower, j.upper)
    edit.joints[jn] = j.replace(
        mimic_joint=None,
        mimic_multiplier=1.0,
        mimic_offset=0.0,
        lower=lo,
        upper=hi,
        velocity=mod.velocity_limits if mod.velocity_limits is not None else j.velocity,
    )


def _pose(position: Sequence[float], wxyz: Quat) -> FloatArray:
    """The 4x4 transform of a position and a unit quaternion ``(w, x, y, z)``."""
    T = np.eye(4)
    T[:3, :3] = matrix_from_quat(wxyz)
    T[:3, 3] = position
    return T
