"""Exact distance from points to a triangle mesh's surface, vectorized in bounded blocks.

For each point, the distance to its nearest vertex is an upper bound on its distance to the
surface; only triangles whose bounding box lies within that bound can hold the closest point.
Those candidates get the exact point-triangle distance (the closest point found by the Voronoi
regions of the triangle: a vertex, an edge or the face), and the smallest wins, each one found
narrowing the bound for the candidates still to come.

The candidates come from a tree of boxes (:class:`~xrdf_tools.spheres.box_tree.BoxTree`)
walked for all points at once, never from testing every point against every triangle. A long
triangle is put in the tree by pieces (:func:`_pieces`): a CAD part's slivers (a disk
tessellated as a fan from one point) have boxes that span the part, so every point would be
within reach of all of them (a 4,000-triangle shaft with fan caps took 35 s for 20,000
points). Each triangle longer than a share of the mesh's size is covered by the boxes of a grid
of parallelograms along its shortest and longest edges, and the grid's corners, points on the
surface, tighten each point's first bound. A piece names its triangle, and the distance is
always computed to the whole triangle: pieces only choose which triangles are tried, and every
triangle within the bound is tried, so the result is that of testing every pair, bit for bit.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt

from ..util.arrays import BoolArray, FloatArray, IntArray, ragged_index
from .box_tree import BoxTree

if TYPE_CHECKING:
    import trimesh

__all__ = ["near_face_distance", "surface_distance"]


#: Point-triangle pairs whose exact distance is computed at once (about 400 bytes each).
PAIR_BLOCK = 1_000_000


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
    pieces = _pieces(tri)
    _try_nearest_pieces(pts, tri, pieces, best)
    bound = _padded(best, pieces.slack)
    tree = BoxTree(pieces.lo, pieces.hi)
    pieces = replace(pieces, lo=pieces.lo[:0], hi=pieces.hi[:0])  # the tree keeps them sorted
    for pi, box in tree.within(pts, bound):
        fi = pieces.owner[box]
        if pieces.cut:  # a triangle was cut: try each candidate triangle once
            key = np.unique(pi * len(tri) + fi)
            pi, fi = key // len(tri), key % len(tri)
        for s0 in range(0, len(pi), PAIR_BLOCK):
            sl = slice(s0, s0 + PAIR_BLOCK)
            d = _point_triangle_distance(pts[pi[sl]], tri[fi[sl]])
            np.minimum.at(best, pi[sl], d)
        # the walk reads ``bound`` as it goes: a closer triangle found prunes the rest
        bound[pi] = np.minimum(bound[pi], _padded(best[pi], pieces.slack))
    return best


#: Pieces whose triangles each point tries before the walk.
_SEEDS = 3


def _try_nearest_pieces(
    pts: FloatArray, tri: FloatArray, pieces: _Pieces, best: FloatArray
) -> None:
    """Narrow ``best`` by the distance to the triangles of the :data:`_SEEDS` pieces whose
    corners lie nearest each point: a bound close to the distance before the walk starts,
    so that the far side of a rod or a cylinder is never tried."""
    from scipy.spatial import cKDTree

    k = min(_SEEDS, len(pieces.seeds))
    _, nearest = cKDTree(pieces.seeds).query(pts, k=k)
    owner = pieces.seed_owner[np.asarray(nearest, dtype=np.int64).reshape(len(pts), k)]
    for column in owner.T:
        np.minimum(best, _point_triangle_distance(pts, tri[column]), out=best)


def _padded(distance: FloatArray, slack: float) -> FloatArray:
    """A bound a rounding error above ``distance`` (an upper bound on the true distance)."""
    out: FloatArray = distance * (1.0 + 1e-9) + slack
    return out


#: Meshes with at most this many triangles are never cut into pieces.
_FEW_TRIANGLES = 512
#: Triangles longer than this share of the mesh's box diagonal are looked up by pieces ...
_PIECE_SHARE = 1.0 / 64.0
#: ... unless that makes more than this many pieces: then the pieces are made longer ...
_PIECE_BUDGET = 1_000_000
#: ... and only those whose box's three face areas sum to more than this many times their own
#: area (a triangle along an axis or broad: at most about 3; a sliver across the axes: its
#: length over its width).
_BOX_WASTE = 8.0


@dataclass(frozen=True)
class _Pieces:
    """Boxes ``[lo, hi]`` that together cover every triangle and the triangle each belongs to
    (``owner``); points on the triangles (``seeds``) and the triangle of each
    (``seed_owner``); the padding that covers rounding in the boxes (``slack``); and whether
    any triangle was cut into several boxes (else a box is its triangle's)."""

    lo: FloatArray
    hi: FloatArray
    owner: IntArray
    seeds: FloatArray
    seed_owner: IntArray
    slack: float
    cut: bool


def _pieces(tri: FloatArray) -> _Pieces:
    """Each triangle of ``tri (F, 3, 3)`` as its own box with its centroid as seed; and each
    longer than :data:`_PIECE_SHARE` of the mesh (in a mesh past :data:`_FEW_TRIANGLES`)
    also as the cells of a grid of parallelograms spanned by its shortest and longest edge,
    each cell's first corner a seed: a sliver becomes a row of short cells, a large triangle
    a patchwork. The cells' boxes (clipped to the triangle's own) replace the triangle's box
    where it is far larger than the triangle (:data:`_BOX_WASTE`: a sliver across the axes,
    not one along an axis nor a broad triangle, whose boxes the tree prunes well)."""
    lo, hi = tri.min(1), tri.max(1)
    owner = np.arange(len(tri), dtype=np.int64)
    slack = 1e-9 * float(np.abs(tri).max()) + 1e-300
    long_, n1, n2 = _cut_counts(tri, lo, hi)
    if len(long_) == 0:
        return _Pieces(lo, hi, owner, tri.mean(1), owner, slack, False)
    corner, short_edge, long_edge = _edge_frame(tri[long_])
    cell_lo, cell_hi, cell_of, points = _cells(corner, short_edge, long_edge, n1, n2)
    of = long_[cell_of]
    boxed = _wasteful(tri[long_], lo[long_], hi[long_])
    cells = boxed[cell_of]
    kept = np.ones(len(tri), dtype=bool)
    kept[long_[boxed]] = False
    return _Pieces(
        np.concatenate([lo[kept], np.maximum(cell_lo[cells], lo[of[cells]]) - slack]),
        np.concatenate([hi[kept], np.minimum(cell_hi[cells], hi[of[cells]]) + slack]),
        np.concatenate([owner[kept], of[cells]]),
        np.concatenate([tri.mean(1), points]),
        np.concatenate([owner, of]),
        slack,
        bool(boxed.any()),
    )


def _wasteful(tri: FloatArray, lo: FloatArray, hi: FloatArray) -> BoolArray:
    """Which triangles' boxes have three face areas that sum to more than :data:`_BOX_WASTE`
    times the triangle's area."""
    extent = hi - lo
    box_area = (extent * np.roll(extent, 1, axis=1)).sum(1)
    area = 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
    out: BoolArray = box_area > _BOX_WASTE * area
    return out


def _cut_counts(
    tri: FloatArray, lo: FloatArray, hi: FloatArray
) -> tuple[IntArray, IntArray, IntArray]:
    """The triangles to cut and their cells along the shortest and the longest edge: those
    longer than :data:`_PIECE_SHARE` of the mesh's box diagonal, the share doubled while the
    cells would number past :data:`_PIECE_BUDGET`; none in a mesh of few triangles."""
    empty = np.zeros(0, dtype=np.int64)
    if len(tri) <= _FEW_TRIANGLES:
        return empty, empty, empty
    _, short, long_ = _edge_frame(tri)
    short_len, long_len = np.linalg.norm(short, axis=1), np.linalg.norm(long_, axis=1)
    length = float(np.linalg.norm(hi.max(0) - lo.min(0))) * _PIECE_SHARE
    while True:
        cut = np.flatnonzero(long_len > length)
        n1 = np.ceil(short_len[cut] / length).astype(np.int64)
        n2 = np.ceil(long_len[cut] / length).astype(np.int64)
        if int((n1 * n2).sum()) <= _PIECE_BUDGET:
            return cut, n1, n2
        length *= 2.0


def _edge_frame(tri: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Per triangle, the vertex its shortest and longest edges share, and those two edges as
    vectors from it (any two edges of a triangle share a vertex)."""
    edges = np.stack(
        [tri[:, 2] - tri[:, 1], tri[:, 0] - tri[:, 2], tri[:, 1] - tri[:, 0]], axis=1
    )  # edge k is opposite vertex k
    length = np.linalg.norm(edges, axis=2)
    longest = np.argmax(length, axis=1)
    shortest = np.argmin(length, axis=1)
    shortest = np.where(shortest == longest, (longest + 1) % 3, shortest)
    shared = 3 - longest - shortest
    rows = np.arange(len(tri))
    corner = tri[rows, shared]
    # the shortest edge joins the shared vertex and the one opposite the longest, and so on
    return corner, tri[rows, longest] - corner, tri[rows, shortest] - corner


def _cells(
    corner: FloatArray, u: FloatArray, v: FloatArray, n1: IntArray, n2: IntArray
) -> tuple[FloatArray, FloatArray, IntArray, FloatArray]:
    """The cells ``corner + [i, i+1]/n1 * u + [j, j+1]/n2 * v`` of each triangle ``(corner,
    corner + u, corner + v)`` whose first corner lies in it (``i/n1 + j/n2 < 1``, in integers):
    their boxes, the triangle of each (an index into the arguments) and their first corners.
    Every point of a triangle lies in one of its cells."""
    of, offset = ragged_index(n1 * n2)
    a, b = n1[of], n2[of]
    i, j = offset // b, offset % b
    keep = i * b + j * a < a * b
    of, i, j, a, b = of[keep], i[keep], j[keep], a[keep], b[keep]
    p, du, dv = corner[of], u[of], v[of]
    s0, s1 = (i / a)[:, None], ((i + 1) / a)[:, None]
    t0, t1 = (j / b)[:, None], ((j + 1) / b)[:, None]
    first = p + s0 * du + t0 * dv
    ends = np.stack([first, p + s1 * du + t0 * dv, p + s0 * du + t1 * dv, p + s1 * du + t1 * dv])
    return ends.min(0), ends.max(0), of, first


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
