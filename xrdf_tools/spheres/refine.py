"""Refine fitted spheres by gradient steps on coverage and on the union's protrusion.

The greedy fit (:mod:`.fit`) keeps every sphere within a hard protrusion bound, so every sphere
reaches it and the 95th percentile of the protrusion of the union's boundary grows as fast as
the coverage. This stage trades the two the way the metrics measure them (:mod:`.metrics`),
by minimising the sum of two losses, both in metres and scaled with the part (so the balance
does not depend on the link's size):

* **coverage loss** -- the mean, over the fitter's volume samples, of a smoothed count of
  the samples left out: with ``g = min_k(|p - c_k| - r_k)`` a sample's gap to the union and
  ``l = (volume / k) ** (1/3)``, ``COUNT_WEIGHT * l * sigmoid(g / (SOFTNESS * l))`` plus
  ``GAP_WEIGHT * max(0, g)`` (the smoothed count has no pull on samples far out; the gap
  does). A covered share is the metric's coverage, so ``COUNT_WEIGHT * l`` is the price of
  the whole volume in protrusion: a part whose coverage costs much protrusion (a flat
  plate) stops at less coverage than a tube;
* **protrusion loss** -- the distance outside the solid of the points of the union's boundary
  whose protrusion lies in the band ``PROTRUSION_BAND`` of quantiles, each weighted by its
  share of the boundary's area (``REFINE_DIRECTIONS`` points on each sphere, those inside
  another sphere dropped). The band lies around the 95th percentile that the metrics report:
  points below it do not raise it, and the few above it (a big sphere's cap past a thin part)
  are free as long as they stay few.

The distance outside the solid is the fitter's signed distance grid (trilinear, its gradient
from the grid's central differences), continued beyond the grid by the distance to the grid's
box. Steps are Adam's, their size ``STEP_FRACTION`` of the cube root of the solid's volume
shrinking linearly to ``FINAL_STEP`` of that; clip planes are kept after each step.

:func:`refined_fit` starts from greedy fits under several bounds (``START_BOUNDS``: a
tight bound places many mid-sized spheres, a loose one fewer big ones; which is better depends
on the part) and from clusters of the volume samples (:func:`cluster_start`: spheres spread by
volume, which suits a flat or short part such as a hand), refines each for ``SCREEN_STEPS``
and carries on with the lowest loss. Last,
each sphere grows to cover the samples and mesh vertices nearest to it that lie outside it by
at most ``TOUCH_UP`` of its radius (slivers a grid cell cannot see: a ball gets its own
radius back).

Every operation is elementwise or a sequential sum (``bincount``), never a BLAS product, and
the samples are the fitter's: the same fitter and count give the same spheres in every process
and with any thread count.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..util.arrays import FloatArray
from ..xrdf.model import Sphere
from .metrics import fibonacci_directions

if TYPE_CHECKING:
    from .fit import SphereFitter

#: The coverage loss of a volume sample left out, as a share of the cube root of the volume per
#: sphere: what one unit of covered share is worth in protrusion (metres).
COUNT_WEIGHT = 0.058
#: Width of the step from covered to not covered, the same way a share of that cube root.
SOFTNESS = 0.03
#: Weight of the gap itself (metres per metre), which pulls spheres towards samples far out.
GAP_WEIGHT = 0.5
#: The quantiles of the union boundary's protrusion whose points the protrusion loss pulls in.
PROTRUSION_BAND = (0.92, 0.98)
REFINE_STEPS = 90
#: Volume samples of the fitter used by the coverage loss (the first this many).
REFINE_POINTS = 3000
#: Points on each sphere where its protrusion is evaluated.
REFINE_DIRECTIONS = 128
#: The bounds of the greedy fits refined, as multiples of the fitter's bound.
START_BOUNDS = (1.0, 2.0)
#: Steps each start is refined for before the best is kept.
SCREEN_STEPS = 20
#: Lloyd rounds of the clustered start (:func:`cluster_start`).
CLUSTER_ROUNDS = 20
#: The clustered start's radius: this quantile of its cluster's distances to its centre.
CLUSTER_SHARE = 0.9
#: Swap-and-move rounds of the first start's greedy fit (:meth:`~.fit.SphereFitter.fit`); the
#: other starts are plain greedy picks (a round there costs time and, after the steps, won or
#: lost no Panda link).
START_ROUNDS = 1
#: Adam's step, as a share of the cube root of the solid's volume.
STEP_FRACTION = 0.02
#: The last step's size, as a share of the first's.
FINAL_STEP = 0.1
#: How far (a share of its radius) a sphere grows at most to close a sliver.
TOUCH_UP = 0.01
_BETA1, _BETA2 = 0.9, 0.999
_MIN_RADIUS = 1e-4


class _Outside:
    """Signed distance of the fitter's grid and its gradient at any point (trilinear, from
    the grid and its central differences); beyond the grid, the value at the nearest grid
    point plus the distance to it. Points and gradients are in the solid's frame (a thin
    part's grid is turned: :class:`~.sdf_grid.Sdf`); :attr:`origin` and :attr:`hi` are the
    grid's corners in its own frame."""

    def __init__(self, fitter: SphereFitter) -> None:
        sdf = fitter.sdf
        self.sdf = sdf
        self.origin, self.step = sdf.origin, sdf.step
        grads = [np.gradient(sdf.values, sdf.step, axis=a) for a in range(3)]
        #: value and gradient per node, ``(nx * ny * nz, 4)`` in C order
        self.nodes = np.stack([sdf.values, *grads], axis=-1).reshape(-1, 4)
        _, ny, nz = sdf.values.shape
        self.strides = (ny * nz, nz, 1)
        self.cells = np.asarray(sdf.values.shape, dtype=np.float64) - 1.0
        self.hi = sdf.origin + sdf.step * self.cells

    def __call__(self, points: FloatArray) -> tuple[FloatArray, FloatArray]:
        points = self.sdf.to_grid(points)
        clamped = np.clip(points, self.origin, self.hi)
        offset = points - clamped
        beyond = np.sqrt(offset[:, 0] ** 2 + offset[:, 1] ** 2 + offset[:, 2] ** 2)
        frac = np.minimum((clamped - self.origin) / self.step, self.cells - 1e-9)
        base = np.floor(frac).astype(np.int64)
        t = frac - base
        sx, sy, sz = self.strides
        first = base[:, 0] * sx + base[:, 1] * sy + base[:, 2] * sz
        out = np.zeros((len(points), 4))
        for corner in range(8):
            dx, dy, dz = corner & 1, (corner >> 1) & 1, (corner >> 2) & 1
            w = (t[:, 0] if dx else 1.0 - t[:, 0]) * (t[:, 1] if dy else 1.0 - t[:, 1])
            w = w * (t[:, 2] if dz else 1.0 - t[:, 2])
            out += w[:, None] * self.nodes.take(first + (dx * sx + dy * sy + dz * sz), axis=0)
        value = out[:, 0] + beyond
        grad = out[:, 1:]
        far = beyond > 0.0
        grad[far] = offset[far] / beyond[far, None]
        return value, self.sdf.from_grid(grad)


