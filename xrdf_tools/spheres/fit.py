"""Fit spheres to one closed solid: candidates, greedy cover, local refinement.

1. Sample points inside the solid (volume) and on its surface; these are what the spheres
   should cover (volume points weigh ``VOLUME_WEIGHT``, surface points the rest).
2. Build a signed distance grid of the solid (inside test per grid node, distance to a dense
   surface sample); trilinear interpolation gives the depth of any point and how far a point
   lies outside.
3. Candidate spheres: centres at interior sample points, each with the *largest* radius whose
   surface stays within ``max_protrusion`` of the solid (checked at 64 directions on the grid).
   A point deep inside (near the medial axis) gets a large sphere.
4. Greedy set cover: repeatedly take the candidate that covers the most still-uncovered
   weight.
5. Refinement: each sphere in turn is swapped for the best candidate given the others, then
   moved by a shrinking step in 26 directions (radius re-maximised each time) while that
   increases the covered weight.

Everything is driven by one seeded generator, and every decision compares exact numbers: the
inside test is exact (:mod:`.inside`), covered weight is a count of covered points of each kind
times that kind's weight (a BLAS product of 0/1 values is an exact integer whatever its
summation order or thread count), and distances are computed elementwise, not by a matrix
product. So the same solid, count and seed give the same spheres in every process.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt

from ..xrdf.model import Sphere
from .metrics import contains, fibonacci_directions, sample_surface, sample_volume

if TYPE_CHECKING:
    import trimesh

FloatArray = npt.NDArray[np.float64]
BoolArray = npt.NDArray[np.bool_]

VOLUME_WEIGHT = 0.75
DEFAULT_PROTRUSION_FRACTION = 0.06
_GRID_CELLS = 48
_DIRS = fibonacci_directions(64)
_MOVES = fibonacci_directions(26)


def default_max_protrusion(solid: trimesh.Trimesh) -> float:
    """The default protrusion budget: 6 % of the cube root of the solid's volume (metres)."""
    return float(DEFAULT_PROTRUSION_FRACTION * float(abs(solid.volume)) ** (1.0 / 3.0))


@dataclass
class _Sdf:
    """Signed distance on a regular grid (negative inside), trilinear lookup."""

    origin: FloatArray
    step: float
    values: FloatArray

    def __call__(self, points: FloatArray) -> FloatArray:
        from scipy.ndimage import map_coordinates

        idx = ((points - self.origin) / self.step).T
        return np.asarray(map_coordinates(self.values, idx, order=1, mode="nearest"))


def _build_sdf(solid: trimesh.Trimesh, margin: float, rng: np.random.Generator) -> _Sdf:
    from scipy.ndimage import distance_transform_edt
    from scipy.spatial import cKDTree

    lo = np.asarray(solid.bounds[0], dtype=np.float64) - margin
    hi = np.asarray(solid.bounds[1], dtype=np.float64) + margin
    step = float((hi - lo).max()) / _GRID_CELLS
    shape = np.ceil((hi - lo) / step).astype(int) + 1
    axes = [lo[i] + step * np.arange(shape[i]) for i in range(3)]
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    dense = np.concatenate(
        [sample_surface(solid, 30_000, rng), np.asarray(solid.vertices, dtype=np.float64)]
    )
    inside = contains(solid, grid)
    # coarse distances from the voxel mask, exact-ish ones near the surface from the samples
    mask = inside.reshape(*shape)
    coarse = (
        np.where(mask, -distance_transform_edt(mask), distance_transform_edt(~mask)).reshape(-1)
        * step
    )
    band = 3.0 * step
    near, _ = cKDTree(dense).query(grid, distance_upper_bound=band)
    fine = np.isfinite(near)
    values = coarse.copy()
    values[fine] = np.where(inside[fine], -near[fine], near[fine])
    values[~fine] = np.where(
        inside[~fine], np.minimum(coarse[~fine], -band), np.maximum(coarse[~fine], band)
    )
    return _Sdf(lo, step, values.reshape(*shape))


