"""The :class:`KinematicModel`: a kinematic tree as flat, read-only arrays, and its lookups
(frames and actuated joints by name, with messages that say why a name is not there)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import numpy as np
import numpy.typing as npt

from ...util.arrays import BoolArray, FloatArray, IntArray
from ...util.errors import UrdfError, did_you_mean
from ...util.frozen import FrozenMap
from ...util.numbers import LIMIT_TOLERANCE
from ..urdf_source import JointInfo
from .base import FrameSelection
from .paths import JointPaths
from .plan import FkPlan, make_plan


@dataclass(frozen=True, eq=False)
class KinematicModel:
    """A kinematic tree as flat arrays in topological order (``parent[i] < i``, root first).

    Per frame (``F = len(frame_names)``):

    * ``parent`` [F] int: parent frame index, -1 for the root;
    * ``joint_of_frame`` [F]: name of the joint attaching the frame to its parent (None: root);
    * ``joint_type`` [F] int8: :class:`JointType` code;
    * ``origin`` [F, 4, 4]: joint origin in the parent frame (identity for the root);
    * ``axis`` [F, 3]: unit joint axis (zero for fixed joints);
    * ``q_index`` [F] int: index into the configuration vector driving the frame, -1 if none;
    * ``mimic_multiplier``, ``mimic_offset`` [F]: joint value ``= mult * q[q_index] + offset``
      (1 and 0 for actuated joints; a movable frame with ``q_index == -1`` stays at ``offset``).

    Per actuated joint (``n = len(actuated_joints)``): ``lower``, ``upper`` [n] position limits
    (``-pi``, ``pi`` for continuous joints, marked in ``continuous`` [n] bool).

    ``joints`` holds every joint kept after the modifiers (URDF joints, as changed by
    ``remove_mimic_attributes``, and added frames' joints) in topological order;
    ``pruned_joints``/``pruned_frames`` list what ``set_base_frame`` removed.
    """

    frame_names: tuple[str, ...]
    parent: IntArray
    joint_of_frame: tuple[str | None, ...]
    joint_type: npt.NDArray[np.int8]
    origin: FloatArray
    axis: FloatArray
    q_index: IntArray
    mimic_multiplier: FloatArray
    mimic_offset: FloatArray
    actuated_joints: tuple[str, ...]
    lower: FloatArray
    upper: FloatArray
    continuous: BoolArray
    joints: Mapping[str, JointInfo] = field(default_factory=FrozenMap)
    pruned_joints: tuple[str, ...] = ()
    pruned_frames: tuple[str, ...] = ()
    added_frames: tuple[str, ...] = ()
    source_path: str = "<urdf>"
    _frame_idx: dict[str, int] = field(init=False, repr=False)
    _joint_idx: dict[str, int] = field(init=False, repr=False)
    _plan: FkPlan = field(init=False, repr=False)

    def __post_init__(self) -> None:
        F = len(self.frame_names)
        n = len(self.actuated_joints)
        arrays: dict[str, tuple[Any, tuple[int, ...]]] = {
            "parent": (np.intp, (F,)),
            "joint_type": (np.int8, (F,)),
            "origin": (np.float64, (F, 4, 4)),
            "axis": (np.float64, (F, 3)),
            "q_index": (np.intp, (F,)),
            "mimic_multiplier": (np.float64, (F,)),
            "mimic_offset": (np.float64, (F,)),
            "lower": (np.float64, (n,)),
            "upper": (np.float64, (n,)),
            "continuous": (np.bool_, (n,)),
        }
        for name, (dtype, shape) in arrays.items():
            arr = np.array(getattr(self, name), dtype=dtype, copy=True)
            if arr.shape != shape:
                raise ValueError(f"KinematicModel.{name} must have shape {shape}, not {arr.shape}")
            arr.flags.writeable = False
            object.__setattr__(self, name, arr)
        if F == 0 or self.parent[0] != -1 or np.any(self.parent[1:] >= np.arange(1, F)):
            raise ValueError("KinematicModel frames must be in topological order, root first")
        if len(self.joint_of_frame) != F:
            raise ValueError("KinematicModel.joint_of_frame must have one entry per frame")
        if np.any((self.q_index < -1) | (self.q_index >= n)):
            raise ValueError("KinematicModel.q_index out of range")
        object.__setattr__(self, "joints", FrozenMap(self.joints))
        object.__setattr__(self, "_frame_idx", {f: i for i, f in enumerate(self.frame_names)})
        object.__setattr__(self, "_joint_idx", {j: i for i, j in enumerate(self.actuated_joints)})
        object.__setattr__(self, "_plan", make_plan(self))

    # --- sizes and names -------------------------------------------------------------------
    @property
    def n_frames(self) -> int:
        return len(self.frame_names)

    @property
    def n_actuated(self) -> int:
        return len(self.actuated_joints)

    @property
    def base_frame(self) -> str:
        """The root frame: poses are expressed in it."""
        return self.frame_names[0]

    @property
    def mimic_joints(self) -> tuple[str, ...]:
        """Kept mimic followers, in topological order."""
        return tuple(n for n, j in self.joints.items() if j.is_movable and j.is_mimic)

    def has_frame(self, name: str) -> bool:
        return name in self._frame_idx

    def joints_on_path(self, frame_a: str, frame_b: str) -> tuple[str, ...]:
        """The actuated joints whose values change the pose of ``frame_b`` relative to
        ``frame_a`` (the joints between each frame and their common ancestor; a mimic joint
        counts as its master), in configuration order."""
        a, b = self.frame_index(frame_a), self.frame_index(frame_b)
        bits = self.joint_paths.between([a], [b])[0]
        return tuple(name for i, name in enumerate(self.actuated_joints) if bits >> i & 1)

    @cached_property
    def joint_paths(self) -> JointPaths:
        """The actuated joints between frames, for many frame pairs at once
        (:meth:`JointPaths.between`: bit ``i`` of a mask is ``q[i]``)."""
        return JointPaths(self.parent, self.q_index)

    def frame_index(self, name: str) -> int:
        """Index of frame ``name``; :class:`UrdfError` with a suggestion when unknown."""
        try:
            return self._frame_idx[name]
        except KeyError:
            pass
        if name in self.pruned_frames:
            raise UrdfError(
                f"frame '{name}' was removed by set_base_frame '{self.base_frame}' (only frames "
                f"below the base frame are kept)",
                path=self.source_path,
            )
        raise UrdfError(
            f"unknown frame '{name}'" + did_you_mean(name, self.frame_names),
            path=self.source_path,
        )

    def actuated_index(self, name: str) -> int:
        """Index of an actuated joint in ``q``; :class:`UrdfError` says why a joint is not."""
        try:
            return self._joint_idx[name]
        except KeyError:
            pass
        why = self.not_actuated_reason(name)
        raise UrdfError(f"joint '{name}' {why}", path=self.source_path)

    def cspace_reason(self, name: str) -> str:
        """Why ``name`` cannot be a c-space joint: :meth:`not_actuated_reason`, or position
        limits that no position fits (the URDF's lower above its upper, read as written for a
        joint no c-space uses); empty for a joint that can."""
        why = self.not_actuated_reason(name)
        if why:
            return why
        i = self._joint_idx[name]
        lower, upper = float(self.lower[i]), float(self.upper[i])
        if lower > upper:
            return (
                f"has its lower limit {lower:g} above its upper limit {upper:g} in the URDF: "
                "no position fits"
            )
        return ""

    def outside_limits(self, name: str, value: float) -> str:
        """Why the actuated joint ``name`` cannot be at ``value`` ("is outside its limits
        [lo, hi]", past :data:`~xrdf_tools.util.numbers.LIMIT_TOLERANCE`); empty for a
        position within them, and for a continuous joint."""
        i = self._joint_idx[name]
        if bool(self.continuous[i]):
            return ""
        lo, hi = float(self.lower[i]), float(self.upper[i])
        if lo - LIMIT_TOLERANCE <= value <= hi + LIMIT_TOLERANCE:
            return ""
        return f"is outside its limits [{lo:g}, {hi:g}]"

    def not_actuated_reason(self, name: str) -> str:
        """Why ``name`` is no coordinate of ``q`` ("is a mimic joint (…)", "is not a joint of
        the robot; did you mean …?"); empty for an actuated joint."""
        if name in self._joint_idx:
            return ""
        j = self.joints.get(name)
        if j is not None and j.is_mimic and j.is_movable:
            return f"is a mimic joint (it follows '{j.mimic_joint}'), not a coordinate"
        if j is not None:
            return f"is a {j.type} joint, which has no coordinate"
        if name in self.pruned_joints:
            return f"was removed by set_base_frame '{self.base_frame}'"
        return "is not a joint of the robot" + did_you_mean(name, self.actuated_joints)

    def frame_indices(self, frames: FrameSelection) -> IntArray:
        """Indices for ``frames`` (names or indices; None = all) as an int array [F']."""
        if frames is None:
            return np.arange(self.n_frames, dtype=np.intp)
        if isinstance(frames, str):
            frames = [frames]
        out = np.empty(len(frames), dtype=np.intp)
        for k, f in enumerate(frames):
            if isinstance(f, str):
                out[k] = self.frame_index(f)
            else:
                i = int(f)
                if not 0 <= i < self.n_frames:
                    raise ValueError(f"frame index {i} out of range [0, {self.n_frames})")
                out[k] = i
        return out

    def ancestors(self, frame: int | str) -> list[int]:
        """Indices from ``frame`` up to the root (both included; each parent index is smaller
        than its child's, so the walk ends)."""
        i = self.frame_index(frame) if isinstance(frame, str) else int(frame)
        chain: list[int] = []
        while i >= 0:
            chain.append(i)
            i = int(self.parent[i])
        return chain
