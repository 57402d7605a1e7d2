"""Which boxes lie within a distance of each point: a bounding-volume tree walked in numpy.

The boxes are sorted along a Morton (Z-order) curve of their centres and grouped in leaves of
:data:`LEAF` consecutive boxes; each level above holds the boxes of pairs of the level below.
A query walks the tree for many points at once, keeping the (point, node) pairs whose node box
lies within the point's reach, level by level. Unlike a k-d tree of box centres, whose search
radius must grow by the largest box, the walk prunes with the boxes themselves, so long thin
boxes (the slivers of a CAD part) cost no more than small ones.

Everything is integer sorting and comparisons of the input floats: the same pairs on every run
and machine, whatever the order in which they are found.
"""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np
import numpy.typing as npt

from ..util.arrays import BoolArray, FloatArray, IntArray, ragged_index

CodeArray = npt.NDArray[np.uint64]

__all__ = ["LEAF", "BoxTree"]

#: Boxes per leaf of the tree.
LEAF = 8
#: (point, node) pairs tested at once; a larger frontier is split and walked depth first.
FRONTIER = 1 << 20
#: Bits per axis of the Morton code.
_BITS = 21


class BoxTree:
    """The boxes ``[lo, hi]`` (``(B, 3)`` each) in a tree over their centres' Morton order."""

    def __init__(self, lo: FloatArray, hi: FloatArray) -> None:
        self.order = np.argsort(_morton(0.5 * (lo + hi)), kind="stable")
        self.lo, self.hi = lo[self.order], hi[self.order]
        leaves = -(-len(lo) // LEAF)
        self.leaf_start = np.minimum(np.arange(leaves + 1, dtype=np.int64) * LEAF, len(lo))
        starts = self.leaf_start[:-1]
        self.levels: list[tuple[FloatArray, FloatArray]] = []
        if leaves:
            self.levels.append(
                (np.minimum.reduceat(self.lo, starts), np.maximum.reduceat(self.hi, starts))
            )
            while len(self.levels[-1][0]) > 1:
                self.levels.append(_pair_up(*self.levels[-1]))

    def within(self, pts: FloatArray, reach: FloatArray) -> Iterator[tuple[IntArray, IntArray]]:
        """``(point, box)`` index pairs, in blocks: every box within ``reach`` of a point
        (the box's distance to the point, 0 inside it, at most ``reach``)."""
        if not self.levels or len(pts) == 0:
            return
        top = len(self.levels) - 1
        stack = [(top, np.arange(len(pts), dtype=np.int64), np.zeros(len(pts), dtype=np.int64))]
        while stack:
            level, pi, node = stack.pop()
            lo, hi = self.levels[level]
            keep = _near(pts[pi], lo[node], hi[node], reach[pi])
            pi, node = pi[keep], node[keep]
            if level == 0:
                yield self._leaf_boxes(pts, reach, pi, node)
                continue
            child_pi, child = _children(pi, node, len(self.levels[level - 1][0]))
            for s0 in range(0, len(child), FRONTIER)[::-1]:
                sl = slice(s0, s0 + FRONTIER)
                stack.append((level - 1, child_pi[sl], child[sl]))

    def _leaf_boxes(
        self, pts: FloatArray, reach: FloatArray, pi: IntArray, leaf: IntArray
    ) -> tuple[IntArray, IntArray]:
        first = self.leaf_start[leaf]
        pair, within = ragged_index(self.leaf_start[leaf + 1] - first)
        box = first[pair] + within
        pi = pi[pair]
        keep = _near(pts[pi], self.lo[box], self.hi[box], reach[pi])
        return pi[keep], self.order[box[keep]]


def _near(p: FloatArray, lo: FloatArray, hi: FloatArray, reach: FloatArray) -> BoolArray:
    """Whether each box ``[lo, hi]`` lies within ``reach`` of its point ``p``."""
    gap = np.maximum(np.maximum(lo - p, p - hi), 0.0)
    out: BoolArray = np.einsum("nk,nk->n", gap, gap) <= reach**2
    return out


def _children(pi: IntArray, node: IntArray, below: int) -> tuple[IntArray, IntArray]:
    """The (point, child) pairs of (point, node) pairs, children ``2n`` and ``2n + 1`` of a
    level of ``below`` nodes (the last node of an odd level has one child)."""
    left = 2 * node
    right = left + 1
    has_right = right < below
    pis = np.concatenate([pi, pi[has_right]])
    kids = np.concatenate([left, right[has_right]])
    return pis, kids


def _pair_up(lo: FloatArray, hi: FloatArray) -> tuple[FloatArray, FloatArray]:
    """The level above: the box of each pair of consecutive boxes (an odd last one alone)."""
    if len(lo) % 2:
        lo, hi = np.concatenate([lo, lo[-1:]]), np.concatenate([hi, hi[-1:]])
    return np.minimum(lo[0::2], lo[1::2]), np.maximum(hi[0::2], hi[1::2])


def _morton(centres: FloatArray) -> CodeArray:
    """Each point's Morton code: its coordinates scaled to :data:`_BITS`-bit integers over
    the points' box, the bits interleaved."""
    lo = centres.min(0) if len(centres) else np.zeros(3)
    span = (centres.max(0) - lo) if len(centres) else np.ones(3)
    scale = np.where(span > 0, ((1 << _BITS) - 1) / np.where(span > 0, span, 1.0), 0.0)
    cells = ((centres - lo) * scale).astype(np.uint64)
    code = _spread(cells[:, 0]) | (_spread(cells[:, 1]) << np.uint64(1))
    out: CodeArray = code | (_spread(cells[:, 2]) << np.uint64(2))
    return out


def _spread(x: CodeArray) -> CodeArray:
    """The bits of 21-bit integers ``x`` spread two places apart."""
    x = x & np.uint64(0x1FFFFF)
    for shift, mask in (
        (32, 0x1F00000000FFFF),
        (16, 0x1F0000FF0000FF),
        (8, 0x100F00F00F00F00F),
        (4, 0x10C30C30C30C30C3),
        (2, 0x1249249249249249),
    ):
        x = (x | (x << np.uint64(shift))) & np.uint64(mask)
    return x
