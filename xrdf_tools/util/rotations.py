"""Rotation conversions, one formula each, for every module that turns an orientation into
another form.

Conventions (the URDF and XRDF ones):

* quaternions are ``(w, x, y, z)`` unless a name says ``xyzw`` (the ROS/Foxglove order);
* roll-pitch-yaw angles are radians about fixed axes, ``R = Rz(yaw) · Ry(pitch) · Rx(roll)``;
* a rotation matrix is row-major and maps child-frame coordinates to parent-frame ones.

The scalar conversions use :mod:`math` only and return nested tuples, so importing this module
does not import numpy (the XRDF model and the linter use it at start-up); the conversions on
arrays import numpy when first called.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    FloatArray = npt.NDArray[np.float64]

__all__ = [
    "Matrix3",
    "Quat",
    "axis_angle_matrix",
    "matrix_from_quat",
    "matrix_from_rpy",
    "quat_from_rpy",
    "quat_xyzw_from_matrix",
    "quats_xyzw_from_matrices",
    "rpy_from_matrix",
    "skew",
    "unit_quat",
]

Quat = tuple[float, float, float, float]
Row = tuple[float, float, float]
Matrix3 = tuple[Row, Row, Row]

_IDENTITY_QUAT: Quat = (1.0, 0.0, 0.0, 0.0)


def unit_quat(w: float, x: float, y: float, z: float) -> Quat:
    """``(w, x, y, z)`` scaled to unit length; the zero quaternion becomes the identity."""
    n = math.sqrt(w * w + x * x + y * y + z * z)
    if n == 0.0:
        return _IDENTITY_QUAT
    return (w / n, x / n, y / n, z / n)


def quat_from_rpy(roll: float, pitch: float, yaw: float) -> Quat:
    """Quaternion ``(w, x, y, z)`` of roll-pitch-yaw angles (unit up to rounding)."""
    cr, sr = math.cos(roll / 2), math.sin(roll / 2)
    cp, sp = math.cos(pitch / 2), math.sin(pitch / 2)
    cy, sy = math.cos(yaw / 2), math.sin(yaw / 2)
    return (
        cr * cp * cy + sr * sp * sy,
        sr * cp * cy - cr * sp * sy,
        cr * sp * cy + sr * cp * sy,
        cr * cp * sy - sr * sp * cy,
    )


def matrix_from_quat(wxyz: Quat) -> Matrix3:
    """Rotation matrix of a unit quaternion ``(w, x, y, z)``."""
    w, x, y, z = wxyz
    return (
        (1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)),
        (2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)),
        (2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)),
    )


def matrix_from_rpy(roll: float, pitch: float, yaw: float) -> Matrix3:
    """Rotation matrix of roll-pitch-yaw angles, ``Rz(yaw) · Ry(pitch) · Rx(roll)`` expanded
    (the direct product, not through a quaternion: it is what a URDF ``rpy`` means)."""
    cr, sr = math.cos(roll), math.sin(roll)
    cp, sp = math.cos(pitch), math.sin(pitch)
    cw, sw = math.cos(yaw), math.sin(yaw)
    return (
        (cw * cp, cw * sp * sr - sw * cr, cw * sp * cr + sw * sr),
        (sw * cp, sw * sp * sr + cw * cr, sw * sp * cr - cw * sr),
        (-sp, cp * sr, cp * cr),
    )


def rpy_from_matrix(m: Any) -> tuple[float, float, float]:
    """Roll-pitch-yaw angles of a rotation matrix (the inverse of :func:`matrix_from_rpy`),
    pitch in [-π/2, π/2]. Roll is read from what is left once yaw and pitch are undone, so the
    angles give the matrix back to rounding also at pitch ±π/2 (where roll and yaw turn about
    one axis and yaw alone is not defined)."""
    r = [[float(m[i][j]) for j in range(3)] for i in range(3)]
    pitch = math.atan2(-r[2][0], math.hypot(r[0][0], r[1][0]))
    yaw = math.atan2(r[1][0], r[0][0])
    cy, sy, cp, sp = math.cos(yaw), math.sin(yaw), math.cos(pitch), math.sin(pitch)
    left_y = -sy * r[0][1] + cy * r[1][1]
    left_z = sp * (cy * r[0][1] + sy * r[1][1]) + cp * r[2][1]
    return math.atan2(left_z, left_y), pitch, yaw


def quat_xyzw_from_matrix(rotation: Any) -> Quat:
    """Unit quaternion ``(x, y, z, w)`` of a rotation matrix [3, 3]: one matrix of
    :func:`quats_xyzw_from_matrices`."""
    import numpy as np

    q = quats_xyzw_from_matrices(np.asarray(rotation, dtype=np.float64)[None])[0]
    return (float(q[0]), float(q[1]), float(q[2]), float(q[3]))


def quats_xyzw_from_matrices(rotations: Any) -> FloatArray:
    """Unit quaternions ``(x, y, z, w)`` [..., 4] of rotation matrices [..., 3, 3] (Shepperd's
    method: the largest of ``w, x, y, z`` is computed first, so no division by a small number),
    with ``w >= 0``. Elementwise arithmetic and a norm summed in order: each quaternion has the
    same bits on every machine and in any batch."""
    import numpy as np

    m = np.asarray(rotations, dtype=np.float64)
    d0, d1, d2 = m[..., 0, 0], m[..., 1, 1], m[..., 2, 2]
    tr = d0 + d1 + d2
    case = np.where(tr > 0, 0, np.where((d0 > d1) & (d0 > d2), 1, np.where(d1 > d2, 2, 3)))
    with np.errstate(invalid="ignore", divide="ignore"):
        s = 2.0 * np.sqrt(
            np.choose(case, [tr + 1.0, 1.0 + d0 - d1 - d2, 1.0 + d1 - d0 - d2, 1.0 + d2 - d0 - d1])
        )
        a21, a02, a10 = (
            m[..., 2, 1] - m[..., 1, 2],
            m[..., 0, 2] - m[..., 2, 0],
            m[..., 1, 0] - m[..., 0, 1],
        )
        b01, b02, b12 = (
            m[..., 0, 1] + m[..., 1, 0],
            m[..., 0, 2] + m[..., 2, 0],
            m[..., 1, 2] + m[..., 2, 1],
        )
        quarter = 0.25 * s
        w = np.choose(case, [quarter, a21 / s, a02 / s, a10 / s])
        x = np.choose(case, [a21 / s, quarter, b01 / s, b02 / s])
        y = np.choose(case, [a02 / s, b01 / s, quarter, b12 / s])
        z = np.choose(case, [a10 / s, b02 / s, b12 / s, quarter])
    length = np.sqrt(((x * x + y * y) + z * z) + w * w)
    q = np.stack([x, y, z, w], axis=-1) / length[..., None]
    q = np.where(q[..., 3:] < 0, -q, q)
    result: FloatArray = q
    return result


def skew(axis: FloatArray) -> FloatArray:
    """Cross-product matrix ``K`` of a 3-vector ``a`` (``K @ v == a × v``)."""
    import numpy as np

    a = axis
    return np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])


def axis_angle_matrix(axis: FloatArray, angle: float) -> FloatArray:
    """Rotation by ``angle`` radians about the unit ``axis`` (Rodrigues:
    ``I + sin θ · K + (1 − cos θ) · K²``)."""
    import numpy as np

    from .fixed_order import matmul

    K = skew(axis)
    out: FloatArray = np.eye(3) + math.sin(angle) * K + (1 - math.cos(angle)) * matmul(K, K)
    return out
