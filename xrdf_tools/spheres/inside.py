"""Which points lie inside a closed triangle mesh: exact ray parity, the same bits everywhere.

A ray goes from each point in +z; the point is inside when the ray crosses the surface an odd
number of times. The crossing test runs in the xy projection with exact tie-breaking, so the
answer depends only on the input floats, never on thread count, hash seed or a ray library's
acceleration structure (embree's parallel BVH build gave a different answer run to run for
points whose ray grazes an edge):

* Each edge's orientation test is computed from its two vertices in index order, so the two
  triangles that share an edge see exactly opposite values.
* A value of exactly 0 (the ray through an edge or a vertex) is decided as if the point were
  moved by an infinitesimal (epsilon, epsilon^2) in xy ("simulation of simplicity"): every shared
  edge and vertex is then claimed by exactly one side, so parity is exact on a closed mesh.
* Triangles that project to a segment (vertical walls) are never crossed.

Candidate (point, triangle) pairs come from a uniform xy grid of buckets and are processed in
bounded blocks, so memory stays linear in the points and faces.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING

import numpy as np

from ..util.arrays import BoolArray, FloatArray
from ..util.arrays import Int64Array as IntArray

if TYPE_CHECKING:
    import trimesh

__all__ = ["grid_inside", "points_inside"]


#: Point-triangle candidate pairs tested per block (about 200 bytes each).
PAIR_BLOCK = 1_000_000


def points_inside(mesh: trimesh.Trimesh, points: FloatArray) -> BoolArray:
    """``(N,)`` booleans: which of ``points (N, 3)`` lie inside the closed ``mesh``."""
    pts = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    vertices = np.asarray(mesh.vertices, dtype=np.float64)
    faces = np.asarray(mesh.faces, dtype=np.int64)
    return _inside(vertices, faces, pts)


def grid_inside(
    mesh: trimesh.Trimesh, axes: tuple[FloatArray, FloatArray, FloatArray]
) -> BoolArray:
    """``(nx, ny, nz)`` booleans: which nodes of the grid ``axes`` lie inside the closed
    ``mesh``; the same answer as :func:`points_inside` on the nodes, with one ray per xy column
    (the crossings of a column are found once and counted above each node of it)."""
    xs, ys, zs = (np.asarray(a, dtype=np.float64) for a in axes)
    vertices = np.asarray(mesh.vertices, dtype=np.float64)
    faces = np.asarray(mesh.faces, dtype=np.int64)
    out = np.zeros((len(xs), len(ys), len(zs)), dtype=bool)
    if len(faces) == 0 or out.size == 0:
        return out
    gx, gy = np.meshgrid(xs, ys, indexing="ij")
    columns = np.stack([gx.ravel(), gy.ravel(), np.full(gx.size, -np.inf)], axis=1)
    table = _TriangleTable(vertices, faces)
    grid = _Buckets(columns, table.lo, table.hi)
    cols: list[IntArray] = []
    heights: list[FloatArray] = []
    for tri, pnt in grid.candidate_blocks():
        c, z = table.crossings(tri, pnt, columns)
        cols.append(c)
        heights.append(z)
    col = np.concatenate(cols) if cols else np.zeros(0, dtype=np.int64)
    z = np.concatenate(heights) if heights else np.zeros(0)
    order = np.lexsort((z, col))
    col, z = col[order], z[order]
    bounds = np.searchsorted(col, np.arange(len(columns) + 1))
    flat = out.reshape(len(columns), len(zs))
    for k in np.flatnonzero(np.diff(bounds)):
        zc = z[bounds[k] : bounds[k + 1]]
        above = len(zc) - np.searchsorted(zc, zs, side="right")  # crossings with z > node
        flat[k] = (above % 2).astype(bool)
    return out


def _inside(vertices: FloatArray, faces: IntArray, pts: FloatArray) -> BoolArray:
    crossings = np.zeros(len(pts), dtype=np.int64)
    if len(pts) == 0 or len(faces) == 0:
        return crossings.astype(bool)
    table = _TriangleTable(vertices, faces)
    grid = _Buckets(pts, table.lo, table.hi)
    for tri, pnt in grid.candidate_blocks():
        crossings += np.bincount(table.crossed_above(tri, pnt, pts), minlength=len(pts))
    return (crossings % 2).astype(bool)


def _orient(a: FloatArray, b: FloatArray, p: FloatArray) -> FloatArray:
    """Twice the signed xy area of (a, b, p): > 0 when p lies left of a -> b."""
    return (b[..., 0] - a[..., 0]) * (p[..., 1] - a[..., 1]) - (b[..., 1] - a[..., 1]) * (
        p[..., 0] - a[..., 0]
    )


class _TriangleTable:
    """Per triangle, what the crossing test needs, computed once.

    For each edge, in canonical (lower vertex index first) direction: its start point ``a``,
    direction ``d``, and the sign ``g`` (+-1) that turns its orientation value into "on the
    triangle's inner side when > 0"; ``tie`` says which side an exact 0 falls on (the
    point shifted by (eps, eps^2)).
    """

    def __init__(self, vertices: FloatArray, faces: IntArray) -> None:
        v = vertices[faces]
        orientation = np.sign(_orient(v[:, 0], v[:, 1], v[:, 2]))
        keep = orientation != 0.0  # a triangle seen edge-on is never crossed
        faces, v, orientation = faces[keep], v[keep], orientation[keep]
        self.vertices_z = v[:, :, 2]
        self.lo = v[:, :, :2].min(1)
        self.hi = v[:, :, :2].max(1)
        ax, ay, dx, dy, g, tie = [], [], [], [], [], []
        # edge k is opposite vertex k: its orientation value is vertex k's barycentric weight
        for i, j in ((1, 2), (2, 0), (0, 1)):
            fi, fj = faces[:, i], faces[:, j]
            first_is_i = fi < fj
            a = np.where(first_is_i[:, None], v[:, i, :2], v[:, j, :2])
            b = np.where(first_is_i[:, None], v[:, j, :2], v[:, i, :2])
            flip = np.where(first_is_i, 1.0, -1.0)
            ddx, ddy = b[:, 0] - a[:, 0], b[:, 1] - a[:, 1]
            shift = np.where(ddy != 0.0, -np.sign(ddy), np.sign(ddx))
            ax.append(a[:, 0])
            ay.append(a[:, 1])
            dx.append(ddx)
            dy.append(ddy)
            g.append(flip * orientation)
            tie.append(shift * flip * orientation > 0.0)
        self.ax, self.ay = np.stack(ax, 1), np.stack(ay, 1)
        self.dx, self.dy = np.stack(dx, 1), np.stack(dy, 1)
        self.g, self.tie = np.stack(g, 1), np.stack(tie, 1)

    def crossed_above(self, tri: IntArray, pnt: IntArray, pts: FloatArray) -> IntArray:
        """The points of the (triangle, point) pairs whose +z ray crosses the triangle."""
        pnt, z = self.crossings(tri, pnt, pts)
        crossed: IntArray = pnt[z > pts[pnt, 2]]
        return crossed

    def crossings(
        self, tri: IntArray, pnt: IntArray, pts: FloatArray
    ) -> tuple[IntArray, FloatArray]:
        """The (point, height) of each pair whose vertical line through the point crosses
        the triangle: the line's xy lies in the triangle's projection (exact tie rules)."""
        px, py = pts[pnt, 0], pts[pnt, 1]
        lo, hi = self.lo[tri], self.hi[tri]
        near = (px >= lo[:, 0]) & (px <= hi[:, 0]) & (py >= lo[:, 1]) & (py <= hi[:, 1])
        tri, pnt, px, py = tri[near], pnt[near], px[near], py[near]
        weights = []
        inside = np.ones(len(tri), dtype=bool)
        for k in range(3):
            value = self.dx[tri, k] * (py - self.ay[tri, k]) - self.dy[tri, k] * (
                px - self.ax[tri, k]
            )
            inner = value * self.g[tri, k]
            inside &= (inner > 0.0) | ((inner == 0.0) & self.tie[tri, k])
            weights.append(inner)
        tri, pnt = tri[inside], pnt[inside]
        w = np.stack([x[inside] for x in weights], 1)
        z = (w * self.vertices_z[tri]).sum(1) / w.sum(1)
        return pnt, z


class _Buckets:
    """Points sorted into a uniform xy grid; each triangle meets the buckets its xy box covers."""

    def __init__(self, pts: FloatArray, tri_lo: FloatArray, tri_hi: FloatArray) -> None:
        self.tri_lo, self.tri_hi = tri_lo, tri_hi
        lo = pts[:, :2].min(0)
        hi = pts[:, :2].max(0)
        if len(tri_lo):
            lo, hi = np.minimum(lo, tri_lo.min(0)), np.maximum(hi, tri_hi.max(0))
        span = np.maximum(hi - lo, 1e-12)
        cells = max(1, int(np.sqrt(max(len(pts), len(tri_lo)) / 4.0)))
        self.shape = np.minimum(np.maximum((span / span.max() * cells).astype(np.int64), 1), 4096)
        self.lo = lo
        self.size = span / self.shape
        cell = self._cell_of(pts[:, :2])
        key = cell[:, 0] * self.shape[1] + cell[:, 1]
        self.order = np.argsort(key, kind="stable")
        counts = np.bincount(key, minlength=int(self.shape[0] * self.shape[1]))
        self.start = np.concatenate([[0], np.cumsum(counts)])
        self.n_faces = len(tri_lo)

    def _cell_of(self, xy: FloatArray) -> IntArray:
        c = np.floor((xy - self.lo) / self.size).astype(np.int64)
        clipped: IntArray = np.clip(c, 0, self.shape - 1)
        return clipped

    def candidate_blocks(self) -> Iterator[tuple[IntArray, IntArray]]:
        """``(triangle index, point index)`` pair arrays, in blocks of about PAIR_BLOCK."""
        c_lo = self._cell_of(self.tri_lo)
        c_hi = self._cell_of(self.tri_hi)
        nx = c_hi[:, 0] - c_lo[:, 0] + 1
        ny = c_hi[:, 1] - c_lo[:, 1] + 1
        # (triangle, cell) pairs
        per_tri = nx * ny
        tri_of = np.repeat(np.arange(self.n_faces, dtype=np.int64), per_tri)
        offset = np.arange(len(tri_of), dtype=np.int64) - np.repeat(
            np.cumsum(per_tri) - per_tri, per_tri
        )
        cx = c_lo[tri_of, 0] + offset // ny[tri_of]
        cy = c_lo[tri_of, 1] + offset % ny[tri_of]
        key = cx * self.shape[1] + cy
        first = self.start[key]
        count = self.start[key + 1] - first
        keep = count > 0
        tri_of, first, count = tri_of[keep], first[keep], count[keep]
        ends = np.cumsum(count)
        begin = 0
        while begin < len(count):
            base = ends[begin - 1] if begin else 0
            stop = int(np.searchsorted(ends, base + PAIR_BLOCK, side="right"))
            stop = max(stop, begin + 1)
            t, f, n = tri_of[begin:stop], first[begin:stop], count[begin:stop]
            pair_tri = np.repeat(t, n)
            within = np.arange(int(n.sum()), dtype=np.int64) - np.repeat(np.cumsum(n) - n, n)
            pair_pt = self.order[np.repeat(f, n) + within]
            yield pair_tri, pair_pt
            begin = stop