class SphereFitter:
    """Fits spheres to one watertight solid; reusable for several counts (greedy prefix)."""

    def __init__(
        self,
        solid: trimesh.Trimesh,
        *,
        seed: int | Sequence[int] = 0,
        max_protrusion: float | None = None,
        volume_samples: int = 3000,
        surface_samples: int = 1500,
        candidates: int = 1000,
    ) -> None:
        rng = np.random.default_rng(seed)
        self.solid = solid
        self.volume = float(abs(solid.volume))
        self.tau = float(max_protrusion if max_protrusion is not None else 0.0)
        if max_protrusion is None:
            self.tau = default_max_protrusion(solid)
        extent = float(np.max(solid.extents))
        margin = 2.0 * self.tau + extent / _GRID_CELLS * 3
        self.sdf = _build_sdf(solid, margin, rng)
        vol = sample_volume(solid, volume_samples, rng)
        surf = sample_surface(solid, surface_samples, rng)
        self.points = np.concatenate([vol, surf])
        self.n_volume = len(vol)
        self.w_volume = VOLUME_WEIGHT / max(len(vol), 1)
        self.w_surface = (1.0 - VOLUME_WEIGHT) / max(len(surf), 1)
        cand = sample_volume(solid, candidates, rng)
        if len(cand) == 0:
            cand = np.asarray(solid.vertices, dtype=np.float64).mean(0, keepdims=True)
        self.cand_c = cand
        self.cand_r = self.max_radius(cand)
        self.cand_cov = self._cover(self.cand_c, self.cand_r)
        self._cand_cov_f = self.cand_cov.astype(np.float64)
        self.scale = self.volume ** (1.0 / 3.0)

    # ----------------------------------------------------------------------------------------
    def max_radius(self, centers: FloatArray, iterations: int = 12) -> FloatArray:
        """Largest radius per centre whose sphere stays within the protrusion budget."""
        depth = np.maximum(-self.sdf(centers), 0.0)
        lo = 0.5 * depth
        hi = depth + 2.0 * self.tau + 2.0 * self.sdf.step
        for _ in range(iterations):
            mid = 0.5 * (lo + hi)
            pts = centers[:, None, :] + mid[:, None, None] * _DIRS[None, :, :]
            worst = self.sdf(pts.reshape(-1, 3)).reshape(len(centers), -1).max(1)
            ok = worst <= self.tau
            lo = np.where(ok, mid, lo)
            hi = np.where(ok, hi, mid)
        return lo

    def _cover(self, centers: FloatArray, radii: FloatArray) -> BoolArray:
        """``(K, P)``: which sample points each sphere covers (elementwise, no BLAS)."""
        d2 = np.zeros((len(centers), len(self.points)))
        for axis in range(3):
            diff = centers[:, axis, None] - self.points[None, :, axis]
            d2 += diff * diff
        return np.asarray(d2 <= radii[:, None] ** 2)

    def _gains(self, cover: FloatArray, free: BoolArray) -> FloatArray:
        """Free weight each row of ``cover`` (0/1 as float) covers: exact counts per kind of
        point times that kind's weight, so ties and comparisons are the same on every run."""
        nv = self.n_volume
        free_f = free.astype(np.float64)
        volume = cover[:, :nv] @ free_f[:nv]
        surface = cover[:, nv:] @ free_f[nv:]
        return np.asarray(volume * self.w_volume + surface * self.w_surface)

    # ----------------------------------------------------------------------------------------
    def greedy(self, k: int) -> tuple[list[int], list[float]]:
        """Indices of ``k`` greedy candidates and the covered share of the volume samples
        after each pick."""
        covered = np.zeros(len(self.points), dtype=bool)
        picks: list[int] = []
        curve: list[float] = []
        for _ in range(k):
            gain = self._gains(self._cand_cov_f, ~covered)
            if picks:
                gain[picks] = -1.0
            best = int(np.argmax(gain))
            picks.append(best)
            covered |= self.cand_cov[best]
            curve.append(float(covered[: self.n_volume].mean()) if self.n_volume else 1.0)
        return picks, curve

    def fit(self, k: int, rounds: int = 3) -> tuple[Sphere, ...]:
        """``k`` spheres: greedy picks, then swap and move refinement."""
        if k <= 0:
            return ()
        picks, _ = self.greedy(k)
        centers = self.cand_c[picks].copy()
        radii = self.cand_r[picks].copy()
        cov = self.cand_cov[picks].copy()
        for rnd in range(rounds):
            step = self.scale / (6.0 * 2.0**rnd)
            for i in range(k):
                free = (cov.sum(0) - cov[i]) == 0
                current = float(self._gains(cov[i][None, :].astype(np.float64), free)[0])
                # swap for the best candidate given the others
                gains = self._gains(self._cand_cov_f, free)
                j = int(np.argmax(gains))
                if gains[j] > current + 1e-9:
                    centers[i], radii[i], cov[i] = self.cand_c[j], self.cand_r[j], self.cand_cov[j]
                    current = float(gains[j])
                # move the centre, radius re-maximised
                for _ in range(4):
                    trial_c = centers[i][None, :] + step * _MOVES
                    trial_r = self.max_radius(trial_c)
                    trial_cov = self._cover(trial_c, trial_r)
                    tg = self._gains(trial_cov.astype(np.float64), free)
                    t = int(np.argmax(tg))
                    if tg[t] <= current + 1e-9:
                        break
                    centers[i], radii[i], cov[i] = trial_c[t], trial_r[t], trial_cov[t]
                    current = float(tg[t])
        return tuple(_rounded(c, r) for c, r in zip(centers, radii, strict=True))


def _rounded(c: FloatArray, r: float) -> Sphere:
    """Centre rounded to 0.1 mm, radius rounded up to 0.1 mm (never below 0.1 mm)."""
    center = (round(float(c[0]), 4), round(float(c[1]), 4), round(float(c[2]), 4))
    radius = max(float(np.ceil(float(r) * 1e4 - 1e-6) / 1e4), 1e-4)
    return Sphere(center=center, radius=radius)


def fit_solid(
    solid: trimesh.Trimesh, count: int, *, seed: int = 0, max_protrusion: float | None = None
) -> tuple[Sphere, ...]:
    """``count`` spheres for one watertight solid (see the module docstring)."""
    return SphereFitter(solid, seed=seed, max_protrusion=max_protrusion).fit(count)
