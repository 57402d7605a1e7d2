"""The signed distance grid of one solid that the sphere fit reads (:mod:`.fit`): which nodes
lie inside (:func:`.inside.grid_inside`), a Euclidean distance transform for distances, and
near the surface each node's exact distance to the faces of the nearest surface samples
(:func:`.distance.near_face_distance`); trilinear lookup, and the level set of any distance
as points on the grid's edges."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..util.arrays import FloatArray
from .distance import near_face_distance
from .metrics import sample_surface_faces

if TYPE_CHECKING:
    import trimesh

__all__ = ["GRID_CELLS", "Sdf", "build_sdf", "level_points"]

#: Cells along the grid's longest side.
GRID_CELLS = 48
#: Surface samples whose faces give the exact distances near the surface.
_SURFACE_DENSE = 4_000


@dataclass
class Sdf:
    """Signed distance on a regular grid (negative inside), trilinear lookup."""

    origin: FloatArray
    step: float
    values: FloatArray

    def __call__(self, points: FloatArray) -> FloatArray:
        from scipy.ndimage import map_coordinates

        idx = ((points - self.origin) / self.step).T
        return np.asarray(map_coordinates(self.values, idx, order=1, mode="nearest"))


def build_sdf(
    solid: trimesh.Trimesh, margin: float, rng: np.random.Generator, step: float | None = None
) -> Sdf:
    """The distance grid ``margin`` around the solid; its cells ``step`` (default:
    ``GRID_CELLS`` cells along the grid's longest side)."""
    from scipy.ndimage import distance_transform_edt

    from .inside import grid_inside

    lo = np.asarray(solid.bounds[0], dtype=np.float64) - margin
    hi = np.asarray(solid.bounds[1], dtype=np.float64) + margin
    step = float((hi - lo).max()) / GRID_CELLS if step is None else float(step)
    shape = np.ceil((hi - lo) / step).astype(int) + 1
    axes = [lo[i] + step * np.arange(shape[i]) for i in range(3)]
    mask = grid_inside(solid, (axes[0], axes[1], axes[2]))
    # coarse distances from the voxel mask; near the surface, the distance to the faces of the
    # nearest surface samples
    coarse = np.where(mask, -distance_transform_edt(mask), distance_transform_edt(~mask)) * step
    band = 3.0 * step
    near_band = np.abs(coarse) <= band + step
    grid = lo + step * np.argwhere(near_band).astype(np.float64)
    dense, dense_faces = sample_surface_faces(solid, _SURFACE_DENSE, rng)
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
    return Sdf(lo, step, values)


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
    return pts
