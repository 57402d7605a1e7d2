"""The oriented bounding box of a solid, in a frame that is the same on every machine.

trimesh finds the smallest box by comparing the volumes of candidate boxes, one per direction
of the solid's hull. For a symmetric solid -- a plate, a URDF ``<box>`` -- several candidates
are the same box turned about its axes, their volumes equal but for the last bits a BLAS
product leaves, which differ from one machine to another: so does the frame trimesh returns.
A sheet's spheres are laid out in that frame and a bounding-box solid is built in it, so the
frame is made canonical here: each axis points where its first clearly non-zero component is
positive, axes of equal extents (a square plate) are ordered by their directions and their
extents made equal, and the last axis completes a right-handed frame.
"""

from __future__ import annotations

import functools
from typing import Any

import numpy as np
import numpy.typing as npt

from ..util.arrays import FloatArray
from ..util.fixed_order import rigid_inverse

#: Extents within this fraction of each other are one extent (a square plate's sides).
SAME_EXTENT = 1e-9
#: A unit axis' component this small is zero when the axis' direction is chosen or compared.
ZERO_COMPONENT = 1e-9


def oriented_box(points: npt.ArrayLike) -> tuple[FloatArray, FloatArray]:
    """``(to_link, extents)``: the 4x4 rigid transform from the box frame (the box centred at
    its origin, along its axes) to the frame of ``points`` [N, 3], and the box's extents
    along its x, y and z axes, ascending. Raises what trimesh raises for a degenerate set."""
    import trimesh

    oriented: Any = trimesh.bounds.oriented_bounds
    to_box, found = oriented(np.asarray(points, dtype=np.float64), ordered=True)
    frame = rigid_inverse(to_box)
    extents = np.asarray(found, dtype=np.float64).copy()
    axes = [_pointing(frame[:3, k]) for k in range(3)]

    def compare(i: int, j: int) -> int:
        return _before(i, j, extents, axes)

    order = sorted(range(3), key=functools.cmp_to_key(compare))
    extents, axes = extents[order], [axes[k] for k in order]
    for k in (2, 1):
        if extents[k] - extents[k - 1] <= SAME_EXTENT * extents[k]:
            extents[k - 1] = extents[k]
    out = np.eye(4)
    out[:3, 0], out[:3, 1] = axes[0], axes[1]
    out[:3, 2] = np.cross(axes[0], axes[1])
    out[:3, 3] = frame[:3, 3]
    return out, extents


def _pointing(axis: FloatArray) -> FloatArray:
    """``axis`` or its opposite: the one whose first clearly non-zero component is positive."""
    for c in axis:
        if abs(c) > ZERO_COMPONENT:
            return axis if c > 0.0 else -axis
    return axis


def _before(i: int, j: int, extents: FloatArray, axes: list[FloatArray]) -> int:
    """Axes by extent, axes of the same extent by direction (first clearly different
    component)."""
    a, b = float(extents[i]), float(extents[j])
    if abs(a - b) > SAME_EXTENT * max(a, b):
        return -1 if a < b else 1
    for x, y in zip(axes[i], axes[j], strict=True):
        if abs(x - y) > ZERO_COMPONENT:
            return -1 if x < y else 1
    return 0
