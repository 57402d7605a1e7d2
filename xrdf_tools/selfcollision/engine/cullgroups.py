"""Culled body pairs that share one side, tested as groups.

Body pairs between the same two bodies that share one side (the same bounding sphere on the
lower body: a frame of the static rest of the robot against each frame of a hand) form a
group: that side against one sphere around all their other sides. Per configuration each
group is tested first (:meth:`~.culling.Culler.gaps2`, one row per group); its members only
where the group is within reach (:func:`grouped_near`), all of a group's members at once (one
GEMM places their other sides at those configurations).

The configurations within reach are those of testing every member everywhere. A member's
clearance bound at the others is the smaller of its own gaps where it was tested, and of the
group's gap elsewhere plus how far inside the group's sphere the member stays: a valid lower
bound, at least the margin, but not always the member's own smallest gap (which would need
every member tested wherever the group's gap could be smaller: twice the cost).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...util.arrays import FloatArray, IntArray
from .bodies import F32

__all__ = ["GroupTable", "grouped_near"]

#: (member, configuration) entries of a group tested at once: 1 MB of float32 distances.
_BLOCK = 1 << 18


@dataclass(frozen=True, eq=False)
class GroupTable:
    """Every group's members, flattened (``M`` members in all, group by group).

    Per group [G]: the two bodies (``lo`` holds the shared side, centre ``shared`` [G, 3]),
    its reach, and where its members start in the member arrays (``starts`` [G + 1]).
    Per member [M]: its row in the plan (``row``), its group, the centre of its other side
    in the body ``hi`` (``centre`` [M, 3]), its reach, and how far inside the group's sphere
    its other side stays (``inside``)."""

    lo: IntArray
    hi: IntArray
    shared: F32
    group_reach: FloatArray
    starts: IntArray
    row: IntArray
    group: IntArray
    centre: F32
    reach: FloatArray
    inside: FloatArray


def grouped_near(
    table: GroupTable, g2: F32, R: F32, t: F32, margin: float
) -> tuple[IntArray, IntArray, FloatArray]:
    """The members' configurations within reach and their bounds, from the groups' squared
    gaps ``g2`` [G, B] and the body poses ``R`` [nb, 3, 3, B], ``t`` [nb, 3, B].

    Returns the (member row, configuration) entries within reach, and per member [M] a lower
    bound of its clearance at every other configuration (at least ``margin``)."""
    reach_g = table.group_reach
    within = g2 <= (reach_g**2).astype(np.float32)[:, None]
    found = _Found(len(table.row))
    for g in np.flatnonzero(within.any(axis=1)).tolist():
        found.test(table, g, np.flatnonzero(within[g]), R, t, margin)
    far2 = np.min(g2, axis=1, where=~within, initial=np.inf).astype(np.float64)
    rest = np.sqrt(far2) - reach_g + margin
    low = np.minimum(found.low, rest[table.group] + table.inside)
    if not found.rows:
        empty = np.zeros(0, dtype=np.intp)
        return empty, empty, low
    return np.concatenate(found.rows), np.concatenate(found.cols), low


class _Found:
    """The members' entries within reach, and per member [M] its smallest clearance bound
    where it was tested and not within reach."""

    def __init__(self, n_members: int) -> None:
        self.rows: list[IntArray] = []
        self.cols: list[IntArray] = []
        self.low = np.full(n_members, np.inf)

    def test(self, table: GroupTable, g: int, at: IntArray, R: F32, t: F32, margin: float) -> None:
        """Test group ``g``'s members at the configurations ``at``, in blocks of at most
        :data:`_BLOCK` (member, configuration) entries (bounded memory)."""
        members = slice(int(table.starts[g]), int(table.starts[g + 1]))
        reach = table.reach[members]
        reach2 = (reach**2).astype(np.float32)[None, :]
        step = max(1, _BLOCK // (members.stop - members.start))
        for s0 in range(0, len(at), step):
            cols = at[s0 : s0 + step]
            d2 = _member_gaps2(table, g, members, cols, R, t)  # [n, m]
            near = d2 <= reach2
            far_min = np.min(d2, axis=0, where=~near, initial=np.inf).astype(np.float64)
            low = np.sqrt(far_min) - reach + margin
            np.minimum(self.low[members], low, out=self.low[members])
            b, m = np.nonzero(near)
            self.rows.append(table.row[members][m])
            self.cols.append(cols[b])


def _member_gaps2(table: GroupTable, g: int, members: slice, at: IntArray, R: F32, t: F32) -> F32:
    """Squared distances [n, m] between group ``g``'s shared side and its members' other
    sides at the configurations ``at`` [n]."""
    lo, hi = int(table.lo[g]), int(table.hi[g])
    shared = np.einsum("ijn,j->ni", R[lo][:, :, at], table.shared[g]) + t[lo][:, at].T  # [n, 3]
    Rh = R[hi][:, :, at].transpose(2, 0, 1).reshape(-1, 3)  # [n·3, 3]
    other = (Rh @ table.centre[members].T).reshape(len(at), 3, -1)  # [n, 3, m]: one GEMM
    other += (t[hi][:, at].T - shared)[:, :, None]
    out: F32 = np.einsum("nkm,nkm->nm", other, other)
    return out
