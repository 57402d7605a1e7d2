"""The actuated joints between two frames, for many frame pairs at once.

A joint lies between frames ``a`` and ``b`` when it drives a frame below their lowest common
ancestor ``l`` on the path to either (a mimic joint counts as its master). Per frame, the set
of joints driving its root path is a bit mask ``M``; the joints between ``a`` and ``b`` are
then ``(M[a] | M[b]) & ~M[l]``, except for a joint that drives two frames of one root path (a
mimic below its master), which may lie both above ``l`` and below it: such repeats are
decided from the depth of the joint's deepest frame on each side's root path. Each pair
costs a few integer operations instead of a walk along the tree.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from ...util.ancestry import Ancestry
from ...util.arrays import IntArray

__all__ = ["JointPaths"]

_NONE: dict[int, int] = {}


class JointPaths:
    """Bit masks of the actuated joints (bit ``i``: ``q[i]``) on each frame's root path, from
    the tree ``parent`` [F] and each frame's driving joint ``q_index`` [F] (-1 for none)."""

    def __init__(self, parent: IntArray, q_index: IntArray) -> None:
        self.tree = Ancestry(parent)
        par, qs = parent.tolist(), q_index.tolist()
        depth = self.tree.depth.tolist()
        masks, repeats = [0] * len(par), [0] * len(par)
        deepest: list[dict[int, int]] = [_NONE] * len(par)
        for f in range(1, len(par)):
            p, q = par[f], qs[f]
            mask, rep, deep = masks[p], repeats[p], deepest[p]
            if q >= 0:
                bit = 1 << q
                if mask & bit:  # a second frame of one joint on this root path
                    rep |= bit
                    deep = {**deep, q: depth[f]}
                mask |= bit
            masks[f], repeats[f], deepest[f] = mask, rep, deep
        self._masks, self._repeats, self._deepest, self._depth = masks, repeats, deepest, depth

    def between(self, a: npt.ArrayLike, b: npt.ArrayLike) -> list[int]:
        """Per frame pair ``(a[i], b[i])``: the bit mask of the joints between them."""
        a, b = np.asarray(a, dtype=np.intp), np.asarray(b, dtype=np.intp)
        lca = self.tree.lca(a, b).tolist()
        masks, repeats = self._masks, self._repeats
        out = []
        for x, y, m in zip(a.tolist(), b.tolist(), lca, strict=True):
            bits = (masks[x] | masks[y]) & ~masks[m]
            above = (repeats[x] | repeats[y]) & masks[m]
            if above:
                bits |= self._repeated_below(x, y, m, above)
            out.append(bits)
        return out

    def _repeated_below(self, x: int, y: int, m: int, above: int) -> int:
        """Of the joints ``above`` (each driving ``m`` or a frame above it), those that also
        drive a frame below ``m`` on the root path of ``x`` or of ``y``."""
        out = 0
        level = self._depth[m]
        dx, dy = self._deepest[x], self._deepest[y]
        while above:
            bit = above & -above
            above ^= bit
            q = bit.bit_length() - 1
            if dx.get(q, -1) > level or dy.get(q, -1) > level:
                out |= bit
        return out