@dataclass
class _Adam:
    """Adam's moments for one parameter array."""

    m: FloatArray
    v: FloatArray

    def step(self, grad: FloatArray, size: float, t: int) -> FloatArray:
        self.m = _BETA1 * self.m + (1.0 - _BETA1) * grad
        self.v = _BETA2 * self.v + (1.0 - _BETA2) * grad * grad
        rate = size * np.sqrt(1.0 - _BETA2**t) / (1.0 - _BETA1**t)
        return np.asarray(rate * self.m / (np.sqrt(self.v) + 1e-12))


@dataclass
class _Problem:
    """What the losses need: the volume samples (``(3, N)`` float32 rows and the same as
    ``(N, 3)`` doubles), the directions on each sphere, the distance field, the coverage
    loss, Adam's step, the clip planes and the number of steps."""

    points: FloatArray
    rows: FloatArray
    directions: FloatArray
    outside: _Outside
    coverage: _Coverage
    size: float
    clips: FloatArray
    steps: int

    def rate(self, t: int) -> float:
        """Adam's step at step ``t``: ``size`` shrinking linearly to ``FINAL_STEP`` of it."""
        done = min(max(t - 1, 0) / max(self.steps - 1, 1), 1.0)
        return self.size * (1.0 - (1.0 - FINAL_STEP) * done)


