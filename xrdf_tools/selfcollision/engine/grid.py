"""Cell grids for body pairs whose relative pose depends on one or two joints.

The relative pose of two bodies depends only on the joints on the tree path between them.
When that is one or two revolute joints, the pair's joint box is cut into cells once, and each
cell is decided in float64 with a rigorous bound on how far a sphere centre can move inside
it: a sphere of the outer body turning by at most ``h/2`` about an axis at distance ``ρ``
moves by at most ``ρ·h/2`` (chord ≤ arc), and the moves of two joints add up. A cell whose
every sphere pair stays farther apart than the exact-clearance margin is *far*: its
configurations need no evaluation at all (they cannot collide, and their clearances are not
needed exactly). Configurations in the other cells are evaluated as usual, so the grid changes
no verdict and no exact value; it only skips work.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import dataclass

import numpy as np

from ...util.arrays import BoolArray, FloatArray, IntArray

__all__ = ["PairGrid", "build_pair_grid"]

#: Cells of a two-joint grid and of a one-joint grid.
CELLS_2D = 1 << 16
CELLS_1D = 1 << 13
#: Absolute slack (m) for float64 rounding in the cell decisions.
_SLACK = 1e-9
#: Tolerance (in cells) for a joint value on the box edge: a point that far outside the last
#: cell moves its spheres by far less than the slack.
_EDGE = 1e-9


@dataclass(frozen=True, eq=False)
class PairGrid:
    """Per cell of the joint box of one body pair: far (True) or to be evaluated.

    ``cols``, ``mult``, ``off``: the varying columns driving the path joints (outer first) and
    their mimic factors; ``lo``, ``h``, ``shape``: each joint's first cell edge, cell width
    and cell count. ``far_bound``: lower bound of every sphere clearance in a far cell.
    """

    cols: IntArray
    mult: FloatArray
    off: FloatArray
    lo: FloatArray
    h: FloatArray
    shape: tuple[int, ...]
    far: BoolArray
    far_bound: float

    def near(self, q_var: FloatArray) -> BoolArray:
        """Configurations [B] that are not in a far cell (outside the box counts as near)."""
        B = q_var.shape[0]
        if self.all_far and self._inside(q_var):
            return np.zeros(B, dtype=np.bool_)
        cell = np.zeros(B, dtype=np.intp)
        inside = np.ones(B, dtype=np.bool_)
        for j, n in enumerate(self.shape):
            x = q_var[:, self.cols[j]] * (self.mult[j] / self.h[j])
            x += (self.off[j] - self.lo[j]) / self.h[j]  # the cell coordinate
            inside &= x >= -_EDGE
            inside &= x <= n + _EDGE
            np.clip(x, 0, n - 1, out=x)
            cell *= n
            cell += x.astype(np.intp)  # truncation is floor here: x >= 0
        out: BoolArray = self.far[cell]
        np.logical_not(out, out=out)
        out |= ~inside
        return out

    @property
    def far_fraction(self) -> float:
        return float(np.mean(self.far))

    @property
    def all_far(self) -> bool:
        return bool(self.far.all())

    def _inside(self, q_var: FloatArray) -> bool:
        """Every configuration lies in the grid's box (checked on the column extremes)."""
        for j, n in enumerate(self.shape):
            col = q_var[:, self.cols[j]]
            ends = np.array([col.min(), col.max()]) * self.mult[j] + self.off[j]
            x = (ends - self.lo[j]) / self.h[j]
            if x.min() < -_EDGE or x.max() > n + _EDGE:
                return False
        return True


def _rot_z(theta: FloatArray) -> FloatArray:
    """Rotations about z [n, 3, 3]."""
    c, s = np.cos(theta), np.sin(theta)
    out = np.zeros((len(theta), 3, 3))
    out[:, 0, 0], out[:, 0, 1], out[:, 1, 0], out[:, 1, 1] = c, -s, s, c
    out[:, 2, 2] = 1.0
    return out


