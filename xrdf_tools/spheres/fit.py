"""Fit spheres to one closed solid: candidates, greedy cover, local refinement.

1. Sample points inside the solid (volume) and on its surface; these are what the spheres
   should cover (volume points weigh ``VOLUME_WEIGHT``, surface points the rest).
2. Build a signed distance grid of the solid (inside test per grid node, distance to a dense
   surface sample); trilinear interpolation gives the depth of any point and how far a point
   lies outside.
3. Candidate spheres: centres at interior sample points, each with the *largest* radius whose
   surface stays within ``max_protrusion`` of the solid: the distance from the centre to the
   level set ``sdf = max_protrusion`` (its points interpolated on the grid edges, in a k-d
   tree), and to each clip plane. A point deep inside (near the medial axis) gets a large
   sphere.
4. Greedy set cover: repeatedly take the candidate that covers the most still-uncovered
   weight.
5. Refinement: each sphere in turn is swapped for the best candidate given the others, then
   moved by a shrinking step in 26 directions (radius re-maximised each time) while that
   increases the covered weight.

A fitter can be re-bound to another bound (:meth:`SphereFitter.rebound`: same samples and
candidates, new level set and radii); :func:`bound_for_coverage` uses it to pick, for a given
count, the smallest bound at which the spheres cover a given share.

Everything is driven by one seeded generator, and every decision compares exact numbers: the
inside test is exact (:mod:`.inside`), covered weight is a count of covered points of each kind
times that kind's weight (a BLAS product of 0/1 values is an exact integer whatever its
summation order or thread count), and distances are computed elementwise, not by a matrix
product. So the same solid, count and seed give the same spheres in every process.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt

from ..util.arrays import BoolArray, FloatArray
from ..util.errors import XrdfToolsError
from ..xrdf.model import Sphere
from .metrics import fibonacci_directions, sample_surface, sample_volume
from .sdf_grid import GRID_CELLS, Sdf, build_sdf, level_points, needs_thin_grid, thin_sdf

if TYPE_CHECKING:
    import trimesh
    from scipy.spatial import cKDTree

IntArray = npt.NDArray[np.uint8]

VOLUME_WEIGHT = 0.9
DEFAULT_PROTRUSION_FRACTION = 0.06
MIN_DEFAULT_PROTRUSION = 0.002
_COVER_BLOCK = 32
_MOVES = fibonacci_directions(26)
#: Ratio of consecutive protrusion bounds tried by :func:`bound_for_coverage`.
BOUND_STEP = 1.1
#: The largest bound :func:`bound_for_coverage` tries, as a share of the solid's largest extent.
BOUND_CAP_FRACTION = 0.4
#: The smallest bound :func:`bound_for_coverage` tries: the default bound over this.
BOUND_FLOOR_DIVISOR = 2.0
_CHECK_RUNGS = 3
#: A widened distance grid reaches this many times the bound that needed it.
ROOM_FACTOR = 2.0
#: Every this many candidates take part in a quick probe of a bound.
PROBE_STRIDE = 4


#: A clip plane: unit normal ``n`` and offset ``d``; spheres keep ``n . c - r >= d``.
Plane = tuple[tuple[float, float, float], float]


def parse_clip(text: str) -> tuple[str, Plane]:
    """``LINK:nx,ny,nz,d`` as ``(link, ((nx, ny, nz) normalised, d scaled alike))``: the
    spheres of LINK keep ``n . centre - radius >= d`` (link frame, metres)."""
    link, sep, numbers = text.rpartition(":")
    parts = numbers.split(",")
    if not sep or not link or len(parts) != 4:
        raise XrdfToolsError(f"clip '{text}': expected LINK:nx,ny,nz,d (e.g. base_link:0,0,1,0)")
    try:
        values = [float(v) for v in parts]
    except ValueError:
        raise XrdfToolsError(f"clip '{text}': nx, ny, nz and d must be numbers") from None
    if not all(math.isfinite(v) for v in values):
        raise XrdfToolsError(f"clip '{text}': nx, ny, nz and d must be finite numbers")
    norm = math.sqrt(sum(v * v for v in values[:3]))
    if not 0.0 < norm < math.inf:  # the squares over- or underflowed (1e300, 1e-200)
        norm = math.hypot(*values[:3])
    if not 0.0 < norm < math.inf:
        raise XrdfToolsError(f"clip '{text}': the normal (nx, ny, nz) must be non-zero")
    nx, ny, nz = (v / norm for v in values[:3])
    return link, ((nx, ny, nz), values[3] / norm)


#: A link's fitting plan: the cache key of its fit, its protrusion bound, its clip planes and
#: its seed.
LinkPlan = tuple[tuple[object, ...], float | None, tuple[Plane, ...], list[int]]


def default_max_protrusion(solid: trimesh.Trimesh) -> float:
    """The default protrusion budget: 6 % of the cube root of the solid's volume, at least
    ``MIN_DEFAULT_PROTRUSION`` (metres): a finger or a thin rod would otherwise need many
    tiny spheres for little gain."""
    scaled = DEFAULT_PROTRUSION_FRACTION * float(abs(solid.volume)) ** (1.0 / 3.0)
    return float(max(scaled, MIN_DEFAULT_PROTRUSION))


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
        clips: Sequence[Plane] = (),
        room: float | None = None,
    ) -> None:
        """``room``: the distance grid reaches past this bound as well (by three cells), with
        the cells of the grid for the fitter's own bound, so that fits under bounds up to
        ``room`` need no other grid."""
        rng = np.random.default_rng(seed)
        self.clips = np.array([[*n, d] for n, d in clips], dtype=np.float64).reshape(-1, 4)
        self.solid = solid
        self.volume = float(abs(solid.volume))
        tau = default_max_protrusion(solid) if max_protrusion is None else float(max_protrusion)
        self.seed = seed
        self.room = 0.0
        if room is not None and room > tau:
            cell = (float(np.max(solid.extents)) + 2.0 * self._margin(tau)) / GRID_CELLS
            margin = max(self._margin(tau), room + 3.0 * cell)
            self.sdf = self._grid(tau, room, margin, cell, rng)
            self.room = float(room)
        else:
            self.widen(tau, rng)
        vol = self.kept(sample_volume(solid, volume_samples, rng))
        surf = self.kept(sample_surface(solid, surface_samples, rng))
        self.points = np.concatenate([vol, surf])
        self._xyz = (self.points[None, :, 0], self.points[None, :, 1], self.points[None, :, 2])
        self.n_volume = len(vol)
        self.w_volume = VOLUME_WEIGHT / max(len(vol), 1)
        self.w_surface = (1.0 - VOLUME_WEIGHT) / max(len(surf), 1)
        cand = self.kept(sample_volume(solid, candidates, rng))
        if len(cand) == 0:
            cand = self.kept(np.asarray(solid.vertices, dtype=np.float64).mean(0, keepdims=True))
        self.empty = len(cand) == 0 or len(self.points) == 0
        self.cand_c = cand
        self.scale = self.volume ** (1.0 / 3.0)
        self.rebound(tau)

    def _margin(self, room: float) -> float:
        """The grid's margin around the solid for a bound of ``room``."""
        return 2.0 * room + float(np.max(self.solid.extents)) / GRID_CELLS * 3

    def _grid(
        self,
        bound: float,
        room: float,
        margin: float,
        cell: float | None,
        rng: np.random.Generator,
    ) -> Sdf:
        """The distance grid for a bound of ``bound`` reaching past ``room``: ``margin``
        around the solid in cells of ``cell`` (None: :data:`GRID_CELLS` along its longest
        side), unless the part is thinner than such cells (:func:`.sdf_grid.needs_thin_grid`),
        whose grid follows its thickness (:func:`.sdf_grid.thin_sdf`)."""
        solid = self.solid
        across = float(np.max(solid.extents)) + 2.0 * margin
        coarse = across / GRID_CELLS if cell is None else cell
        if needs_thin_grid(solid, bound, coarse):
            return thin_sdf(solid, bound, room, rng)
        return build_sdf(solid, margin, rng, cell)

    def widen(self, room: float, rng: np.random.Generator | None = None) -> None:
        """Build the distance grid so that it reaches past a bound of ``room`` (its margin
        around the solid grows with it, and its cells with the margin). The grid is built from
        a generator seeded as the fitter's first, so the same room gives the same grid."""
        rng = rng or np.random.default_rng(self.seed)
        self.sdf = self._grid(room, room, self._margin(room), None, rng)
        #: the largest bound the distance grid reaches past (see :meth:`rebound`)
        self.room = float(room)

    def rebound(self, tau: float) -> None:
        """Make ``tau`` the protrusion bound: the level set it becomes, the candidates' radii
        and what they cover. The samples stay, and so does the distance grid unless ``tau``
        is beyond its :attr:`room` (then it is widened to ``tau``)."""
        from scipy.spatial import cKDTree

        if tau > self.room * (1.0 + 1e-12):
            self.widen(tau)
        self.tau = float(tau)
        self._level_tree = cKDTree(level_points(self.sdf, self.tau))
        self.cand_r = self.max_radius(self.cand_c)
        self.cand_cov = self.covers(self.cand_c, self.cand_r)
        self._cand_packed = self._pack(self.cand_cov)

    # ----------------------------------------------------------------------------------------
    def max_radius(self, centers: FloatArray) -> FloatArray:
        """Largest radius per centre whose sphere stays within the protrusion budget: the
        distance to the nearest point where the solid's distance field exceeds the budget
        (its level set, found on the grid; 0 for a centre already beyond it)."""
        return self._radius_within(centers, self._level_tree, self.tau)

    def _radius_within(self, centers: FloatArray, level_tree: cKDTree, tau: float) -> FloatArray:
        dist, _ = level_tree.query(centers)
        radius = np.asarray(dist, dtype=np.float64)
        for plane in self.clips:
            radius = np.minimum(radius, self._plane_distance(centers, plane))
        ok = self.sdf(centers) < tau
        return np.where(ok, np.maximum(radius, 0.0), 0.0)

    def greedy_share(self, tau: float, k: int) -> float:
        """A quick probe of bound ``tau`` (within :attr:`room`): the covered share of the
        volume samples after ``k`` greedy picks from every ``PROBE_STRIDE``-th candidate. The
        fitter's own bound, candidates and grid are unchanged."""
        from scipy.spatial import cKDTree

        centers = self.cand_c[::PROBE_STRIDE]
        radii = self._radius_within(centers, cKDTree(level_points(self.sdf, tau)), tau)
        cover = self.covers(centers, radii)
        curve = self._greedy(self._pack(cover), cover, k)[1]
        return curve[-1] if curve else 0.0

    @staticmethod
    def _plane_distance(points: FloatArray, plane: FloatArray) -> FloatArray:
        """Signed distance of ``points`` to ``plane`` (n, d): ``n . p - d``, positive on the
        kept side (elementwise, no BLAS)."""
        return np.asarray(
            points[:, 0] * plane[0] + points[:, 1] * plane[1] + points[:, 2] * plane[2] - plane[3]
        )

    def kept(self, points: FloatArray) -> FloatArray:
        """The points on the kept side of every clip plane."""
        keep: BoolArray = np.ones(len(points), dtype=bool)
        for plane in self.clips:
            keep &= self._plane_distance(points, plane) > 0.0
        return points[keep]

    def covered_share(self, spheres: Sequence[Sphere]) -> float:
        """Share of the fitter's volume samples inside ``spheres``."""
        if self.n_volume == 0 or not spheres:
            return 0.0
        c = np.array([s.center for s in spheres], dtype=np.float64)
        r = np.array([s.radius for s in spheres], dtype=np.float64)
        return float(self.covers(c, r)[:, : self.n_volume].any(0).mean())

    def covers(self, centers: FloatArray, radii: FloatArray) -> BoolArray:
        """``(K, P)``: which of the fitter's sample points (its :attr:`n_volume` volume
        samples, then its surface samples) each sphere covers (elementwise squared distances,
        no BLAS, in blocks of spheres that stay in cache)."""
        out = np.empty((len(centers), len(self.points)), dtype=bool)
        px, py, pz = self._xyz
        for s in range(0, len(centers), _COVER_BLOCK):
            c = centers[s : s + _COVER_BLOCK]
            d2 = (c[:, 0, None] - px) ** 2
            d2 += (c[:, 1, None] - py) ** 2
            d2 += (c[:, 2, None] - pz) ** 2
            out[s : s + _COVER_BLOCK] = d2 <= radii[s : s + _COVER_BLOCK, None] ** 2
        return out

    def _pack(self, cover: BoolArray) -> tuple[IntArray, IntArray]:
        """Rows of ``cover`` as bits, volume and surface points apart."""
        nv = self.n_volume
        return np.packbits(cover[:, :nv], axis=1), np.packbits(cover[:, nv:], axis=1)

    def _gains(self, packed: tuple[IntArray, IntArray], free: BoolArray) -> FloatArray:
        """Free weight each packed cover row covers: exact counts of covered free points per
        kind times that kind's weight, so ties and comparisons are the same on every run."""
        nv = self.n_volume
        fv, fs = np.packbits(free[:nv]), np.packbits(free[nv:])
        volume = np.bitwise_count(packed[0] & fv).sum(1, dtype=np.int64)
        surface = np.bitwise_count(packed[1] & fs).sum(1, dtype=np.int64)
        return np.asarray(volume * self.w_volume + surface * self.w_surface)

    # ----------------------------------------------------------------------------------------
    def greedy(self, k: int) -> tuple[list[int], list[float]]:
        """Indices of ``k`` greedy candidates and the covered share of the volume samples
        after each pick."""
        return self._greedy(self._cand_packed, self.cand_cov, k)

    def _greedy(
        self, packed: tuple[IntArray, IntArray], cover: BoolArray, k: int
    ) -> tuple[list[int], list[float]]:
        covered = np.zeros(len(self.points), dtype=bool)
        picks: list[int] = []
        curve: list[float] = []
        for _ in range(0 if self.empty else k):
            gain = self._gains(packed, ~covered)
            if picks:
                gain[picks] = -1.0
            best = int(np.argmax(gain))
            picks.append(best)
            covered |= cover[best]
            curve.append(float(covered[: self.n_volume].mean()) if self.n_volume else 1.0)
        return picks, curve

    def fit(self, k: int, rounds: int = 5) -> tuple[Sphere, ...]:
        """``k`` spheres: greedy picks, then swap and move refinement."""
        if k <= 0 or self.empty:
            return ()
        picks, _ = self.greedy(k)
        centers = self.cand_c[picks].copy()
        radii = self.cand_r[picks].copy()
        cov = self.cand_cov[picks].copy()
        for rnd in range(rounds):
            step = self.scale / (6.0 * 2.0**rnd)
            for i in range(k):
                free = (cov.sum(0) - cov[i]) == 0
                current = float(self._gains(self._pack(cov[i][None, :]), free)[0])
                # swap for the best candidate given the others
                gains = self._gains(self._cand_packed, free)
                j = int(np.argmax(gains))
                if gains[j] > current + 1e-9:
                    centers[i], radii[i], cov[i] = self.cand_c[j], self.cand_r[j], self.cand_cov[j]
                    current = float(gains[j])
                # move the centre, radius re-maximised
                for _ in range(4):
                    trial_c = centers[i][None, :] + step * _MOVES
                    trial_r = self.max_radius(trial_c)
                    trial_cov = self.covers(trial_c, trial_r)
                    tg = self._gains(self._pack(trial_cov), free)
                    t = int(np.argmax(tg))
                    if tg[t] <= current + 1e-9:
                        break
                    centers[i], radii[i], cov[i] = trial_c[t], trial_r[t], trial_cov[t]
                    current = float(tg[t])
        return self.as_spheres(centers, radii)

    def as_spheres(self, centers: FloatArray, radii: FloatArray) -> tuple[Sphere, ...]:
        """Centres [k, 3] and radii [k] as the spheres a fit writes: rounded, and kept inside
        the fitter's clip planes (:meth:`_rounded`)."""
        return tuple(self._rounded(c, float(r)) for c, r in zip(centers, radii, strict=True))

    def _rounded(self, c: FloatArray, r: float) -> Sphere:
        """:func:`_rounded`, then kept inside the clip planes (radius rounded down there)."""
        sphere = _rounded(c, r)
        if len(self.clips):
            centre = np.array([sphere.center], dtype=np.float64)
            room = min(float(self._plane_distance(centre, p)[0]) for p in self.clips)
            if sphere.radius > room:
                radius = max(float(np.floor(room * 1e4 + 1e-6) / 1e4), 1e-4)
                sphere = Sphere(center=sphere.center, radius=radius)
        return sphere