@dataclass
class _Run:
    """One start being refined: its spheres, Adam's moments, steps taken, and at its last
    step the loss and the share of the volume samples covered."""

    centers: FloatArray
    radii: FloatArray
    adam_c: _Adam
    adam_r: _Adam
    steps: int = 0
    loss: float = float("inf")
    share: float = 0.0

    @classmethod
    def start(cls, spheres: Sequence[Sphere]) -> _Run:
        centers = np.array([s.center for s in spheres], dtype=np.float64).reshape(-1, 3)
        radii = np.array([s.radius for s in spheres], dtype=np.float64)
        return cls.at(centers, radii)

    @classmethod
    def at(cls, centers: FloatArray, radii: FloatArray) -> _Run:
        zeros_c, zeros_r = np.zeros_like(centers), np.zeros_like(radii)
        return cls(centers, radii, _Adam(zeros_c, zeros_c.copy()), _Adam(zeros_r, zeros_r.copy()))

    def advance(self, problem: _Problem, steps: int) -> None:
        """``steps`` Adam steps."""
        for _ in range(steps):
            self.steps += 1
            cov_c, cov_r, cov, self.share = problem.coverage.gradient(
                problem.points, self.centers, self.radii, problem.rows
            )
            out_c, out_r, out = _protrusion_gradient(
                problem.outside, self.centers, self.radii, problem.directions
            )
            self.loss = cov + out
            grad_c, grad_r = cov_c + out_c, cov_r + out_r
            rate = problem.rate(self.steps)
            self.centers = self.centers - self.adam_c.step(grad_c, rate, self.steps)
            step_r = self.adam_r.step(grad_r, rate, self.steps)
            radii = np.maximum(self.radii - step_r, _MIN_RADIUS)
            self.radii = _keep_clipped(self.centers, radii, problem.clips)


@dataclass(frozen=True)
class _Coverage:
    """The coverage loss of each volume sample with gap ``g`` to the union (see the module
    docstring): ``count * sigmoid(g / softness) + gap * max(0, g)``, ``count`` and
    ``softness`` in metres."""

    count: float
    softness: float
    gap: float

    def gradient(
        self,
        points: FloatArray,
        centers: FloatArray,
        radii: FloatArray,
        rows: FloatArray | None = None,
    ) -> tuple[FloatArray, FloatArray, float, float]:
        """The mean loss's gradient in the centres and radii (each point pulls on its nearest
        sphere only), the mean loss and the share of the points covered. The nearest sphere is
        found in single precision (``points`` are ``(3, N)`` float32 rows), the rest in
        double (``rows``: the same points as ``(N, 3)`` doubles, made here if not given)."""
        k, n = len(radii), points.shape[1]
        c32, r32 = centers.astype(np.float32), radii.astype(np.float32)
        dist = np.sqrt(
            (points[0][None, :] - c32[:, 0, None]) ** 2
            + (points[1][None, :] - c32[:, 1, None]) ** 2
            + (points[2][None, :] - c32[:, 2, None]) ** 2
        )
        nearest = np.argmin(dist - r32[:, None], axis=0)
        cols = np.arange(n)
        near = dist[nearest, cols].astype(np.float64)
        gap = near - radii[nearest]
        soft = 1.0 / (1.0 + np.exp(-np.clip(gap / self.softness, -40.0, 40.0)))
        slope = self.count / self.softness * soft * (1.0 - soft) + self.gap * (gap > 0.0)
        pull = slope / max(n, 1)
        rows = points.T.astype(np.float64) if rows is None else rows
        unit = (rows - centers[nearest]) / np.maximum(near, 1e-12)[:, None]
        grad_c = np.stack(
            [-np.bincount(nearest, weights=pull * unit[:, a], minlength=k) for a in range(3)],
            axis=1,
        )
        grad_r = -np.bincount(nearest, weights=pull, minlength=k)
        loss = float((self.count * soft + self.gap * np.maximum(gap, 0.0)).mean()) if n else 0.0
        share = float((gap <= 0.0).mean()) if n else 1.0
        return grad_c.astype(np.float64), grad_r.astype(np.float64), loss, share


