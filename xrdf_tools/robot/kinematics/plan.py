"""The per-frame constants batched FK multiplies, computed once per :class:`KinematicModel`.

A frame's pose is its parent's pose times the joint origin times the joint motion. The plan
folds the origin and the joint axis into one constant matrix per frame, so that FK is one
stacked matmul per frame plus elementwise terms in ``sin θ``, ``1 − cos θ`` or the prismatic
displacement (see :func:`xrdf_tools.robot.kinematics.fk_batch_last`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

import numpy as np
import numpy.typing as npt

from ...util.arrays import FloatArray, IntArray
from ...util.fixed_order import matmul
from ...util.rotations import axis_angle_matrix, skew
from .base import MOVING_TYPES, JointType


class FrameArrays(Protocol):
    """The per-frame arrays a plan is made from (a :class:`~.model.KinematicModel` has them)."""

    @property
    def n_frames(self) -> int: ...
    @property
    def parent(self) -> IntArray: ...
    @property
    def joint_type(self) -> npt.NDArray[np.int8]: ...
    @property
    def origin(self) -> FloatArray: ...
    @property
    def axis(self) -> FloatArray: ...
    @property
    def q_index(self) -> IntArray: ...
    @property
    def mimic_multiplier(self) -> FloatArray: ...
    @property
    def mimic_offset(self) -> FloatArray: ...


# How the FK loop treats a frame.
KIND_FIXED, KIND_ROT, KIND_PRISM = 0, 1, 2


@dataclass(frozen=True)
class FkPlan:
    """Per-frame constants for FK (index 0, the root, is unused).

    The constants of frame ``f`` form a (3, c) matrix ``M`` multiplied by the parent rotation:
    fixed ``[A | t]``, revolute ``[A | A·K | A·aaᵀ − A | t]``, prismatic ``[A | t | A·a]``,
    where ``A``/``t`` are the joint origin's rotation/translation, ``a`` the unit axis and
    ``K`` its cross-product matrix (Rodrigues: ``A·R(θ) = A + sinθ·A·K + (1−cosθ)(A·aaᵀ − A)``).
    """

    parents: tuple[int, ...]
    kinds: tuple[int, ...]
    consts_t: tuple[FloatArray, ...]  # (c, 3): the constants transposed, for the matmul
    consts_root: tuple[FloatArray, ...]  # (3, c, 1): the product when the parent is the root
    rows: tuple[int, ...]  # prismatic: row of the joint values; revolute: row of sin/cos
    row_q: IntArray  # [n_rows] index into q
    row_mult: FloatArray  # [n_rows]
    row_off: FloatArray  # [n_rows]
    rot_rows: IntArray  # rows of revolute/continuous joints (the ones needing sin/cos)


def joint_transform(jt: int, axis: FloatArray, value: float) -> FloatArray:
    """The 4x4 motion of a joint of type ``jt`` about/along the unit ``axis`` at ``value``
    (identity for joints that do not move)."""
    T = np.eye(4)
    if jt in (JointType.REVOLUTE, JointType.CONTINUOUS):
        T[:3, :3] = axis_angle_matrix(axis, value)
    elif jt == JointType.PRISMATIC:
        T[:3, 3] = value * axis
    return T


def make_plan(model: FrameArrays) -> FkPlan:
    """The :class:`FkPlan` of ``model``.

    A movable frame that no coordinate drives (a mimic of a joint held fixed) has its constant
    joint value baked into its origin and becomes a fixed frame of the plan.
    """
    kinds = [KIND_FIXED]
    consts: list[FloatArray] = [np.zeros((3, 4))]
    rows = [-1]
    rot_rows: list[int] = []
    row_q: list[int] = []
    row_mult: list[float] = []
    row_off: list[float] = []
    for i in range(1, model.n_frames):
        jt = int(model.joint_type[i])
        T = np.array(model.origin[i])
        a = model.axis[i]
        movable = jt in MOVING_TYPES
        if movable and model.q_index[i] < 0:
            T = matmul(T, joint_transform(jt, a, float(model.mimic_offset[i])))
            movable = False
        A, t = T[:3, :3], T[:3, 3:4]
        if not movable:
            kinds.append(KIND_FIXED)
            consts.append(np.ascontiguousarray(np.hstack([A, t])))
            rows.append(-1)
            continue
        if jt == JointType.PRISMATIC:
            rows.append(len(row_q))
            kinds.append(KIND_PRISM)
            consts.append(np.ascontiguousarray(np.hstack([A, t, matmul(A, a)[:, None]])))
        else:
            rows.append(len(rot_rows))
            rot_rows.append(len(row_q))
            kinds.append(KIND_ROT)
            K = skew(a)
            aa = matmul(A, np.outer(a, a)) - A
            consts.append(np.ascontiguousarray(np.hstack([A, matmul(A, K), aa, t])))
        row_q.append(int(model.q_index[i]))
        row_mult.append(float(model.mimic_multiplier[i]))
        row_off.append(float(model.mimic_offset[i]))
    consts_t = tuple(np.ascontiguousarray(c.T) for c in consts)
    consts_root = tuple(np.ascontiguousarray(c[:, :, None]) for c in consts)
    for c in (*consts_t, *consts_root):
        c.flags.writeable = False
    return FkPlan(
        parents=tuple(int(p) for p in model.parent),
        kinds=tuple(kinds),
        consts_t=consts_t,
        consts_root=consts_root,
        rows=tuple(rows),
        row_q=np.array(row_q, dtype=np.intp),
        rot_rows=np.array(rot_rows, dtype=np.intp),
        row_mult=np.array(row_mult, dtype=np.float64),
        row_off=np.array(row_off, dtype=np.float64),
    )
