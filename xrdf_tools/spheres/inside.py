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

Candidate (point, triangle) pairs come from a uniform xy grid of buckets over the triangles,
built once per mesh (:func:`face_grid`, kept while the mesh object lives and its vertices and
faces are unchanged): a query costs time in proportion to its points and the few triangles
over each, not to the whole mesh, so the many queries of a fit on a CAD mesh of millions of
triangles pay for its faces once. Pairs are processed in bounded blocks, and each block
computes the edge values of only its own triangles, so memory stays linear in the points and
faces. Any superset of the triangles whose xy box holds a point gives the same answer (the
test is exact), so the grid decides speed, never the result.
"""

from __future__ import annotations

import weakref
from collections.abc import Iterator
from typing import TYPE_CHECKING

import numpy as np

from ..util.arrays import BoolArray, FloatArray
from ..util.arrays import Int64Array as IntArray

if TYPE_CHECKING:
    import trimesh

__all__ = ["face_grid", "grid_inside", "points_inside"]


#: Point-triangle candidate pairs tested per block (about 200 bytes each).
PAIR_BLOCK = 1_000_000
#: (triangle, cell) pairs a grid may list per triangle before it is made coarser.
PAIRS_PER_FACE = 8
#: A triangle whose xy box covers more grid cells than this is tested against every point of
#: a query instead of being listed in each cell (a long sliver across a CAD part) ...
WIDE_CELLS = 256
#: ... as long as there are at most this many such triangles (else the grid is made coarser).
MAX_WIDE = 64
#: Triangles whose (triangle, cell) pairs are computed at once while the grid is built.
_BUILD_BLOCK = 1 << 17


def points_inside(mesh: trimesh.Trimesh, points: FloatArray) -> BoolArray:
    """``(N,)`` booleans: which of ``points (N, 3)`` lie inside the closed ``mesh``."""
    pts = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    crossings = np.zeros(len(pts), dtype=np.int64)
    if len(pts) == 0 or len(mesh.faces) == 0:
        return crossings.astype(bool)
    for pnt, z in face_grid(mesh).crossings(pts):
        crossings += np.bincount(pnt[z > pts[pnt, 2]], minlength=len(pts))
    return (crossings % 2).astype(bool)


def grid_inside(
    mesh: trimesh.Trimesh, axes: tuple[FloatArray, FloatArray, FloatArray]
) -> BoolArray:
    """``(nx, ny, nz)`` booleans: which nodes of the grid ``axes`` lie inside the closed
    ``mesh``; the same answer as :func:`points_inside` on the nodes, with one ray per xy column
    (the crossings of a column are found once and counted above each node of it)."""
    xs, ys, zs = (np.asarray(a, dtype=np.float64) for a in axes)
    out = np.zeros((len(xs), len(ys), len(zs)), dtype=bool)
    if len(mesh.faces) == 0 or out.size == 0:
        return out
    gx, gy = np.meshgrid(xs, ys, indexing="ij")
    columns = np.stack([gx.ravel(), gy.ravel(), np.full(gx.size, -np.inf)], axis=1)
    cols: list[IntArray] = []
    heights: list[FloatArray] = []
    for c, z in face_grid(mesh).crossings(columns):
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


def _orient(a: FloatArray, b: FloatArray, p: FloatArray) -> FloatArray:
    """Twice the signed xy area of (a, b, p): > 0 when p lies left of a -> b."""
    return (b[..., 0] - a[..., 0]) * (p[..., 1] - a[..., 1]) - (b[..., 1] - a[..., 1]) * (
        p[..., 0] - a[..., 0]
    )


class _TriangleTable:
    """Per triangle (of those a block of pairs names), what the crossing test needs.

    For each edge, in canonical (lower vertex index first) direction: its start point ``a``,
    direction ``d``, and the sign ``g`` (+-1) that turns its orientation value into "on the
    triangle's inner side when > 0"; ``tie`` says which side an exact 0 falls on (the
    point shifted by (eps, eps^2)); ``seen`` is false for a triangle seen edge-on, which is
    never crossed.
    """

    def __init__(self, vertices: FloatArray, faces: IntArray) -> None:
        v = vertices[faces]
        orientation = np.sign(_orient(v[:, 0], v[:, 1], v[:, 2]))
        self.seen = orientation != 0.0
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

    def crossings(
        self, tri: IntArray, pnt: IntArray, pts: FloatArray
    ) -> tuple[IntArray, FloatArray]:
        """The (point, height) of each pair whose vertical line through the point crosses
        the triangle: the line's xy lies in the triangle's projection (exact tie rules)."""
        px, py = pts[pnt, 0], pts[pnt, 1]
        lo, hi = self.lo[tri], self.hi[tri]
        near = (px >= lo[:, 0]) & (px <= hi[:, 0]) & (py >= lo[:, 1]) & (py <= hi[:, 1])
        near &= self.seen[tri]
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


class FaceGrid:
    """A mesh's triangles sorted into a uniform xy grid, each listed in every cell its xy box
    covers. The grid starts at about two triangles a cell and is made coarser while the
    (triangle, cell) pairs exceed :data:`PAIRS_PER_FACE` a triangle (the long slivers of a CAD
    part cross many cells); the few triangles that still cover more than :data:`WIDE_CELLS`
    cells are kept in a list tested against every point instead."""

    def __init__(self, vertices: FloatArray, faces: IntArray) -> None:
        self.vertices, self.faces = vertices, faces
        lo, hi = _xy_boxes(vertices, faces)
        self.lo = lo.min(0) if len(lo) else np.zeros(2)
        self.span = np.maximum((hi.max(0) if len(hi) else self.lo) - self.lo, 1e-12)
        cells = max(1, int(np.sqrt(len(faces) / 2.0)))
        while True:
            self._resolution(cells)
            covered = self._covered(lo, hi)
            wide = covered > WIDE_CELLS
            listed = int(covered[~wide].sum())
            if cells == 1 or (listed <= PAIRS_PER_FACE * len(faces) and wide.sum() <= MAX_WIDE):
                break
            cells = max(1, cells // 2)
        keys, tris = [], []
        for s0 in range(0, len(faces), _BUILD_BLOCK):
            sl = slice(s0, s0 + _BUILD_BLOCK)
            key, tri = self._cells_of(lo[sl], hi[sl], wide[sl])
            keys.append(key.astype(np.int32))  # cells and triangles < 2**31: half the memory
            tris.append((tri + s0).astype(np.int32))
        del lo, hi
        key = np.concatenate(keys) if keys else np.zeros(0, dtype=np.int32)
        del keys
        order = np.argsort(key, kind="stable")
        self.tri_of_cell = np.concatenate(tris)[order] if tris else np.zeros(0, dtype=np.int32)
        counts = np.bincount(key, minlength=int(self.shape[0] * self.shape[1]))
        self.start = np.concatenate([[0], np.cumsum(counts)])
        self.wide = np.flatnonzero(wide)

    def _resolution(self, cells: int) -> None:
        """Set the grid to ``cells`` cells along the longer xy side."""
        shape = (self.span / self.span.max() * cells).astype(np.int64)
        self.shape = np.minimum(np.maximum(shape, 1), 4096)
        self.size = self.span / self.shape

    def _cell_of(self, xy: FloatArray) -> IntArray:
        c = np.floor((xy - self.lo) / self.size).astype(np.int64)
        clipped: IntArray = np.clip(c, 0, self.shape - 1)
        return clipped

    def _covered(self, lo: FloatArray, hi: FloatArray) -> IntArray:
        """How many cells each xy box ``[lo, hi]`` covers."""
        span: IntArray = self._cell_of(hi) - self._cell_of(lo) + 1
        return span[:, 0] * span[:, 1]

    def _cells_of(
        self, lo: FloatArray, hi: FloatArray, wide: BoolArray
    ) -> tuple[IntArray, IntArray]:
        """The (cell key, triangle) pairs of the triangles with xy boxes ``[lo, hi]`` (indices
        into these boxes), the ``wide`` ones left out."""
        c_lo, c_hi = self._cell_of(lo), self._cell_of(hi)
        ny = c_hi[:, 1] - c_lo[:, 1] + 1
        per_tri = np.where(wide, 0, (c_hi[:, 0] - c_lo[:, 0] + 1) * ny)
        tri_of = np.repeat(np.arange(len(lo), dtype=np.int64), per_tri)
        offset = np.arange(len(tri_of), dtype=np.int64) - np.repeat(
            np.cumsum(per_tri) - per_tri, per_tri
        )
        cx = c_lo[tri_of, 0] + offset // ny[tri_of]
        cy = c_lo[tri_of, 1] + offset % ny[tri_of]
        return cx * self.shape[1] + cy, tri_of

    def crossings(self, pts: FloatArray) -> Iterator[tuple[IntArray, FloatArray]]:
        """``(point, height)`` of each crossing of a vertical line through one of ``pts`` with
        a triangle, in blocks of about :data:`PAIR_BLOCK` candidate pairs."""
        for tri, pnt in self._candidate_blocks(pts):
            used, local = np.unique(tri, return_inverse=True)
            table = _TriangleTable(self.vertices, self.faces[used])
            yield table.crossings(local.reshape(-1), pnt, pts)

    def _candidate_blocks(self, pts: FloatArray) -> Iterator[tuple[IntArray, IntArray]]:
        """``(triangle index, point index)`` pair arrays: every triangle of each point's cell,
        then every wide triangle with every point."""
        cell = self._cell_of(pts[:, :2])
        key = cell[:, 0] * self.shape[1] + cell[:, 1]
        first = self.start[key]
        count = self.start[key + 1] - first
        ends = np.cumsum(count)
        begin = 0
        while begin < len(count):
            base = ends[begin - 1] if begin else 0
            stop = max(int(np.searchsorted(ends, base + PAIR_BLOCK, side="right")), begin + 1)
            f, n = first[begin:stop], count[begin:stop]
            within = np.arange(int(n.sum()), dtype=np.int64) - np.repeat(np.cumsum(n) - n, n)
            pair_pt = np.repeat(np.arange(begin, stop, dtype=np.int64), n)
            yield self.tri_of_cell[np.repeat(f, n) + within], pair_pt
            begin = stop
        if len(self.wide):
            step = max(1, PAIR_BLOCK // len(self.wide))
            for s0 in range(0, len(pts), step):
                p = np.arange(s0, min(len(pts), s0 + step), dtype=np.int64)
                yield np.tile(self.wide, len(p)), np.repeat(p, len(self.wide))


def _xy_boxes(vertices: FloatArray, faces: IntArray) -> tuple[FloatArray, FloatArray]:
    """Each triangle's xy bounding box ``(lo, hi)``, ``(F, 2)`` each."""
    xy = vertices[:, :2]
    a, b, c = xy[faces[:, 0]], xy[faces[:, 1]], xy[faces[:, 2]]
    return np.minimum(np.minimum(a, b), c), np.maximum(np.maximum(a, b), c)


_GRIDS: weakref.WeakKeyDictionary[trimesh.Trimesh, tuple[int, FaceGrid]] = (
    weakref.WeakKeyDictionary()
)


def face_grid(mesh: trimesh.Trimesh) -> FaceGrid:
    """The :class:`FaceGrid` of ``mesh``, built on first use and kept while ``mesh`` lives and
    its vertices and faces stay as they were."""
    state = hash(mesh)
    kept = _GRIDS.get(mesh)
    if kept is not None and kept[0] == state:
        return kept[1]
    vertices = np.asarray(mesh.vertices, dtype=np.float64)
    grid = FaceGrid(vertices, np.asarray(mesh.faces, dtype=np.int64))
    _GRIDS[mesh] = (state, grid)
    return grid
