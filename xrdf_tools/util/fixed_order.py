"""Small matrix products with the same bits on every machine.

A BLAS or LAPACK product (``@``, ``np.dot``, ``np.linalg.inv``, trimesh's
``apply_transform``) is computed by kernels the library picks for the CPU at run time: with or
without fused multiply-add, in SIMD lanes of different widths, blocked differently. The last
bits of the result then differ from one machine to another (an AVX2 laptop, an AVX-512 CI
runner, another BLAS build). Where such bits reach an output, directly or through a fit that
amplifies them, the same inputs would give different bytes on another machine.

The functions here sum the inner dimension term by term, in index order, with separate
multiplies and adds (numpy never fuses them), so each result depends only on its inputs. They
are meant for the small inner dimensions of geometry (3 or 4); the hot loops that only take
decisions protected by error bounds may keep BLAS.
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

from .arrays import FloatArray

__all__ = [
    "QUANTUM",
    "matmul",
    "norm",
    "quantized",
    "rigid_inverse",
    "transform_points",
]

#: Grid (m) that mesh vertices are rounded to before anything is fitted to them: about 0.14 µm,
#: far below any length the fit outputs (0.1 mm) or a message shows (a 0.3 mm sheet stays
#: 0.3 mm), far above the last-bit differences a mesh loader's own transforms leave on another
#: machine (below 1e-15 m at a metre). An irrational multiple of 0.1 µm:
#: on a power-of-two grid a float32 coordinate (an STL file) lies exactly on a rounding
#: midpoint one time in 64, on a decimal one a coordinate written in 0.1 µm (a text file) one
#: time in 10; there a last bit decides the rounding.
QUANTUM = 1e-7 * math.sqrt(2.0)


def matmul(a: npt.ArrayLike, b: npt.ArrayLike) -> FloatArray:
    """``a @ b`` (float64, leading dimensions broadcast; a 1-D ``b`` is a column vector), the
    inner dimension summed term by term in index order."""
    x = np.asarray(a, dtype=np.float64)
    y = np.asarray(b, dtype=np.float64)
    vector = y.ndim == 1
    if vector:
        y = y[:, None]
    out = x[..., :, 0, None] * y[..., 0, None, :]
    for k in range(1, x.shape[-1]):
        out = out + x[..., :, k, None] * y[..., k, None, :]
    result: FloatArray = out[..., 0] if vector else out
    return result


def transform_points(T: npt.ArrayLike, points: npt.ArrayLike) -> FloatArray:
    """Points ``[N, 3]`` moved by the 4x4 transform ``T``: ``R p + t``, term by term."""
    m = np.asarray(T, dtype=np.float64)
    p = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    out = p[:, 0, None] * m[None, :3, 0]
    out = out + p[:, 1, None] * m[None, :3, 1]
    out = out + p[:, 2, None] * m[None, :3, 2]
    result: FloatArray = out + m[None, :3, 3]
    return result


def rigid_inverse(T: npt.ArrayLike) -> FloatArray:
    """Inverse of the rigid 4x4 transform(s) ``T`` [..., 4, 4]: ``[Rᵀ, −Rᵀ t]``."""
    m = np.asarray(T, dtype=np.float64)
    out = np.zeros(m.shape)
    rt = np.swapaxes(m[..., :3, :3], -1, -2)
    out[..., :3, :3] = rt
    out[..., :3, 3] = -matmul(rt, m[..., :3, 3, None])[..., 0]
    out[..., 3, 3] = 1.0
    return out


def norm(v: npt.ArrayLike) -> float:
    """Euclidean length of one vector, its squares summed in order (``np.linalg.norm`` of a
    vector is a BLAS dot product)."""
    return math.sqrt(sum(float(x) * float(x) for x in np.asarray(v, dtype=np.float64).ravel()))


def quantized(vertices: npt.ArrayLike) -> FloatArray:
    """``vertices`` rounded to the nearest point of the :data:`QUANTUM` grid.

    A fit amplifies a last-bit difference in its input into different spheres; rounding every
    coordinate to the grid first makes such differences vanish, except for a coordinate that
    lies within a last bit of a grid midpoint (about one in 10⁹ at a metre)."""
    v = np.asarray(vertices, dtype=np.float64)
    out: FloatArray = np.round(v / QUANTUM) * QUANTUM + 0.0  # + 0.0: no -0.0
    return out
