"""One URDF joint as plain, typed values (:class:`JointInfo`), read from its checked
``<joint>`` element (:func:`joint_from_xml`) or from a yourdfpy joint (:func:`joint_info`).

Both read the numbers as yourdfpy does (``float`` of each whitespace-separated field; the
origin composed as translation then ``rpy`` in the static xyz convention, with the same numpy
operations), so both give the same bits.

The bottom of the robot model: it imports nothing of xrdf-tools, so
:class:`~xrdf_tools.robot.core.Robot`, the kinematics, the linter and the converter build on it.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from ..util.arrays import FloatArray

__all__ = ["MOVABLE_TYPES", "JointInfo", "joint_from_xml", "joint_info", "origin_matrix"]


MOVABLE_TYPES = ("revolute", "continuous", "prismatic")


@dataclass(frozen=True, eq=False)
class JointInfo:
    """One URDF joint as plain values.

    ``origin`` is the (4, 4) read-only transform from the parent link to the joint frame (which
    is also the child link frame at joint value 0). ``axis`` is the axis as written (default
    ``(1, 0, 0)``, not normalised). ``lower``/``upper``/``velocity``/``effort`` are ``None``
    when the URDF does not give them. A mimic follower has ``mimic_joint`` set and moves as
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
    effort: float | None = None
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
    def is_held(self) -> bool:
        """Revolute or prismatic with equal lower and upper limits and no mimic: it cannot
        move (a CAD exporter writes 0 0 for limits never set). Reversed limits are a mistake,
        not this. A mimic follower moves with its master whatever its own limits say (the
        kinematics and cuRobo ignore them): a gripper's second finger exported with limits
        0 0 counted as held, so the links either side of it were adjacent one joint too far
        and their pair left out of the self-collision checks."""
        return (
            self.type in ("revolute", "prismatic")
            and not self.is_mimic
            and (self.lower is not None and self.lower == self.upper)
        )

    @property
    def limits_reversed(self) -> bool:
        """Revolute or prismatic with its lower limit above its upper (one not given is 0, as
        the kinematic model reads it): no position fits."""
        low = 0.0 if self.lower is None else self.lower
        high = 0.0 if self.upper is None else self.upper
        return self.type in ("revolute", "prismatic") and low > high

    @property
    def unset_position(self) -> float:
        """The position an XRDF gives this joint when ``default_joint_positions`` does not name
        it: zero clamped to its limits (a limit not given is the URDF default 0, as the
        kinematic model reads it; a continuous joint has none)."""
        if self.type == "continuous":
            return 0.0
        low = 0.0 if self.lower is None else self.lower
        high = 0.0 if self.upper is None else self.upper
        return float(min(max(0.0, low), high))

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
            self.effort,
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
        effort=_opt_float(limit.effort) if limit is not None else None,
        mimic_joint=str(mimic.joint) if mimic is not None else None,
        mimic_multiplier=(
            1.0 if mimic is None or mimic.multiplier is None else float(mimic.multiplier)
        ),
        mimic_offset=0.0 if mimic is None or mimic.offset is None else float(mimic.offset),
        line=line,
    )


def _opt_float(v: Any) -> float | None:
    return None if v is None else float(v)


def joint_from_xml(e: Any, line: int | None) -> JointInfo:
    """One checked ``<joint>`` element (lxml) as :class:`JointInfo`."""
    origin = e.find("origin")
    axis = e.find("axis")
    limit = e.find("limit")
    mimic = e.find("mimic")
    axis_xyz = [1.0, 0.0, 0.0] if axis is None else _floats(axis.get("xyz", "1 0 0"))
    return JointInfo(
        name=str(e.get("name")),
        type=str(e.get("type")),
        parent=str(e.find("parent").get("link")),
        child=str(e.find("child").get("link")),
        origin=np.eye(4) if origin is None else origin_matrix(origin),
        axis=(float(axis_xyz[0]), float(axis_xyz[1]), float(axis_xyz[2])),
        lower=_opt_float(limit.get("lower")) if limit is not None else None,
        upper=_opt_float(limit.get("upper")) if limit is not None else None,
        velocity=_opt_float(limit.get("velocity")) if limit is not None else None,
        effort=_opt_float(limit.get("effort")) if limit is not None else None,
        mimic_joint=str(mimic.get("joint")) if mimic is not None else None,
        mimic_multiplier=1.0 if mimic is None else float(mimic.get("multiplier", 1.0)),
        mimic_offset=0.0 if mimic is None else float(mimic.get("offset", 0.0)),
        line=line,
    )


def origin_matrix(origin: Any) -> FloatArray:
    """The (4, 4) transform of an ``<origin xyz rpy>`` element: translation, then the rotation
    ``Rz(yaw) Ry(pitch) Rx(roll)``, composed exactly as yourdfpy composes it."""
    xyz = np.array(_floats(origin.get("xyz", "0 0 0")))
    rpy = np.array(_floats(origin.get("rpy", "0 0 0")))
    translate = np.identity(4)
    translate[:3, 3] = xyz[:3]
    m: FloatArray = np.dot(np.identity(4), translate)
    m = np.dot(m, _static_xyz_matrix(rpy[0], rpy[1], rpy[2]))
    m /= m[3, 3]
    return m


def _static_xyz_matrix(ai: float, aj: float, ak: float) -> FloatArray:
    """Rotation about static x by ``ai``, then y by ``aj``, then z by ``ak`` (4, 4)."""
    si, sj, sk = np.sin(ai), np.sin(aj), np.sin(ak)
    ci, cj, ck = np.cos(ai), np.cos(aj), np.cos(ak)
    cc, cs = ci * ck, ci * sk
    sc, ss = si * ck, si * sk
    m = np.eye(4)
    m[0, 0] = cj * ck
    m[0, 1] = sj * sc - cs
    m[0, 2] = sj * cc + ss
    m[1, 0] = cj * sk
    m[1, 1] = sj * ss + cc
    m[1, 2] = sj * cs - sc
    m[2, 0] = -sj
    m[2, 1] = cj * si
    m[2, 2] = cj * ci
    return m


def _floats(text: str) -> list[float]:
    return list(map(float, text.split()))