def bound_for_coverage(fitter: SphereFitter, k: int, target: float) -> tuple[Sphere, ...]:
    """``k`` spheres under the smallest protrusion bound at which they cover ``target`` of
    the fitter's volume samples (or under the highest bound tried); the fitter is left
    re-bound to it.

    The bounds tried are the rungs ``tau0 * BOUND_STEP**j`` around the fitter's own bound
    ``tau0``, from ``tau0 / BOUND_FLOOR_DIVISOR`` up to ``BOUND_CAP_FRACTION`` of the solid's
    largest extent (the distance grid is widened when a rung lies past its room). A rung is
    judged by a quick greedy probe (:meth:`SphereFitter.greedy_share`) plus what refinement
    added to that probe at ``tau0`` (a probe costs a fraction of a refined fit, and grows
    with the bound): the lowest rung judged to reach the target is found by a bisection
    (below ``tau0`` when the refined fit there reaches the target, else above it, trying rungs
    1, 2, 4, ... first). The refined fit at that rung is kept if it reaches the target; else the
    rungs above it are fitted in turn (at most ``_CHECK_RUNGS``) until one does."""
    spheres = fitter.fit(k)
    if fitter.empty:
        return spheres
    tau0 = fitter.tau
    share = fitter.covered_share(spheres)
    gain = share - fitter.greedy_share(tau0, k)
    cap = max(tau0, BOUND_CAP_FRACTION * float(np.max(fitter.solid.extents)))
    top = int(np.floor(np.log(cap / tau0) / np.log(BOUND_STEP) + 1e-9))
    bottom = -int(np.floor(np.log(BOUND_FLOOR_DIVISOR) / np.log(BOUND_STEP) + 1e-9))

    def bound(j: int) -> float:
        tau = min(tau0 * BOUND_STEP**j, cap)
        if tau > fitter.room * (1.0 + 1e-12):
            fitter.widen(min(cap, ROOM_FACTOR * tau))
        return tau

    def rebound(j: int) -> None:
        fitter.rebound(bound(j))

    def judged(j: int) -> bool:
        return fitter.greedy_share(bound(j), k) + gain >= target

    if share >= target:
        lo, hi = bottom - 1, 0  # rung lo is judged short (assumed), rung 0 reaches
    else:
        lo, hi = 0, min(1, top)
        while hi < top and not judged(hi):
            lo, hi = hi, min(2 * hi, top)
    while hi - lo > 1:
        mid = (lo + hi) // 2
        lo, hi = (lo, mid) if judged(mid) else (mid, hi)
    fits: dict[int, tuple[tuple[Sphere, ...], float]] = {0: (spheres, share)}
    chosen = None
    for j in range(hi, min(hi + _CHECK_RUNGS, top) + 1):
        if j not in fits:
            rebound(j)
            got = fitter.fit(k)
            fits[j] = (got, fitter.covered_share(got))
        if fits[j][1] >= target:
            chosen = j
            break
    if chosen is None:  # below tau0: tau0 itself reached the target; above: the highest fitted
        chosen = 0 if share >= target else max(fits)
    rebound(chosen)
    return fits[chosen][0]


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