def _band(values: FloatArray, weights: FloatArray, band: tuple[float, float]) -> FloatArray:
    """Which values lie within the band of weighted quantiles (and protrude at all)."""
    order = np.argsort(values, kind="stable")
    cdf = np.cumsum(weights[order]) / max(float(weights.sum()), 1e-300)
    last = len(values) - 1
    lo = values[order][min(int(np.searchsorted(cdf, band[0])), last)]
    hi = values[order][min(int(np.searchsorted(cdf, band[1])), last)]
    return np.asarray((values > 0.0) & (values >= lo) & (values <= hi))


def _protrusion_gradient(
    outside: _Outside, centers: FloatArray, radii: FloatArray, directions: FloatArray
) -> tuple[FloatArray, FloatArray, float]:
    """Gradient of the area-weighted mean protrusion of the union boundary's points within
    ``PROTRUSION_BAND`` (the weights and the band are held fixed for the step), and that
    loss."""
    k, m = len(radii), len(directions)
    surface = centers[:, None, :] + radii[:, None, None] * directions[None, :, :]
    flat = surface.reshape(-1, 3)
    dist2 = (flat[:, 0, None] - centers[None, :, 0]) ** 2
    dist2 += (flat[:, 1, None] - centers[None, :, 1]) ** 2
    dist2 += (flat[:, 2, None] - centers[None, :, 2]) ** 2
    covered = (dist2 < (radii * (1.0 - 1e-9))[None, :] ** 2).reshape(k, m, k)
    covered[np.arange(k), :, np.arange(k)] = False
    weights = (~covered.any(axis=2)) * (radii[:, None] ** 2)
    value, grad = outside(flat)
    value, grad = value.reshape(k, m), grad.reshape(k, m, 3)
    total = max(float(weights.sum()), 1e-300)
    pull = weights * _band(value.ravel(), weights.ravel(), PROTRUSION_BAND).reshape(k, m) / total
    grad_c = (pull[..., None] * grad).sum(axis=1)
    radial = grad[..., 0] * directions[None, :, 0]
    radial += grad[..., 1] * directions[None, :, 1]
    radial += grad[..., 2] * directions[None, :, 2]
    grad_r = (pull * radial).sum(axis=1)
    return np.asarray(grad_c), np.asarray(grad_r), float((pull * value).sum())


def _keep_clipped(centers: FloatArray, radii: FloatArray, clips: FloatArray) -> FloatArray:
    """Centres moved onto the kept side of each clip plane (in place), radii shrunk to stay
    there."""
    for plane in clips:
        normal = plane[:3]
        room = centers[:, 0] * normal[0] + centers[:, 1] * normal[1] + centers[:, 2] * normal[2]
        room = room - plane[3]
        short = room < _MIN_RADIUS
        centers[short] += (_MIN_RADIUS - room[short])[:, None] * normal[None, :]
        radii = np.minimum(radii, np.maximum(room, _MIN_RADIUS))
    return radii


def _close_slivers(
    points: FloatArray, centers: FloatArray, radii: FloatArray, clips: FloatArray
) -> None:
    """Grow each sphere (in place) to cover the samples nearest to it that lie outside it by
    at most ``TOUCH_UP`` of its radius, within the clip planes."""
    dist = np.sqrt(
        (points[:, 0, None] - centers[None, :, 0]) ** 2
        + (points[:, 1, None] - centers[None, :, 1]) ** 2
        + (points[:, 2, None] - centers[None, :, 2]) ** 2
    )
    nearest = np.argmin(dist - radii[None, :], axis=1)
    near = dist[np.arange(len(points)), nearest]
    reach = (near > radii[nearest]) & (near <= radii[nearest] * (1.0 + TOUCH_UP))
    grown = radii.copy()
    np.maximum.at(grown, nearest[reach], near[reach])
    radii[:] = _keep_clipped(centers, grown, clips)


def _squared_distances(points: FloatArray, centers: FloatArray) -> FloatArray:
    """``(K, N)`` squared distances from each centre to each point (elementwise, no BLAS)."""
    d2 = (points[None, :, 0] - centers[:, 0, None]) ** 2
    d2 += (points[None, :, 1] - centers[:, 1, None]) ** 2
    d2 += (points[None, :, 2] - centers[:, 2, None]) ** 2
    return np.asarray(d2)


