"""Exact distance from points to a triangle mesh's surface, vectorized in bounded blocks.

For each point, the distance to its nearest vertex is an upper bound on its distance to the
surface; only triangles whose bounding box lies within that bound can hold the closest point.
Those candidates get the exact point-triangle distance (the closest point found by the Voronoi
regions of the triangle: a vertex, an edge or the face), and the smallest wins. Memory is
bounded by :data:`PAIR_BLOCK` point-triangle pairs at a time.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt

from ..util.arrays import FloatArray

if TYPE_CHECKING:
    import trimesh

__all__ = ["near_face_distance", "surface_distance"]


#: Point-triangle pairs held at once (a bounding-box test each; about 60 bytes).
PAIR_BLOCK = 2_000_000


def surface_distance(mesh: trimesh.Trimesh, points: FloatArray) -> FloatArray:
    """``(N,)`` distances from ``points (N, 3)`` to the surface of ``mesh`` (unsigned)."""
    from scipy.spatial import cKDTree

    pts = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    vertices = np.asarray(mesh.vertices, dtype=np.float64)
    tri = vertices[np.asarray(mesh.faces, dtype=np.int64)]
    if len(pts) == 0 or len(tri) == 0:
        return np.full(len(pts), np.inf)
    upper, _ = cKDTree(vertices).query(pts)
    best = np.asarray(upper, dtype=np.float64).copy()
    lo, hi = tri.min(1), tri.max(1)
    step = max(1, PAIR_BLOCK // len(tri))
    for start in range(0, len(pts), step):
        p = pts[start : start + step]
        box = np.maximum(np.maximum(lo[None] - p[:, None], p[:, None] - hi[None]), 0.0)
        box2 = np.einsum("pfk,pfk->pf", box, box)
        pi, fi = np.nonzero(box2 <= best[start : start + step, None] ** 2)
        if len(pi) == 0:
            continue
        d = _point_triangle_distance(p[pi], tri[fi])
        block = best[start : start + step]
        np.minimum.at(block, pi, d)
    return best


def near_face_distance(
    mesh: trimesh.Trimesh,
    points: FloatArray,
    samples: FloatArray,
    sample_faces: npt.NDArray[np.int64],
    neighbours: int = 2,
) -> FloatArray:
    """Distances from ``points`` to the faces the ``neighbours`` nearest surface ``samples``
    lie on (``sample_faces``): exact when a point's closest face is among them, an upper
    bound on the distance to the surface otherwise, and far closer to it than the distance to
    the nearest sample. One point-triangle distance per point and neighbour."""
    from scipy.spatial import cKDTree

    pts = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    if len(pts) == 0 or len(samples) == 0:
        return np.full(len(pts), np.inf)
    n = min(neighbours, len(samples))
    _, idx = cKDTree(samples).query(pts, k=n)
    idx = np.asarray(idx, dtype=np.int64).reshape(len(pts), n)
    tri = np.asarray(mesh.vertices, dtype=np.float64)[np.asarray(mesh.faces, dtype=np.int64)]
    faces = sample_faces[idx]
    d = _point_triangle_distance(np.repeat(pts, n, axis=0), tri[faces.ravel()])
    return np.asarray(d.reshape(len(pts), n).min(axis=1))


def _dot(a: FloatArray, b: FloatArray) -> FloatArray:
    out: FloatArray = np.einsum("nk,nk->n", a, b)
    return out


def _point_triangle_distance(p: FloatArray, tri: FloatArray) -> FloatArray:
    """Distance from each ``p[k]`` to triangle ``tri[k]`` (Voronoi regions of the triangle)."""
    a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
    ab, ac = b - a, c - a
    ap, bp, cp = p - a, p - b, p - c
    d1, d2 = _dot(ab, ap), _dot(ac, ap)
    d3, d4 = _dot(ab, bp), _dot(ac, bp)
    d5, d6 = _dot(ab, cp), _dot(ac, cp)
    va = d3 * d6 - d5 * d4
    vb = d5 * d2 - d1 * d6
    vc = d1 * d4 - d3 * d2
    with np.errstate(divide="ignore", invalid="ignore"):
        v_ab = d1 / (d1 - d3)
        w_ac = d2 / (d2 - d6)
        w_bc = (d4 - d3) / ((d4 - d3) + (d5 - d6))
        total = va + vb + vc
        v_in, w_in = vb / total, vc / total
        inside = a + v_in[:, None] * ab + w_in[:, None] * ac  # NaN for a zero-area triangle
        # two vertices a rounding error apart make a weight infinite and an edge vector hold
        # zeros: inf * 0 is NaN here too, left to the last line
        choices = [
            a,
            b,
            a + v_ab[:, None] * ab,
            c,
            a + w_ac[:, None] * ac,
            b + w_bc[:, None] * (c - b),
        ]
    conditions = [
        (d1 <= 0) & (d2 <= 0),
        (d3 >= 0) & (d4 <= d3),
        (vc <= 0) & (d1 >= 0) & (d3 <= 0),
        (d6 >= 0) & (d5 <= d6),
        (vb <= 0) & (d2 >= 0) & (d6 <= 0),
        (va <= 0) & (d4 - d3 >= 0) & (d5 - d6 >= 0),
    ]
    closest = np.select([m[:, None] for m in conditions], choices, default=inside)
    dist: FloatArray = np.linalg.norm(p - closest, axis=1)
    # a degenerate triangle (zero area, or two vertices a rounding error apart) gives NaN
    # here: the nearest of its vertices is an upper bound, exact for two coinciding ones
    bad = ~np.isfinite(dist)
    if np.any(bad):
        corners = np.linalg.norm(p[bad, None] - tri[bad], axis=2).min(axis=1)
        dist[bad] = corners
    return dist
