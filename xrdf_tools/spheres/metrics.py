"""How well a set of spheres represents a solid: the one place coverage is computed.

All metrics are Monte Carlo estimates from a seeded generator, so they are reproducible:

* **coverage** -- share of points sampled uniformly inside the solid that lie inside at least
  one sphere (the covered share of the solid's volume).
* **surface coverage** -- share of points sampled uniformly (by area) on the solid's surface that
  lie inside at least one sphere.
* **protrusion** -- points are sampled uniformly by area on the *boundary of the union of the
  spheres* (points of a sphere's surface that lie inside another sphere are not on that boundary
  and are dropped). A point's protrusion is its distance to the solid's surface when it lies
  outside the solid, and 0 when inside. ``protrusion_mean`` / ``protrusion_p95`` /
  ``protrusion_max`` are the area-weighted mean, 95th percentile and maximum, in metres.
  Example: one sphere of radius 0.6 at the centre of a unit cube has half of its surface
  outside in six caps, with protrusion uniform on [0, 0.1] there: mean 0.025, p95 0.09, max 0.1.
* **protrusion share** -- share of the *volume of the union of the spheres* that lies outside
  the solid (points sampled uniformly in the union: each sphere gets points in proportion to
  its volume, and a point is kept only by the first sphere that contains it).
* **surface gap** -- for each point sampled on the solid's surface, its distance to the union
  of the spheres, ``max(0, min_k |p - c_k| - r_k)`` (0 when covered). ``surface_gap_mean`` and
  ``surface_gap_p95`` are its mean and 95th percentile; ``max_uncovered_gap`` its maximum (the
  one-sided Hausdorff distance from the surface to the spheres). Without spheres every gap is
  the diagonal of the solid's bounding box.
* **volume ratio** -- volume of the union of the spheres over the volume of the solid.

The solid must enclose a volume; an open mesh is measured as its convex hull
(``SphereMetrics.solid == "convex_hull"``).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import asdict, dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

from ..util.arrays import FloatArray
from ..xrdf.model import Sphere
from .inside import points_inside

if TYPE_CHECKING:
    import trimesh


DEFAULT_SAMPLES = 20_000


@dataclass(frozen=True)
class SphereMetrics:
    """Metrics of one set of spheres against one solid (see the module docstring)."""

    sphere_count: int
    coverage: float
    surface_coverage: float
    protrusion_mean: float
    protrusion_p95: float
    protrusion_max: float
    volume: float
    area: float = 0.0
    solid: str = "mesh"
    protrusion_share: float = 0.0
    surface_gap_mean: float = 0.0
    surface_gap_p95: float = 0.0
    max_uncovered_gap: float = 0.0
    volume_ratio: float = 0.0
    fit_seconds: float | None = None
    #: The thickness of a solid that is a sheet (:mod:`.sheet`), else None. For a sheet the
    #: protrusion share and volume ratio measure how thin it is, not how well it is fitted
    #: (any sphere over it is nearly all outside it): judge it by coverage, surface coverage
    #: and gaps, and by its protrusion, which is the price of covering it.
    sheet_thickness: float | None = None

    def to_dict(self) -> dict[str, Any]:
        """Every field; ``fit_seconds`` only when set (a wall time, asked for),
        ``sheet_thickness`` only for a sheet."""
        out = asdict(self)
        for optional in ("fit_seconds", "sheet_thickness"):
            if out[optional] is None:
                del out[optional]
        return out


def sphere_arrays(spheres: Sequence[Sphere]) -> tuple[FloatArray, FloatArray]:
    """``(centers (K, 3), radii (K,))`` of a sphere list."""
    if not spheres:
        return np.zeros((0, 3)), np.zeros(0)
    c = np.array([s.center for s in spheres], dtype=np.float64).reshape(-1, 3)
    r = np.array([s.radius for s in spheres], dtype=np.float64)
    return c, r


def as_solid(mesh: trimesh.Trimesh) -> tuple[trimesh.Trimesh, str]:
    """The mesh if it encloses a volume, else its convex hull."""
    from .mesh_solids import is_volume

    if is_volume(mesh):
        return mesh, "mesh"
    return mesh.convex_hull, "convex_hull"


def contains(solid: trimesh.Trimesh, points: FloatArray) -> npt.NDArray[np.bool_]:
    """Inside test for a closed mesh: exact ray parity, the same answer on every run
    (:mod:`.inside`; a ray library's answer changed run to run on points that graze an edge)."""
    return points_inside(solid, points)


#: A solid filling less than this share of its bounding box draws its volume samples in the
#: cells of an octree around it (a coiled cable fills 0.01 % of its box) ...
SPARSE_FILL = 0.02
#: ... refined until the cells are this full, or hold this many cells.
_CELL_FILL = 0.1
_MAX_CELLS = 1 << 17


def sample_volume(solid: trimesh.Trimesh, n: int, rng: np.random.Generator) -> FloatArray:
    """``n`` points uniformly inside ``solid``: rejection sampling in its bounding box, or,
    where the solid fills little of it, in the cells of its octree (:func:`occupied_cells`),
    which hold all of it."""
    lo, hi = (np.asarray(b, dtype=np.float64) for b in solid.bounds)
    size = np.maximum(hi - lo, 1e-12)
    volume = float(solid.volume)
    corners = lo[None]
    if volume / float(np.prod(size)) < SPARSE_FILL:
        corners, size = occupied_cells(solid, lo, size, volume)
    fill = max(volume / (len(corners) * float(np.prod(size))), 1e-3)
    chunks: list[FloatArray] = []
    got = 0
    for _ in range(64):
        need = n - got
        if need <= 0:
            break
        batch = int(min(max(need / fill * 1.2 + 64, 256), 400_000))
        if len(corners) == 1:
            p = rng.uniform(lo, lo + size, size=(batch, 3))
        else:
            p = (
                corners[rng.integers(len(corners), size=batch)]
                + rng.uniform(0.0, 1.0, size=(batch, 3)) * size
            )
        p = p[contains(solid, p)]
        chunks.append(p)
        got += len(p)
    pts = np.concatenate(chunks) if chunks else np.zeros((0, 3))
    return pts[:n]


def occupied_cells(
    solid: trimesh.Trimesh, lo: FloatArray, size: FloatArray, volume: float
) -> tuple[FloatArray, FloatArray]:
    """The lower corners ``(M, 3)`` and the size ``(3,)`` of the cells of an octree over the
    box ``[lo, lo + size]`` that may hold part of ``solid``: each level splits the cells in
    eight and keeps a cell whose centre is inside or within half the cell's diagonal of the
    surface (any inside point of a cell whose centre is outside is that close: the segment
    between them crosses the surface), until the cells are :data:`_CELL_FILL` full."""
    from .distance import surface_distance

    corners = lo[None]
    octants = np.array([[i, j, k] for i in (0, 1) for j in (0, 1) for k in (0, 1)], float)
    while volume / (len(corners) * float(np.prod(size))) < _CELL_FILL:
        if len(corners) * 8 > _MAX_CELLS:
            break
        size = size / 2.0
        corners = (corners[:, None] + octants[None] * size).reshape(-1, 3)
        centres = corners + size / 2.0
        keep = contains(solid, centres)
        out = np.flatnonzero(~keep)
        reach = 0.5 * float(np.linalg.norm(size)) * (1.0 + 1e-9)
        keep[out] = surface_distance(solid, centres[out]) <= reach
        corners = corners[keep]
    return corners, size


def sample_surface(solid: trimesh.Trimesh, n: int, rng: np.random.Generator) -> FloatArray:
    """``n`` points uniformly (by area) on the surface of ``solid``."""
    return sample_surface_faces(solid, n, rng)[0]


def sample_surface_faces(
    solid: trimesh.Trimesh, n: int, rng: np.random.Generator
) -> tuple[FloatArray, npt.NDArray[np.int64]]:
    """:func:`sample_surface` and the face each point lies on."""
    import trimesh

    seed = int(rng.integers(0, 2**31 - 1))
    pts, faces = trimesh.sample.sample_surface(solid, n, seed=seed)
    return np.asarray(pts, dtype=np.float64), np.asarray(faces, dtype=np.int64)


def fibonacci_directions(n: int) -> FloatArray:
    """``n`` near-uniform unit vectors (Fibonacci sphere), deterministic."""
    i = np.arange(n, dtype=np.float64) + 0.5
    z = 1.0 - 2.0 * i / n
    rho = np.sqrt(np.maximum(0.0, 1.0 - z * z))
    phi = np.pi * (3.0 - np.sqrt(5.0)) * i
    return np.stack([rho * np.cos(phi), rho * np.sin(phi), z], axis=1)


def inside_any(
    points: FloatArray, centers: FloatArray, radii: FloatArray, chunk: int = 8192
) -> npt.NDArray[np.bool_]:
    """Whether each point lies inside at least one sphere (closed balls)."""
    out = np.zeros(len(points), dtype=bool)
    if len(radii) == 0:
        return out
    for s in range(0, len(points), chunk):
        p = points[s : s + chunk]
        d2 = ((p[:, None, :] - centers[None, :, :]) ** 2).sum(-1)
        out[s : s + chunk] = (d2 <= (radii[None, :] ** 2) * (1 + 1e-12)).any(1)
    return out


def union_boundary_samples(
    centers: FloatArray, radii: FloatArray, n: int, rng: np.random.Generator
) -> tuple[FloatArray, FloatArray]:
    """Points on the boundary of the union of spheres and their area weights.

    Each sphere gets a share of ``n`` proportional to its area (at least 8 points); points inside
    another sphere are dropped. Weights make the sample area-uniform over the union boundary.
    """
    if len(radii) == 0:
        return np.zeros((0, 3)), np.zeros(0)
    area = 4.0 * np.pi * radii**2
    counts = np.maximum(8, np.round(n * area / area.sum()).astype(int))
    pts_list: list[FloatArray] = []
    w_list: list[FloatArray] = []
    for k, (c, r, m) in enumerate(zip(centers, radii, counts, strict=True)):
        v = rng.normal(size=(int(m), 3))
        v /= np.linalg.norm(v, axis=1, keepdims=True)
        p = c + r * v
        others = np.delete(np.arange(len(radii)), k)
        if len(others):
            d = np.linalg.norm(p[:, None, :] - centers[None, others, :], axis=2)
            keep = ~(d < radii[None, others] * (1 - 1e-9)).any(1)
            p = p[keep]
        pts_list.append(p)
        w_list.append(np.full(len(p), area[k] / m))
    return np.concatenate(pts_list), np.concatenate(w_list)


def outside_distance(solid: trimesh.Trimesh, points: FloatArray) -> FloatArray:
    """Distance to the surface for points outside ``solid``, 0 for points inside (exact:
    :func:`~xrdf_tools.spheres.distance.surface_distance`, memory bounded)."""
    from .distance import surface_distance

    out = np.zeros(len(points))
    if len(points) == 0:
        return out
    outside = np.flatnonzero(~contains(solid, points))
    if len(outside):
        out[outside] = surface_distance(solid, points[outside])
    return out


def weighted_quantile(values: FloatArray, weights: FloatArray, q: float) -> float:
    """Quantile ``q`` in [0, 1] of weighted samples (inverse of the weighted CDF)."""
    if len(values) == 0:
        return 0.0
    order = np.argsort(values, kind="stable")
    v, w = values[order], weights[order]
    cdf = np.cumsum(w) / w.sum()
    idx = int(np.searchsorted(cdf, q, side="left"))
    return float(v[min(idx, len(v) - 1)])


def sphere_metrics(
    mesh: trimesh.Trimesh,
    spheres: Sequence[Sphere],
    *,
    samples: int = DEFAULT_SAMPLES,
    seed: int | Sequence[int] = 0,
) -> SphereMetrics:
    """Coverage, surface coverage and protrusion of ``spheres`` for ``mesh`` (same frame).

    ``samples`` points are drawn inside the solid, as many on its surface and about half as
    many on the union of the spheres; the same ``seed`` gives the same numbers. An open mesh
    is measured as its convex hull.
    """
    return measure(mesh, spheres, samples=samples, seed=seed)[0]


@dataclass(frozen=True)
class MetricSamples:
    """The samples behind one link's metrics, to pool several links (:func:`pooled`)."""

    protrusion: FloatArray
    protrusion_weight: FloatArray
    gap: FloatArray
    gap_weight: FloatArray
    union_volume: float
    outside_volume: float


def union_volume_samples(
    centers: FloatArray, radii: FloatArray, n: int, rng: np.random.Generator
) -> tuple[FloatArray, FloatArray]:
    """Points uniform in the union of spheres, and their volume weights (summing to the
    union's volume): each sphere gets points in proportion to its volume; a point is kept only
    by the first sphere that contains it."""
    if len(radii) == 0:
        return np.zeros((0, 3)), np.zeros(0)
    vol = 4.0 / 3.0 * np.pi * radii**3
    counts = np.maximum(16, np.round(n * vol / vol.sum()).astype(int))
    pts_list: list[FloatArray] = []
    w_list: list[FloatArray] = []
    for k, (c, r, m) in enumerate(zip(centers, radii, counts, strict=True)):
        v = rng.normal(size=(int(m), 3))
        v /= np.linalg.norm(v, axis=1, keepdims=True)
        p = c + r * v * np.cbrt(rng.uniform(size=(int(m), 1)))
        if k:
            p = p[~inside_any(p, centers[:k], radii[:k])]
        pts_list.append(p)
        w_list.append(np.full(len(p), vol[k] / m))
    return np.concatenate(pts_list), np.concatenate(w_list)


def gap_to_spheres(
    points: FloatArray, centers: FloatArray, radii: FloatArray, chunk: int = 8192
) -> FloatArray:
    """Distance of each point to the union of the spheres (0 inside it); inf without spheres."""
    out = np.full(len(points), np.inf)
    if len(radii) == 0:
        return out
    for s in range(0, len(points), chunk):
        p = points[s : s + chunk]
        d = np.sqrt(((p[:, None, :] - centers[None, :, :]) ** 2).sum(-1)) - radii[None, :]
        out[s : s + chunk] = np.maximum(d.min(1), 0.0)
    return out


def measure(
    mesh: trimesh.Trimesh,
    spheres: Sequence[Sphere],
    *,
    samples: int = DEFAULT_SAMPLES,
    seed: int | Sequence[int] = 0,
) -> tuple[SphereMetrics, MetricSamples]:
    """:func:`sphere_metrics` plus the samples behind it (to pool several links)."""
    solid, kind = as_solid(mesh)
    rng = np.random.default_rng(seed)
    centers, radii = sphere_arrays(spheres)
    vol_pts = sample_volume(solid, samples, rng)
    surf_pts = sample_surface(solid, samples, rng)
    coverage = float(inside_any(vol_pts, centers, radii).mean()) if len(vol_pts) else 0.0
    gap = gap_to_spheres(surf_pts, centers, radii)
    surface_cov = float((gap == 0.0).mean()) if len(surf_pts) else 0.0
    b_pts, b_w = union_boundary_samples(centers, radii, max(samples // 2, 64), rng)
    prot = outside_distance(solid, b_pts)
    u_pts, u_w = union_volume_samples(centers, radii, max(samples // 2, 64), rng)
    u_out = ~contains(solid, u_pts)
    volume, area = float(solid.volume), float(solid.area)
    pool = MetricSamples(
        prot,
        b_w,
        gap if len(radii) else np.full(len(surf_pts), float(solid.scale)),
        np.full(len(surf_pts), area / max(len(surf_pts), 1)),
        float(u_w.sum()),
        float(u_w[u_out].sum()),
    )
    return _metrics(len(spheres), coverage, surface_cov, volume, area, kind, pool), pool


def _metrics(
    count: int,
    coverage: float,
    surface_coverage: float,
    volume: float,
    area: float,
    kind: str,
    pool: MetricSamples,
) -> SphereMetrics:
    prot, w = pool.protrusion, pool.protrusion_weight
    gap, gw = pool.gap, pool.gap_weight
    return SphereMetrics(
        sphere_count=count,
        coverage=coverage,
        surface_coverage=surface_coverage,
        protrusion_mean=float((prot * w).sum() / w.sum()) if len(prot) else 0.0,
        protrusion_p95=weighted_quantile(prot, w, 0.95),
        protrusion_max=float(prot.max()) if len(prot) else 0.0,
        volume=volume,
        area=area,
        solid=kind,
        protrusion_share=pool.outside_volume / pool.union_volume if pool.union_volume else 0.0,
        surface_gap_mean=float((gap * gw).sum() / gw.sum()) if len(gap) else 0.0,
        surface_gap_p95=weighted_quantile(gap, gw, 0.95),
        max_uncovered_gap=float(gap.max()) if len(gap) else 0.0,
        volume_ratio=pool.union_volume / volume if volume else 0.0,
    )


def pooled(per: Sequence[SphereMetrics], pools: Sequence[MetricSamples]) -> SphereMetrics:
    """Metrics of several links together: coverage weighted by volume, surface coverage by
    area, distances over the pooled (area-weighted) samples, shares and ratios of the summed
    volumes."""
    vol = sum(m.volume for m in per)
    area = sum(m.area for m in per)
    kinds = {m.solid for m in per}

    def cat(name: str) -> FloatArray:
        arrays = [getattr(p, name) for p in pools]
        return np.concatenate(arrays) if arrays else np.zeros(0)

    pool = MetricSamples(
        cat("protrusion"),
        cat("protrusion_weight"),
        cat("gap"),
        cat("gap_weight"),
        sum(p.union_volume for p in pools),
        sum(p.outside_volume for p in pools),
    )
    return _metrics(
        sum(m.sphere_count for m in per),
        sum(m.coverage * m.volume for m in per) / vol if vol else 0.0,
        sum(m.surface_coverage * m.area for m in per) / area if area else 0.0,
        vol,
        area,
        kinds.pop() if len(kinds) == 1 else "mixed",
        pool,
    )
