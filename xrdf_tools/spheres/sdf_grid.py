"""The signed distance grid of one solid that the sphere fit reads (:mod:`.fit`): which nodes
lie inside (:func:`.inside.grid_inside`), a Euclidean distance transform for distances, and
near the surface each node's exact distance to the faces of the nearest surface samples
(:func:`.distance.near_face_distance`); trilinear lookup, and the level set of any distance
as points on the grid's edges.

A grid of :data:`GRID_CELLS` cubic cells along its longest side (in the solid's own frame) is
the default. A part much thinner than such a cell (a 0.5 m rod 2 mm thick: 12 mm cells) would
have its level sets interpolated across cells far wider than their own curve, and spheres
whose radii come from them reach well past the bound. Its grid (:func:`thin_sdf`) is laid in
the part's oriented bounding box instead (a rod along (1, 1, 1) as one along x), its cubic cells
following the part's thickness and the bound (:func:`level_radius`), and its margin the
bound alone, within :data:`THIN_GRID_NODES` nodes.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..util.arrays import FloatArray
from ..util.fixed_order import matmul
from .distance import near_face_distance
from .metrics import sample_surface_faces

if TYPE_CHECKING:
    import trimesh

__all__ = [
    "GRID_CELLS",
    "THIN_GRID_NODES",
    "Sdf",
    "build_sdf",
    "level_points",
    "level_radius",
    "needs_thin_grid",
    "thin_sdf",
]

#: Cells along the grid's longest side.
GRID_CELLS = 48
#: The most nodes of a thin part's grid (:func:`thin_sdf`): 2**19, about 4 MB per array of
#: values; its build and the fit on it stay within a second or two.
THIN_GRID_NODES = 2**19
#: A thin part's grid aims at this many cells across the radius of its level set
#: (:func:`level_radius`).
THIN_CELLS = 4
#: A thin grid's axes are rounded to multiples of 1 / this (about 1e-12), so that the last bits
#: of the oriented box found (BLAS products) do not reach the grid; a canonical axis stays exact.
_AXIS_GRID = float(2**40)
#: Bisection steps that find the finest cell within :data:`THIN_GRID_NODES`.
_BUDGET_STEPS = 40
#: Surface samples whose faces give the exact distances near the surface.
_SURFACE_DENSE = 4_000


@dataclass
class Sdf:
    """Signed distance on a regular grid (negative inside), trilinear lookup. ``origin`` and
    the cells are in the grid's frame: the solid's own (``axes`` None) or turned, its axes the
    columns of ``axes`` in the solid's frame (:func:`thin_sdf`)."""

    origin: FloatArray
    step: float
    values: FloatArray
    axes: FloatArray | None = None

    def __call__(self, points: FloatArray) -> FloatArray:
        from scipy.ndimage import map_coordinates

        idx = ((self.to_grid(points) - self.origin) / self.step).T
        return np.asarray(map_coordinates(self.values, idx, order=1, mode="nearest"))

    def to_grid(self, points: FloatArray) -> FloatArray:
        """Points (or vectors) ``[N, 3]`` of the solid's frame in the grid's."""
        return points if self.axes is None else matmul(points, self.axes)

    def from_grid(self, points: FloatArray) -> FloatArray:
        """Points (or vectors) ``[N, 3]`` of the grid's frame in the solid's."""
        return points if self.axes is None else matmul(points, self.axes.T)


def build_sdf(
    solid: trimesh.Trimesh, margin: float, rng: np.random.Generator, step: float | None = None
) -> Sdf:
    """The distance grid ``margin`` around the solid; its cells ``step`` (default:
    ``GRID_CELLS`` cells along the grid's longest side)."""
    lo, step, values = _grid_values(solid, margin, rng, step)
    return Sdf(lo, step, values)


def _grid_values(
    solid: trimesh.Trimesh,
    margin: float,
    rng: np.random.Generator,
    step: float | None,
    thin: bool = False,
) -> tuple[FloatArray, float, FloatArray]:
    """:func:`build_sdf`'s grid in the solid's frame: its origin, cell and values (``thin``:
    of a part that may be thinner than a cell, :func:`thin_sdf`)."""
    from scipy.ndimage import distance_transform_edt

    from .inside import grid_inside

    lo = np.asarray(solid.bounds[0], dtype=np.float64) - margin
    hi = np.asarray(solid.bounds[1], dtype=np.float64) + margin
    step = float((hi - lo).max()) / GRID_CELLS if step is None else float(step)
    shape = np.ceil((hi - lo) / step).astype(int) + 1
    axes = [lo[i] + step * np.arange(shape[i]) for i in range(3)]
    mask = grid_inside(solid, (axes[0], axes[1], axes[2]))
    dense, dense_faces = sample_surface_faces(solid, _SURFACE_DENSE, rng)
    # coarse distances from the voxel mask; near the surface, the distance to the faces of the
    # nearest surface samples
    outside = distance_transform_edt(~mask)
    if thin:  # few nodes or none may lie inside: the distance to the surface samples' nodes too
        outside = np.minimum(outside, _sample_node_distance(dense, lo, step, mask.shape))
    coarse = np.where(mask, -distance_transform_edt(mask), outside) * step
    band = 3.0 * step
    near_band = np.abs(coarse) <= band + step
    grid = lo + step * np.argwhere(near_band).astype(np.float64)
    near = near_face_distance(solid, grid, dense, dense_faces)
    fine = near <= band
    inside = mask[near_band]
    values = coarse.copy()
    banded = np.where(
        inside, np.minimum(coarse[near_band], -band), np.maximum(coarse[near_band], band)
    )
    banded[fine] = np.where(inside[fine], -near[fine], near[fine])
    values[near_band] = banded
    far = ~near_band
    values[far] = np.where(mask[far], np.minimum(coarse[far], -band), np.maximum(coarse[far], band))
    return lo, step, values