def cluster_start(points: FloatArray, k: int) -> tuple[FloatArray, FloatArray]:
    """``k`` spheres from clusters of ``points`` (the volume samples): centres seeded by
    farthest-point sampling from the sample nearest the points' mean, then ``CLUSTER_ROUNDS``
    Lloyd rounds (each point to its nearest centre, each centre to its points' mean); each
    radius covers ``CLUSTER_SHARE`` of its cluster. A start that needs no protrusion bound:
    a flat or short part gets spheres spread by its volume, not by where its largest spheres
    fit."""
    n = len(points)
    k = min(k, n)
    mean = points.sum(axis=0) / n
    first = int(np.argmin(_squared_distances(points, mean[None, :])[0]))
    picks = [first]
    nearest = _squared_distances(points, points[first][None, :])[0]
    for _ in range(k - 1):
        picks.append(int(np.argmax(nearest)))
        nearest = np.minimum(nearest, _squared_distances(points, points[picks[-1]][None, :])[0])
    centers = points[picks].copy()
    for _ in range(CLUSTER_ROUNDS):
        owner = np.argmin(_squared_distances(points, centers), axis=0)
        size = np.bincount(owner, minlength=k).astype(np.float64)
        sums = np.stack([np.bincount(owner, weights=points[:, a], minlength=k) for a in range(3)])
        held = size > 0
        centers[held] = (sums[:, held] / size[held]).T
    d2 = _squared_distances(points, centers)
    owner = np.argmin(d2, axis=0)
    reach = np.sqrt(d2[owner, np.arange(n)])
    radii = np.array(
        [
            float(np.quantile(reach[owner == j], CLUSTER_SHARE)) if (owner == j).any() else 0.0
            for j in range(k)
        ]
    )
    return centers, np.maximum(radii, _MIN_RADIUS)


def refined_fit(
    fitter: SphereFitter,
    k: int,
    *,
    starts: Sequence[float] | None = None,
    steps: int | None = None,
    clustered: bool = True,
) -> tuple[Sphere, ...]:
    """``k`` spheres: a greedy fit under each bound of ``starts`` (multiples of the fitter's
    bound; default ``START_BOUNDS``) and, if ``clustered``, :func:`cluster_start` of the
    fitter's volume samples, each refined for ``SCREEN_STEPS`` steps on the losses of the
    module docstring; the one with the lowest loss is refined to ``steps``
    (``REFINE_STEPS``) in all. Ties go to the earlier start. The distance field is the
    fitter's; the fitter is left re-bound to the last start's bound."""
    if k <= 0 or fitter.empty or fitter.n_volume == 0:
        return fitter.fit(k)
    starts = START_BOUNDS if starts is None else starts
    steps = REFINE_STEPS if steps is None else steps
    reach = (fitter.volume / k) ** (1.0 / 3.0)
    tau = fitter.tau
    used = fitter.points[: min(fitter.n_volume, REFINE_POINTS)]
    problem = _Problem(
        np.ascontiguousarray(used.T, dtype=np.float32),
        used.astype(np.float32).astype(np.float64),
        fibonacci_directions(REFINE_DIRECTIONS),
        _Outside(fitter),
        _Coverage(COUNT_WEIGHT * reach, SOFTNESS * reach, GAP_WEIGHT),
        STEP_FRACTION * fitter.scale,
        fitter.clips,
        steps,
    )
    runs: list[_Run] = []
    for factor in starts:
        if factor * tau != fitter.tau:
            fitter.rebound(factor * tau)
        runs.append(_Run.start(fitter.fit(k, rounds=START_ROUNDS if not runs else 0)))
    if clustered and fitter.n_volume >= k:
        centers, radii = cluster_start(fitter.points[: fitter.n_volume], k)
        runs.append(_Run.at(centers, _keep_clipped(centers, radii, fitter.clips)))
    for run in runs:
        run.advance(problem, min(SCREEN_STEPS, steps) if len(runs) > 1 else steps)
    best = min(range(len(runs)), key=lambda i: (runs[i].loss, i))
    chosen = runs[best]
    chosen.advance(problem, steps - chosen.steps)
    if TOUCH_UP > 0:
        targets = np.concatenate(
            [fitter.points, np.asarray(fitter.solid.vertices, dtype=np.float64)]
        )
        _close_slivers(targets, chosen.centers, chosen.radii, fitter.clips)
    return fitter.as_spheres(chosen.centers, chosen.radii)
