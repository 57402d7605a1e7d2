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
triangles pay for its faces once. A triangle is listed only in the cells its xy projection
touches: one whose box covers a few cells in all of them, a larger one row by row, in the
cells of its x extent within the row's band. (Listed in every cell of its box, a long
diagonal sliver covered a large share of the grid: a disc or a cone tessellated as a fan of
slivers from one centre had the grid made coarser until every point met thousands of
triangles, and a 200,000-triangle fan cone took over ten minutes in ``xrdf spheres``.) The
band and the extent are widened by a little more than the rounding of the cell a point is
put in and of the crossing test, so every triangle that could count a point is among those
of its cell. The grid starts at about two triangles a cell and is made coarser only while
the listed (triangle, cell) pairs exceed a budget linear in the triangles (at least
:data:`MIN_PAIRS`), which bounds its memory; a fan then ends at tens to hundreds of
triangles a point. Pairs are processed in bounded blocks, and each block computes the edge
values of only its own triangles, so memory stays linear in the points and faces. Any
superset of the triangles whose xy projection may hold a point gives the same answer (the
test is exact), so the grid decides speed, never the result.
"""

from __future__ import annotations

import weakref
from collections.abc import Iterator
from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt

from ..util.arrays import BoolArray, FloatArray, ragged_index
from ..util.arrays import Int64Array as IntArray

if TYPE_CHECKING:
    import trimesh

__all__ = ["face_grid", "grid_inside", "points_inside"]


#: Point-triangle candidate pairs tested per block (about 200 bytes each).
PAIR_BLOCK = 1_000_000
#: (triangle, cell) pairs a grid may list per triangle before it is made coarser ...
PAIRS_PER_FACE = 8
#: ... and at least this many (a fan of slivers from one centre lists each sliver in a
#: line of cells: a finer grid lists more pairs, but tests fewer of them per point).
MIN_PAIRS = 16_000_000
#: A triangle listed in more grid cells than this is tested against every point of a query
#: instead of being listed in each cell (a long sliver across a CAD part) ...
WIDE_CELLS = 256
#: ... as long as there are at most this many such triangles (else the grid is made coarser).
MAX_WIDE = 64
#: A triangle whose xy box covers at most this many cells is listed in all of them; a larger
#: one only in the cells its projection touches, found row by row.
BOX_CELLS = 4
#: How far a row's band and a triangle's extent in it are widened (relative to a cell, and
#: to the coordinates): more than the rounding of the cell a point is put in and of the
#: crossing test, so a triangle is never missing from a cell whose points it may hold.
PAD_OF_CELL = 1e-6
PAD_OF_COORDINATE = 1e-12
#: Triangles whose (triangle, cell) pairs are computed at once while the grid is built ...
_BUILD_BLOCK = 1 << 17
#: ... and (triangle, row) spans, or for the listing (triangle, cell) pairs, of the triangles
#: listed row by row.
_ROW_BLOCK = 1 << 17


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


#: Row spans of a block of triangles: the triangles, the first row and number of rows of each,
#: and for each row of each in turn its first and last column (see :meth:`FaceGrid._row_spans`).
_Spans = tuple[IntArray, IntArray, IntArray, npt.NDArray[np.int16], npt.NDArray[np.int16]]


class FaceGrid:
    """A mesh's triangles sorted into a uniform xy grid, each listed in the cells its xy
    projection touches (:meth:`_touched`); triangles seen edge-on, never crossed, are not
    listed. The grid starts at about two triangles a cell and is made coarser while the
    (triangle, cell) pairs exceed the budget (:data:`PAIRS_PER_FACE` a triangle, at least
    :data:`MIN_PAIRS`); the few triangles that still touch more than :data:`WIDE_CELLS` cells
    are kept in a list tested against every point instead."""

    def __init__(self, vertices: FloatArray, faces: IntArray) -> None:
        self.vertices, self.faces = vertices, faces
        lo, hi, seen = _xy_boxes(vertices, faces)
        self.lo = lo.min(0) if len(lo) else np.zeros(2)
        self.span = np.maximum((hi.max(0) if len(hi) else self.lo) - self.lo, 1e-12)
        budget = max(PAIRS_PER_FACE * len(faces), MIN_PAIRS)
        cells = max(1, int(np.sqrt(len(faces) / 2.0)))
        while True:
            self._resolution(cells)
            c_lo, c_hi = self._cell_of(lo), self._cell_of(hi)
            box: IntArray = c_hi - c_lo + 1
            fewest = self._fewest_listed(box, seen)
            if cells > 1 and fewest > budget:  # the row spans need not be found
                cells = _coarser(cells, budget / fewest)
                continue
            touched, spans = self._touched(lo, hi, box, seen)
            wide = touched > WIDE_CELLS
            listed = int(touched[~wide].sum())
            if cells == 1 or (listed <= budget and wide.sum() <= MAX_WIDE):
                break
            cells = _coarser(cells, budget / max(listed, 1))
        keys, tris = [], []
        by_box = ~wide & (touched > 0) & (box[:, 0] * box[:, 1] <= BOX_CELLS)
        for key, tri in self._listing(c_lo, c_hi, by_box, np.where(wide, 0, touched), spans):
            keys.append(key.astype(np.int32))  # cells and triangles < 2**31: half the memory
            tris.append(tri.astype(np.int32))
        del lo, hi, c_lo, c_hi, box, spans
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
        magnitude = np.maximum(np.abs(self.lo), np.abs(self.lo + self.span))
        self.pad = PAD_OF_CELL * self.size + PAD_OF_COORDINATE * magnitude

    def _cell_of(self, xy: FloatArray) -> IntArray:
        """The (column, row) of the cells holding the points ``xy (N, 2)``."""
        return self._cell_along(xy, slice(None))

    def _cell_along(self, values: FloatArray, axis: int | slice) -> IntArray:
        """The column (``axis`` 0) or row (1) of the cells holding the coordinates ``values``:
        the one floor and clip every query and every listing goes through."""
        c = np.floor((values - self.lo[axis]) / self.size[axis]).astype(np.int64)
        clipped: IntArray = np.clip(c, 0, self.shape[axis] - 1)
        return clipped

    def _fewest_listed(self, box: IntArray, seen: BoolArray) -> float:
        """At least how many pairs :meth:`_touched` will list, or inf when more than
        :data:`MAX_WIDE` triangles will be wide: a triangle's columns in a row make one run,
        which shares a column with the next row's (their padded bands overlap), and together
        they hold every column of its box (``box``: its columns and rows)."""
        least = np.where(seen, box.sum(1) - 1, 0)
        wide = least > WIDE_CELLS
        if wide.sum() > MAX_WIDE:
            return float("inf")
        return float(least[~wide].sum() - MAX_WIDE * WIDE_CELLS)

    def _touched(
        self, lo: FloatArray, hi: FloatArray, box: IntArray, seen: BoolArray
    ) -> tuple[IntArray, list[_Spans]]:
        """How many cells each triangle (xy box ``[lo, hi]``) is listed in: those of its box
        when it covers at most :data:`BOX_CELLS` of them, else those of its :meth:`_row_spans`
        (returned too); none for a triangle seen edge-on."""
        touched: IntArray = np.where(seen, box[:, 0] * box[:, 1], 0)
        spans = list(self._row_spans(lo, hi, np.flatnonzero(touched > BOX_CELLS)))
        for tris, _, rows, x0, x1 in spans:
            touched[tris] = np.add.reduceat(x1.astype(np.int64) - x0 + 1, np.cumsum(rows) - rows)
        return touched, spans

    def _listing(
        self,
        c_lo: IntArray,
        c_hi: IntArray,
        by_box: BoolArray,
        touched: IntArray,
        spans: list[_Spans],
    ) -> Iterator[tuple[IntArray, IntArray]]:
        """(cell key, triangle) pairs: of the ``by_box`` triangles, every cell of their box
        (from cell ``c_lo`` to ``c_hi``), of the others listed (``touched > 0``), their row
        ``spans``; in blocks of at most :data:`_BUILD_BLOCK` triangles or :data:`_ROW_BLOCK`
        pairs."""
        for s0 in range(0, len(c_lo), _BUILD_BLOCK):
            sl = slice(s0, s0 + _BUILD_BLOCK)
            key, tri = self._cells_of(c_lo[sl], c_hi[sl], ~by_box[sl])
            yield key, tri + s0
        for tris, first_row, rows, x0, x1 in spans:
            row_tri, rank = ragged_index(rows)
            row = first_row[row_tri] + rank
            cells = np.where(touched[tris][row_tri] > 0, x1.astype(np.int64) - x0 + 1, 0)
            for sl in _blocks(cells, _ROW_BLOCK):
                span, offset = ragged_index(cells[sl])
                span += sl.start
                yield (x0[span] + offset) * self.shape[1] + row[span], tris[row_tri[span]]

    def _row_spans(self, lo: FloatArray, hi: FloatArray, tris: IntArray) -> Iterator[_Spans]:
        """Per row of cells each triangle of ``tris`` spans, the columns it touches there:
        ``(triangles, first row, rows, first column, last column)`` (the columns per row of
        each triangle in turn), in blocks of at most :data:`_ROW_BLOCK` rows.

        The columns are those of the triangle's x extent in the row's y band (both padded by
        :attr:`pad`, the extent clipped to the triangle's box), through :meth:`_cell_along`:
        a point whose ray the crossing test could count for the triangle lies in the band of
        its own row and within the padded extent, so its cell is among those listed."""
        first_row = self._cell_along(lo[tris, 1], 1)
        rows = self._cell_along(hi[tris, 1], 1) - first_row + 1
        for sl in _blocks(rows, _ROW_BLOCK):
            t = tris[sl]
            row_tri, rank = ragged_index(rows[sl])
            row = first_row[sl][row_tri] + rank
            tri = t[row_tri]
            y0 = np.maximum(self.lo[1] + row * self.size[1] - self.pad[1], lo[tri, 1])
            y1 = np.minimum(self.lo[1] + (row + 1) * self.size[1] + self.pad[1], hi[tri, 1])
            edges = _edges_by_height(self.vertices[self.faces[t], :2])[:, row_tri]
            x0, x1 = _band_extent(edges, y0, y1)
            met = y0 <= y1  # else (not seen: the band is padded) the whole box
            x0 = np.maximum(np.where(met, x0 - self.pad[0], -np.inf), lo[tri, 0])
            x1 = np.minimum(np.where(met, x1 + self.pad[0], np.inf), hi[tri, 0])
            c0 = self._cell_along(x0, 0).astype(np.int16)  # columns < 4096
            c1 = self._cell_along(x1, 0).astype(np.int16)
            yield t, first_row[sl], rows[sl], c0, c1

    def _cells_of(
        self, c_lo: IntArray, c_hi: IntArray, skip: BoolArray
    ) -> tuple[IntArray, IntArray]:
        """The (cell key, triangle) pairs of the triangles whose boxes run from cell ``c_lo``
        to ``c_hi`` (indices into these) listed in every cell of their box, the ``skip`` ones
        left out."""
        ny = c_hi[:, 1] - c_lo[:, 1] + 1
        per_tri = np.where(skip, 0, (c_hi[:, 0] - c_lo[:, 0] + 1) * ny)
        tri_of, offset = ragged_index(per_tri)
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
        for sl in _blocks(count, PAIR_BLOCK):
            f, n = first[sl], count[sl]
            point, within = ragged_index(n)
            yield self.tri_of_cell[f[point] + within], point + sl.start
        if len(self.wide):
            step = max(1, PAIR_BLOCK // len(self.wide))
            for s0 in range(0, len(pts), step):
                p = np.arange(s0, min(len(pts), s0 + step), dtype=np.int64)
                yield np.tile(self.wide, len(p)), np.repeat(p, len(self.wide))


def _xy_boxes(vertices: FloatArray, faces: IntArray) -> tuple[FloatArray, FloatArray, BoolArray]:
    """Each triangle's xy bounding box ``(lo, hi)``, ``(F, 2)`` each, and whether it is seen
    other than edge-on (the same value :class:`_TriangleTable` computes)."""
    xy = vertices[:, :2]
    a, b, c = xy[faces[:, 0]], xy[faces[:, 1]], xy[faces[:, 2]]
    seen: BoolArray = _orient(a, b, c) != 0.0
    return np.minimum(np.minimum(a, b), c), np.maximum(np.maximum(a, b), c), seen


def _edges_by_height(xy: FloatArray) -> FloatArray:
    """For triangles ``xy (K, 3, 2)``, ``(8, K)``: the x and y of the lowest vertex and of the
    middle one, the x of the highest, and the dx/dy of the edge from the lowest to the
    highest, from the lowest to the middle and from the middle to the highest (0 for a
    horizontal edge)."""
    y = xy[:, :, 1]
    first, last = np.argmin(y, axis=1), np.argmax(y, axis=1)
    last = np.where(last == first, (first + 2) % 3, last)  # all at one height: not seen
    low, mid, high = (xy[np.arange(len(xy)), k] for k in (first, 3 - first - last, last))

    def slope(a: FloatArray, b: FloatArray) -> FloatArray:
        rise = b[:, 1] - a[:, 1]
        run: FloatArray = np.where(
            rise > 0.0, (b[:, 0] - a[:, 0]) / np.where(rise > 0.0, rise, 1.0), 0.0
        )
        return run

    columns = [low[:, 0], low[:, 1], mid[:, 0], mid[:, 1], high[:, 0]]
    return np.stack([*columns, slope(low, high), slope(low, mid), slope(mid, high)])


def _band_extent(
    edges: FloatArray, y0: FloatArray, y1: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """The x extent of each triangle (its :func:`_edges_by_height`) within its band ``y0 <= y
    <= y1`` (within the triangle's heights): of the points where the band's two lines cross
    the edge from the lowest vertex to the highest and the other two edges, and of the middle
    vertex when the band holds it."""
    lx, ly, mx, my, _, long, lower, upper = edges
    ends = [lx + (y - ly) * long for y in (y0, y1)]
    ends += [np.where(y < my, lx + (y - ly) * lower, mx + (y - my) * upper) for y in (y0, y1)]
    x0, x1 = np.minimum.reduce(ends), np.maximum.reduce(ends)
    middle = (y0 <= my) & (my <= y1)
    return np.where(middle, np.minimum(x0, mx), x0), np.where(middle, np.maximum(x1, mx), x1)


def _blocks(cost: IntArray, limit: int) -> Iterator[slice]:
    """Consecutive slices of ``cost`` summing to at most ``limit`` (or one item)."""
    ends = np.cumsum(cost)
    begin = 0
    while begin < len(cost):
        base = ends[begin - 1] if begin else 0
        stop = max(int(np.searchsorted(ends, base + limit, side="right")), begin + 1)
        yield slice(begin, stop)
        begin = stop


def _coarser(cells: int, ratio: float) -> int:
    """The next, coarser resolution after ``cells`` cells a side listed (or would list at
    least) ``1 / ratio`` times the pairs allowed: in proportion, as a fan of slivers lists
    pairs in proportion to the cells a side, with a margin of 5 %; at most half as many."""
    return max(1, cells // 2, min(cells - 1, int(cells * ratio * 0.95)))


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