def _sample_node_distance(
    samples: FloatArray, lo: FloatArray, step: float, shape: tuple[int, ...]
) -> FloatArray:
    """Per node, the distance (in cells) to the nearest node next to a surface sample: for a
    part thinner than a cell, whose voxel mask may be empty (a 1 mm plate between nodes
    1.7 mm apart), where its surface is."""
    from scipy.ndimage import distance_transform_edt

    upper = np.asarray(shape, dtype=np.int64) - 1
    nodes = np.clip(np.rint((samples - lo) / step).astype(np.int64), 0, upper)
    empty = np.ones(shape, dtype=bool)
    empty[nodes[:, 0], nodes[:, 1], nodes[:, 2]] = False
    return np.asarray(distance_transform_edt(empty))


def level_radius(solid: trimesh.Trimesh, bound: float) -> float:
    """About how tightly the level set ``sdf == bound`` curves: the bound plus half the
    part's mean thickness (2 volume / area; a rod's radius, a plate's thickness). A grid
    cell wider than this interpolates that level set across more than its own curve."""
    area = float(solid.area)
    half = 2.0 * float(abs(solid.volume)) / area if area > 0.0 else 0.0
    return float(bound) + half


def needs_thin_grid(solid: trimesh.Trimesh, bound: float, cell: float) -> bool:
    """Whether cells of ``cell`` are too coarse for the level set of ``bound`` (wider than
    :func:`level_radius`): a part thinner than its default grid's cells, not an ordinary
    link (the Panda's and UR5's cells are a third or less of it)."""
    return cell > level_radius(solid, bound)


def thin_sdf(solid: trimesh.Trimesh, bound: float, room: float, rng: np.random.Generator) -> Sdf:
    """The distance grid of a thin part (:func:`needs_thin_grid`) for a bound of ``bound``,
    reaching past ``room`` (``>= bound``): in the frame of the part's oriented bounding box
    (its longest side along z: one ray per xy column of the inside test), cubic cells of a
    :data:`THIN_CELLS`-th of :func:`level_radius`, or the finest within
    :data:`THIN_GRID_NODES` nodes, and a margin of ``max(2 bound, room)`` plus three cells."""
    import trimesh

    from .obb import oriented_box

    axes = np.round(oriented_box(solid.vertices)[0][:3, :3] * _AXIS_GRID) / _AXIS_GRID + 0.0
    turned = trimesh.Trimesh(matmul(solid.vertices, axes), solid.faces, process=False)
    extents = np.asarray(turned.extents, dtype=np.float64)
    reach = max(2.0 * float(bound), float(room))
    step = _thin_step(extents, reach, level_radius(solid, bound) / THIN_CELLS)
    lo, step, values = _grid_values(turned, reach + 3.0 * step, rng, step, thin=True)
    return Sdf(lo, step, values, axes)


def _thin_step(extents: FloatArray, reach: float, finest: float) -> float:
    """The cell of a thin part's grid: ``finest``, or the finest within
    :data:`THIN_GRID_NODES` nodes over ``extents`` plus a margin of ``reach`` and three cells
    on each side (found by bisection)."""

    def nodes(step: float) -> float:
        sides = np.ceil((extents + 2.0 * (reach + 3.0 * step)) / step) + 1.0
        return float(sides[0] * sides[1] * sides[2])

    if nodes(finest) <= THIN_GRID_NODES:
        return float(finest)
    lo, hi = float(finest), float(finest)
    while nodes(hi) > THIN_GRID_NODES:
        hi *= 2.0
    for _ in range(_BUDGET_STEPS):
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if nodes(mid) <= THIN_GRID_NODES else (mid, hi)
    return hi


def level_points(sdf: Sdf, level: float) -> FloatArray:
    """Points of the level set ``sdf == level``: on every grid edge whose two nodes lie on
    either side of ``level``, the linearly interpolated crossing (marching-cubes vertices)."""
    values = sdf.values
    out: list[FloatArray] = []
    for axis in range(3):
        a = np.take(values, np.arange(values.shape[axis] - 1), axis=axis)
        b = np.take(values, np.arange(1, values.shape[axis]), axis=axis)
        cross = (a <= level) != (b <= level)
        idx = np.argwhere(cross).astype(np.float64)
        va, vb = a[cross], b[cross]
        idx[:, axis] += (level - va) / (vb - va)
        out.append(sdf.origin + idx * sdf.step)
    pts = np.concatenate(out)
    if len(pts) == 0:  # the budget reaches past the grid: bound by the grid's corners
        pts = (
            sdf.origin
            + np.array(np.meshgrid(*[[0, n - 1] for n in values.shape])).reshape(3, -1).T * sdf.step
        )
    return sdf.from_grid(pts)
