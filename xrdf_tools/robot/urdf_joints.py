"""One URDF joint as plain, typed values (:class:`JointInfo`), read from a yourdfpy joint.

The bottom of the robot model: it imports nothing of xrdf-tools, so
:class:`~xrdf_tools.robot.core.Robot`, the kinematics, the linter and the converter build on it.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np
import numpy.typing as npt

__all__ = ["MOVABLE_TYPES", "JointInfo", "joint_info"]

FloatArray = npt.NDArray[np.float64]

MOVABLE_TYPES = ("revolute", "continuous", "prismatic")


@dataclass(frozen=True, eq=False)
class JointInfo:
    """One URDF joint as plain values.

    ``origin`` is the (4, 4) read-only transform from the parent link to the joint frame (which
    is also the child link frame at joint value 0). ``axis`` is the axis as written (default
    ``(1, 0, 0)``, not normalised). ``lower``/``upper``/``velocity`` are ``None`` when the URDF
    does not give them. A mimic follower has ``mimic_joint`` set and moves as
    ``mimic_multiplier * q[mimic_joint] + mimic_offset``. ``line`` is the line of the
    ``<joint>`` element when known.
    """

    name: str
    type: str
    parent: str
    child: str
    origin: FloatArray
    axis: tuple[float, float, float] = (1.0, 0.0, 0.0)
    lower: float | None = None
    upper: float | None = None
    velocity: float | None = None
    mimic_joint: str | None = None
    mimic_multiplier: float = 1.0
    mimic_offset: float = 0.0
    line: int | None = None

    def __post_init__(self) -> None:
        origin = np.array(self.origin, dtype=np.float64, copy=True)
        if origin.shape != (4, 4):
            raise ValueError(f"joint '{self.name}': origin must be 4x4, got {origin.shape}")
        origin.flags.writeable = False
        object.__setattr__(self, "origin", origin)

    @property
    def is_movable(self) -> bool:
        """Revolute, continuous or prismatic (floating and planar joints are not modelled)."""
        return self.type in MOVABLE_TYPES

    @property
    def is_mimic(self) -> bool:
        return self.mimic_joint is not None

    @property
    def is_actuated(self) -> bool:
        """Movable and not a mimic follower: a coordinate of the configuration."""
        return self.is_movable and not self.is_mimic

    def replace(self, **changes: Any) -> JointInfo:
        return replace(self, **changes)

    def _key(self) -> tuple[Any, ...]:
        return (
            self.name,
            self.type,
            self.parent,
            self.child,
            self.origin.tobytes(),
            self.axis,
            self.lower,
            self.upper,
            self.velocity,
            self.mimic_joint,
            self.mimic_multiplier,
            self.mimic_offset,
        )

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, JointInfo):
            return NotImplemented
        return self._key() == other._key()

    def __hash__(self) -> int:
        return hash((self.name, self.type, self.parent, self.child))


def joint_info(j: Any, line: int | None) -> JointInfo:
    """One yourdfpy joint as :class:`JointInfo` (``line``: of its ``<joint>`` element)."""
    name = str(j.name)
    origin = np.eye(4) if j.origin is None else np.asarray(j.origin, dtype=np.float64)
    axis_arr = np.array([1.0, 0.0, 0.0]) if j.axis is None else np.asarray(j.axis, dtype=np.float64)
    limit = j.limit
    mimic = j.mimic
    return JointInfo(
        name=name,
        type=str(j.type),
        parent=str(j.parent),
        child=str(j.child),
        origin=origin,
        axis=(float(axis_arr[0]), float(axis_arr[1]), float(axis_arr[2])),
        lower=_opt_float(limit.lower) if limit is not None else None,
        upper=_opt_float(limit.upper) if limit is not None else None,
        velocity=_opt_float(limit.velocity) if limit is not None else None,
        mimic_joint=str(mimic.joint) if mimic is not None else None,
        mimic_multiplier=(
            1.0 if mimic is None or mimic.multiplier is None else float(mimic.multiplier)
        ),
        mimic_offset=0.0 if mimic is None or mimic.offset is None else float(mimic.offset),
        line=line,
    )


def _opt_float(v: Any) -> float | None:
    return None if v is None else float(v)
