"""Exact distance from points to a triangle mesh's surface, vectorized in bounded blocks.

For each point, the distance to its nearest vertex is an upper bound on its distance to the
surface; only triangles whose bounding box lies within that bound can hold the closest point.
Those candidates get the exact point-triangle distance (the closest point found by the Voronoi
regions of the triangle: a vertex, an edge or the face), and the smallest wins. Memory is
bounded by :data:`PAIR_BLOCK` point-triangle pairs at a time.

The candidates are found without testing every point against every triangle (a humanoid's
links of tens of thousands of triangles spent 15 s there): the triangles whose bounding box is
small are looked up in a k-d tree of their box centres, within the point's bound plus the
largest of their half-diagonals (every box within the bound has its centre that close); the
few large ones are tested against every point. Both keep exactly the triangles whose box lies
within the bound, so the distances are those of testing every pair.
"""

from __future__ import annotations

import itertools
from collections.abc import Iterator
from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt

from ..util.arrays import BoolArray, FloatArray, IntArray

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
    best: FloatArray = np.asarray(upper, dtype=np.float64).copy()
    lo, hi = tri.min(1), tri.max(1)
    half = 0.5 * np.linalg.norm(hi - lo, axis=1)
    large = _large_triangles(half)
    pairs = []
    for group in _size_groups(half, ~large):
        pi, fi = _candidates_by_tree(pts, best, lo[group], hi[group], half[group])
        pairs.append((pi, group[fi]))
    pairs += list(_candidates_dense(pts, best, lo[large], hi[large], np.flatnonzero(large)))
    for pi, fi in pairs:
        for s0 in range(0, len(pi), PAIR_BLOCK):
            sl = slice(s0, s0 + PAIR_BLOCK)
            d = _point_triangle_distance(pts[pi[sl]], tri[fi[sl]])
            np.minimum.at(best, pi[sl], d)
    return best


#: Meshes with at most this many triangles test every point against every triangle.
_DENSE_TRIANGLES = 512
#: Box centres each point asks the k-d tree for at once (a point with more within its radius
#: asks again for all of them).
_NEAREST = 32
#: The share of triangles (the smallest boxes) looked up in the k-d tree; the rest (CAD
#: meshes hold a few long thin triangles) are tested against every point.
_SMALL_SHARE = 0.98
#: At most this many triangles are tested against every point.
_DENSE_MAX = 2048


def _large_triangles(half: FloatArray) -> BoolArray:
    """Which triangles (by their boxes' half-diagonals ``half``) are tested against every
    point: all of a small mesh; else the largest 2 %, at most :data:`_DENSE_MAX` of them, so
    that a mesh of millions of like triangles does not test each point against tens of
    thousands (which triangles go where changes the time, never the distances)."""
    if len(half) <= _DENSE_TRIANGLES:
        return np.ones(len(half), dtype=bool)
    cut = float(np.quantile(half, _SMALL_SHARE))
    if len(half) * (1.0 - _SMALL_SHARE) > _DENSE_MAX:
        cut = max(cut, float(np.partition(half, len(half) - _DENSE_MAX)[len(half) - _DENSE_MAX]))
    large: BoolArray = half > cut
    return large


def _size_groups(half: FloatArray, small: BoolArray) -> list[IntArray]:
    """The ``small`` triangles (indices) in groups of like size, each looked up in a k-d tree
    of its own: a tree's search radius grows by its largest half-diagonal, so one tree for
    the slivers and the specks of a CAD mesh would hand each point thousands of candidates.
    Groups split at the quartiles of ``half`` among the small ones (one group for a mesh of
    at most :data:`_DENSE_TRIANGLES`)."""
    index = np.flatnonzero(small)
    if len(index) <= _DENSE_TRIANGLES:
        return [index]
    cuts = np.quantile(half[index], [0.25, 0.5, 0.75])
    group = np.searchsorted(cuts, half[index], side="left")
    return [index[group == g] for g in range(len(cuts) + 1) if np.any(group == g)]


def _within(p: FloatArray, lo: FloatArray, hi: FloatArray, bound: FloatArray) -> BoolArray:
    """Whether the box ``[lo, hi]`` of each pair lies within ``bound`` of its point ``p``."""
    box = np.maximum(np.maximum(lo - p, p - hi), 0.0)
    out: BoolArray = np.einsum("nk,nk->n", box, box) <= bound**2
    return out


def _candidates_by_tree(
    pts: FloatArray, best: FloatArray, lo: FloatArray, hi: FloatArray, half: FloatArray
) -> tuple[IntArray, IntArray]:
    """(point, triangle) pairs whose triangle box lies within the point's bound ``best``,
    found through a k-d tree of the box centres (indices into ``lo``/``hi``)."""
    from scipy.spatial import cKDTree

    if len(lo) == 0:
        empty = np.zeros(0, dtype=np.int64)
        return empty, empty
    radius = best + float(half.max()) * (1.0 + 1e-9) + 1e-12
    tree = cKDTree(0.5 * (lo + hi))
    k = min(_NEAREST, len(lo))
    dist, idx = tree.query(pts, k=k)
    dist, idx = dist.reshape(len(pts), k), idx.reshape(len(pts), k)
    inside = dist <= radius[:, None]
    # a point whose k nearest are all within its radius may have more: those by a ball query
    more = np.flatnonzero(inside[:, -1]) if k < len(lo) else np.zeros(0, dtype=np.int64)
    inside[more] = False
    pi, col = np.nonzero(inside)
    fi = idx[pi, col]
    if len(more):
        near = tree.query_ball_point(pts[more], radius[more])
        counts = np.fromiter((len(x) for x in near), dtype=np.int64, count=len(near))
        total = int(counts.sum())
        pi = np.concatenate([pi, np.repeat(more, counts)])
        fi = np.concatenate([fi, np.fromiter(itertools.chain.from_iterable(near), np.int64, total)])
    keep = _within(pts[pi], lo[fi], hi[fi], best[pi])
    return pi[keep], fi[keep]


def _candidates_dense(
    pts: FloatArray, best: FloatArray, lo: FloatArray, hi: FloatArray, index: IntArray
) -> Iterator[tuple[IntArray, IntArray]]:
    """(point, triangle) pairs whose triangle box (``index[i]`` for box ``i``) lies within the
    point's bound, every point against every box, in blocks of :data:`PAIR_BLOCK` pairs."""
    if len(lo) == 0:
        return
    step = max(1, PAIR_BLOCK // len(lo))
    for start in range(0, len(pts), step):
        p = pts[start : start + step]
        box = np.maximum(np.maximum(lo[None] - p[:, None], p[:, None] - hi[None]), 0.0)
        box2 = np.einsum("pfk,pfk->pf", box, box)
        pi, fi = np.nonzero(box2 <= best[start : start + step, None] ** 2)
        yield pi + start, index[fi]


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