def _cell_counts(spans: list[float], levers: list[float]) -> list[int]:
    """Cells per joint: proportional to span × lever (equal motion per joint), capped."""
    if len(spans) == 1:
        return [CELLS_1D]
    w = [max(s * r, 1e-9) for s, r in zip(spans, levers, strict=True)]
    scale = math.sqrt(CELLS_2D / (w[0] * w[1]))
    n0 = min(CELLS_2D, max(1, round(w[0] * scale)))
    return [n0, max(1, CELLS_2D // n0)]


def build_pair_grid(
    consts: list[FloatArray],
    cols: list[int],
    mult: list[float],
    off: list[float],
    q_lo: list[float],
    q_hi: list[float],
    p_anc: FloatArray,
    x_desc: FloatArray,
    rsum: FloatArray,
    relevant: BoolArray,
    margin: float,
    min_far: float = 0.0,
) -> PairGrid | None:
    """Grid for the path joints (outer first) between an ancestor and a descendant body.

    ``consts`` [j](4, 4): each path joint's constant transform from the previous body
    (z-aligned frames, the joint turning about z); ``p_anc`` [m_a, 3]: sphere centres of the
    ancestor body, ``x_desc`` [m_b, 3]: those of the descendant in its own frame; ``rsum``
    [m_a, m_b]: radius sums; ``relevant`` [m_a, m_b]: the sphere pairs that are counted.
    Two-joint grids are decided coarse first (4 × 4 fine cells each); only the coarse cells
    that are not far are split. None when a fixed pilot of cells finds far fewer far cells
    than ``min_far`` (a grid that would skip too little is not built).
    """
    th = [
        sorted((m * lo + o, m * hi + o)) for m, o, lo, hi in zip(mult, off, q_lo, q_hi, strict=True)
    ]
    lo = np.array([a for a, _ in th])
    spans = [b - a for a, b in th]
    levers = [np.linalg.norm(x_desc[:, :2], axis=1)]  # distance from the innermost axis
    if len(consts) == 2:  # the outer axis: |xy of the inner joint's offset| + |x|
        levers.insert(0, np.linalg.norm(consts[1][:2, 3]) + np.linalg.norm(x_desc, axis=1))
    shape = _cell_counts(spans, [float(lv.max()) if len(lv) else 0.0 for lv in levers])
    h = np.array([max(sp / n, 1e-12) for sp, n in zip(spans, shape, strict=True)])
    ev = _CellTest(consts, lo, x_desc, p_anc, rsum + margin + _SLACK, relevant, levers, [np.inf])
    if len(shape) == 2 and min_far > 0.0:
        pilot = np.random.default_rng(0).integers(0, shape[0] * shape[1], _PILOT_CELLS)
        if ev.far(list(np.divmod(pilot, shape[1])), h).mean() < min_far / 2:
            return None
    far = ev.far([np.arange(shape[0])], h) if len(shape) == 1 else _far_2d(ev, shape, h)
    return PairGrid(
        cols=np.array(cols, dtype=np.intp),
        mult=np.array(mult),
        off=np.array(off),
        lo=lo,
        h=h,
        shape=tuple(shape),
        far=far,
        far_bound=ev.low[0] + margin,  # reach held the margin: add it back
    )


_SPLIT = 4
#: Sphere pairs of the parent cells split at once (each may look at 16 child cells).
_SPLIT_PAIRS = 1 << 16
#: Cells of a two-joint grid decided first, to tell whether the grid is worth building.
_PILOT_CELLS = 512
#: :meth:`_CellTest.split_far` takes this fraction of its coarse cells first, then the rest.
_FIRST_BATCH = 16


def _slices(items: IntArray, step: int) -> Iterator[IntArray]:
    for s0 in range(0, len(items), step):
        yield items[s0 : s0 + step]


def _far_2d(ev: _CellTest, shape: list[int], h: FloatArray) -> BoolArray:
    """Far flags of a two-joint grid: coarse cells first, then the fine cells of the rest.

    A cell lies inside its parent (a cell four times as wide per joint), so a sphere pair's
    gap there is at least its gap in the parent (the centres move by at most the difference
    of the motion bounds). A level is therefore decided on the sphere pairs whose parent gap is
    no more than the smallest far gap seen so far: the others are far there and cannot be the
    smallest. The coarse cells are decided that way from their parents when a pilot has seen a
    far cell, the fine cells of coarse cells that are not far always.
    """
    n0, n1 = shape
    c0, c1 = -(-n0 // _SPLIT), -(-n1 // _SPLIT)
    hc = h * _SPLIT
    if math.isfinite(ev.low[0]):
        p0, p1 = -(-c0 // _SPLIT), -(-c1 // _SPLIT)
        coarse: BoolArray = _children_far(ev, np.arange(p0 * p1), p1, (c0, c1), hc).ravel()
    else:
        i0, i1 = np.divmod(np.arange(c0 * c1), c1)
        coarse = ev.far([i0, i1], hc)
    far = _children_far(ev, np.flatnonzero(~coarse), c1, (c0 * _SPLIT, c1 * _SPLIT), h)
    far |= np.repeat(np.repeat(coarse.reshape(c0, c1), _SPLIT, axis=0), _SPLIT, axis=1)
    out: BoolArray = np.ascontiguousarray(far[:n0, :n1]).ravel()
    return out


def _children_far(
    ev: _CellTest, parents: IntArray, width: int, shape: tuple[int, int], h: FloatArray
) -> BoolArray:
    """Far flags [shape] of the cells (widths ``h``) inside the parent cells ``parents``
    (row-major indices in a grid ``width`` parents wide); other cells stay False."""
    far = np.zeros((-(-shape[0] // _SPLIT) * _SPLIT, -(-shape[1] // _SPLIT) * _SPLIT), np.bool_)
    sub0, sub1 = np.divmod(np.arange(_SPLIT * _SPLIT), _SPLIT)
    for cells in _slices(parents, ev.cells_per_slice(_SPLIT_PAIRS)):
        f0 = ((cells // width)[:, None] * _SPLIT + sub0[None, :]).ravel()
        f1 = ((cells % width)[:, None] * _SPLIT + sub1[None, :]).ravel()
        far[f0, f1] = ev.split_far([cells // width, cells % width], h, shape).ravel()
    out: BoolArray = far[: shape[0], : shape[1]]
    return out


@dataclass(frozen=True, eq=False)
class _CellTest:
    """Decides lists of cells: far when every relevant pair's centre distance exceeds its
    radius sum plus margin (``reach``) plus the cell's motion bound."""

    consts: list[FloatArray]
    lo: FloatArray
    x_desc: FloatArray
    p_anc: FloatArray
    reach: FloatArray  # [m_a, m_b]
    relevant: BoolArray
    levers: list[FloatArray]  # per joint [m_b]
    low: list[float]  # [1]: over far cells, smallest (distance − radius sum − motion) seen

    def far(self, idx: list[IntArray], h: FloatArray) -> BoolArray:
        """``idx``: cell indices per joint (outer first), all of one length L."""
        thr = self._reach_with_motion(h)
        thr2 = np.square(np.maximum(thr, 0.0)) * np.sign(thr)
        out = np.empty(len(idx[0]), dtype=np.bool_)
        # per sphere pair, the smallest squared centre distance over far cells
        nearest = np.full(thr.shape, np.inf)
        for sl, d2 in self._distances2(idx, h):
            far = np.greater(d2, thr2[None]).reshape(len(d2), -1).all(axis=1)
            out[sl] = far
            if far.any():
                d2_far = d2.min(axis=0, where=far[:, None, None], initial=np.inf)
                np.minimum(nearest, d2_far, out=nearest)
        if out.any():  # the smallest centre distance minus reach, over far cells
            # of the counted sphere pairs only: the others (thr −inf) have no gap to give
            gap = np.where(self.relevant.T, np.sqrt(np.maximum(nearest, 0.0)) - thr, np.inf)
            self.low[0] = min(self.low[0], float(gap.min()))
        return out

    def cells_per_slice(self, sphere_pairs: int = 1 << 20) -> int:
        """Cells per slice of the distance computations: about ``sphere_pairs`` each."""
        m = int(self.x_desc.shape[0]) * int(self.p_anc.shape[0])
        return max(1, sphere_pairs // max(1, m))

    def split_far(self, idx: list[IntArray], h: FloatArray, shape: tuple[int, int]) -> BoolArray:
        """Far flags [L, 16] of the fine cells (widths ``h``) of the coarse cells ``idx``
        (widths 4·``h``), row-major within each coarse cell; fine cells outside ``shape``
        are left out (False).

        Only the sphere pairs whose gap in the coarse cell is at most the smallest far gap
        seen so far are computed: the others are far in every fine cell and larger there.
        The coarse cells whose smallest gap is least are taken first, so that the smallest
        far gap falls early and skips most of the rest. (Every far gap is
        positive: a sphere pair skipped that way can neither make a fine cell near nor lower
        the smallest far gap, so the flags and the gap are those of computing every pair.)
        """
        d2c = np.concatenate([d2 for _, d2 in self._distances2(idx, h * _SPLIT)])
        thr_c = self._reach_with_motion(h * _SPLIT)
        gap_c = np.sqrt(np.maximum(d2c, 0.0)) - thr_c[None]  # [L, m_b, m_a]
        sub = np.divmod(np.arange(_SPLIT * _SPLIT), _SPLIT)
        child = [idx[j][:, None] * _SPLIT + sub[j] for j in (0, 1)]  # [L, 16]
        outside = (child[0] >= shape[0]) | (child[1] >= shape[1])
        far: BoolArray = ~outside
        cell_min = gap_c.reshape(len(gap_c), -1).min(axis=1, initial=np.inf)
        order = np.argsort(cell_min, kind="stable")
        first = max(1, len(order) // _FIRST_BATCH)
        for batch in (order[:first], order[first:]):
            cells = np.sort(batch[cell_min[batch] <= self.low[0]])
            if len(cells):
                far[cells] = self._split_cells(
                    [i[cells] for i in idx], gap_c[cells], h, outside[cells]
                )
        return far

    def _split_cells(
        self, idx: list[IntArray], gap_c: FloatArray, h: FloatArray, outside: BoolArray
    ) -> BoolArray:
        """:meth:`split_far` of the coarse cells ``idx`` (their gaps ``gap_c`` [L, m_b, m_a],
        their fine cells ``outside`` the grid [L, 16]), on the sphere pairs whose coarse gap
        is at most the smallest far gap seen so far."""
        # the pairs to look at, sorted by coarse cell, then descendant sphere (row-major)
        cell, jb, ia = np.nonzero(gap_c <= self.low[0])
        # each (coarse cell, descendant sphere) once, at the 16 fine cell centres
        m_b = self.x_desc.shape[0]
        key = cell * m_b + jb  # sorted: the distinct values start where it changes
        first = np.r_[True, key[1:] != key[:-1]] if len(key) else np.zeros(0, dtype=np.bool_)
        at = np.cumsum(first) - 1
        u_cell, u_sphere = np.divmod(key[first], m_b)
        sub = np.divmod(np.arange(_SPLIT * _SPLIT), _SPLIT)
        # each fine cell's joint values, their cosines and sines computed once per cell row
        fine = [idx[j][u_cell, None] * _SPLIT + sub[j] for j in (0, 1)]
        trig = [
            _cos_sin(self.lo[j] + (np.arange(int(fine[j].max(initial=-1)) + 1) + 0.5) * h[j])
            for j in (0, 1)
        ]
        pts = _turned(self.x_desc[u_sphere, None, :], trig[1], fine[1], self.consts[1])
        pts = _turned(pts, trig[0], fine[0], self.consts[0])  # [U, 16, 3]
        diff = pts[at] - self.p_anc[ia][:, None, :]  # [E, 16, 3]
        dist = np.sqrt(np.einsum("esk,esk->es", diff, diff))
        dist[outside[cell]] = np.inf
        thr = self._reach_with_motion(h)[jb, ia][:, None]
        near = np.zeros((len(idx[0]), _SPLIT * _SPLIT), dtype=np.bool_)
        if len(cell):  # one reduction per coarse cell (``cell`` is sorted)
            starts = np.flatnonzero(np.r_[True, cell[1:] != cell[:-1]])
            near[cell[starts]] = np.logical_or.reduceat(dist <= thr, starts, axis=0)
        far: BoolArray = ~(near | outside)
        in_far = far[cell]
        if in_far.any():
            self.low[0] = min(self.low[0], float((dist - thr)[in_far].min()))
        return far

    def _reach_with_motion(self, h: FloatArray) -> FloatArray:
        """Per relevant sphere pair [m_b, m_a]: reach plus the cell's motion bound (−inf for
        the pairs that are not counted)."""
        motion = sum(lv * hj / 2 for lv, hj in zip(self.levers, h.tolist(), strict=True))
        thr: FloatArray = np.where(self.relevant, self.reach + motion[None, :], -np.inf).T
        return thr

    def _distances2(self, idx: list[IntArray], h: FloatArray) -> Iterator[tuple[slice, FloatArray]]:
        """Squared centre distances [L', m_b, m_a] of the cells ``idx``, in bounded slices."""
        m_b, m_a = self.x_desc.shape[0], self.p_anc.shape[0]
        p2 = np.sum(self.p_anc**2, axis=1)
        step = self.cells_per_slice()
        for s0 in range(0, len(idx[0]), step):
            sl = slice(s0, s0 + step)
            theta = [self.lo[j] + (idx[j][sl] + 0.5) * h[j] for j in range(len(idx))]
            pts = self._points(theta)  # [L', m_b, 3]
            cross = (pts.reshape(-1, 3) @ self.p_anc.T).reshape(len(pts), m_b, m_a)
            cross *= 2.0
            d2 = np.sum(pts**2, axis=2)[:, :, None] + p2[None, None, :]
            d2 -= cross
            yield sl, d2

    def _points(self, theta: list[FloatArray]) -> FloatArray:
        """Descendant sphere centres in the ancestor frame at joint values ``theta``."""
        C = self.consts[-1]
        rt = _rot_z(theta[-1]).transpose(0, 2, 1) @ C[:3, :3].T  # [L, 3, 3]: (C·Z)ᵀ
        pts: FloatArray = np.matmul(self.x_desc[None], rt) + C[:3, 3]
        if len(theta) == 2:
            C = self.consts[0]
            rt = _rot_z(theta[0]).transpose(0, 2, 1) @ C[:3, :3].T
            pts = np.matmul(pts, rt) + C[:3, 3]
        return pts


def _cos_sin(theta: FloatArray) -> tuple[FloatArray, FloatArray]:
    return np.cos(theta), np.sin(theta)


def _turned(
    x: FloatArray, trig: tuple[FloatArray, FloatArray], at: IntArray, C: FloatArray
) -> FloatArray:
    """``C · Rz(θ) · x`` [U, S, 3] for points ``x`` [U, S or 1, 3] and the angles ``θ`` whose
    cosines and sines are ``trig`` [n] at the indices ``at`` [U, S]."""
    c, s = trig[0][at], trig[1][at]
    x0, x1, x2 = x[..., 0], x[..., 1], x[..., 2]
    a, b = c * x0 - s * x1, s * x0 + c * x1  # Rz(θ)·x
    R, t = C[:3, :3], C[:3, 3]
    out = np.empty((*at.shape, 3))
    for k in range(3):
        out[..., k] = R[k, 0] * a + R[k, 1] * b + R[k, 2] * x2 + t[k]
    return out
