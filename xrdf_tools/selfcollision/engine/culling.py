"""Culling: which configurations of a chunk a body pair needs to evaluate at all.

Two ways to skip configurations in which a body pair is farther apart than the margin, chosen
once per body pair when the engine is built (:meth:`Culler.choose`):

* a **cell grid** (:mod:`xrdf_tools.selfcollision.engine.grid`) when one or two revolute joints
  separate the bodies: cells proven far are skipped, with the grid's clearance bound;
* a **bounding-sphere cull** when a fixed pilot sample finds the bodies mostly out of reach:
  one float32 distance between the bodies' bounding spheres per configuration
  (:meth:`Culler.gaps2`), widened by the float32 error so that it never skips a near case.

Everything else is evaluated in full. A skipped configuration's clearance lower bound goes into
the chunk's bounds (:meth:`Culler.select`), so the minimum clearance stays honest.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass, replace
from typing import Protocol

import numpy as np

from ...robot.kinematics import KinematicModel
from ...util.arrays import BoolArray, FloatArray, IntArray
from ..collision import bounding_sphere
from .bodies import F32, ROT, Bodies, body_fk
from .cullgroups import GroupTable, grouped_near
from .grid import PairGrid, build_pair_grid
from .pairs import BodyPair

#: A body pair is culled when fewer than this fraction of pilot configurations is within reach.
_CULL_FRACTION = 0.5
_PILOT = 512
#: Body pairs with one or two revolute joints between them and at least this many counted
#: sphere pairs get a cell grid (see :mod:`xrdf_tools.selfcollision.engine.grid`).
_GRID_MIN_PAIRS = 1
_GRID_MAX_JOINTS = 2
#: A grid holds its sphere pairs' radius sums: beyond this many, the pair is culled otherwise.
_GRID_MAX_PAIRS = 1 << 13
#: (culled pairs × configurations) per block of :meth:`Culler.gaps2`: its temporaries stay in
#: the CPU cache (TIAGo's 708 culled pairs: 2× faster than blocks of 2048 configurations),
#: and a few pairs still get long blocks (fewer calls).
_GAP_ELEMENTS = 1 << 16
_GAP_MIN_BLOCK = 256
_GRID_MIN_FAR = 0.25  # a grid whose cells are mostly near saves too little
#: Culled body pairs sharing one side are tested as a group from this many on.
_GROUP_MIN = 2


class Sided(Protocol):
    """Two bodies and a bounding sphere on each (``[x, y, z, radius]``, body frames)."""

    @property
    def a(self) -> int: ...
    @property
    def b(self) -> int: ...
    @property
    def bound_a(self) -> FloatArray: ...
    @property
    def bound_b(self) -> FloatArray: ...


@dataclass(frozen=True, eq=False)
class _Sides:
    a: int
    b: int
    bound_a: FloatArray
    bound_b: FloatArray


def _other_side(bp: BodyPair, body: int) -> FloatArray:
    """The bounding sphere of ``bp``'s side that is not on ``body``."""
    return bp.bound_b if bp.a == body else bp.bound_a


@dataclass(frozen=True, eq=False)
class CullPlan:
    """How a chunk's culled body pairs (``pairs``, in engine order) are tested: the rows
    ``single`` one by one; the groups (body pairs sharing one side: ``sides`` holds that
    side and a sphere around their other sides, ``table`` their members) first as one."""

    pairs: tuple[BodyPair, ...]
    single: IntArray
    sides: tuple[_Sides, ...] = ()
    table: GroupTable | None = None


def _path_joints(bodies: Bodies, a: int, b: int) -> tuple[int, list[int]] | None:
    """(ancestor, bodies whose revolute joints lie between a and b, outer first) when one body
    is an ancestor of the other at most two joints away; None otherwise."""
    for anc, desc in ((a, b), (b, a)):
        joints = [desc]
        while len(joints) <= _GRID_MAX_JOINTS and bodies.parent[joints[0]] >= 0:
            if bodies.parent[joints[0]] == anc:
                if all(bodies.kind[j] == ROT for j in joints):
                    return anc, joints
                return None
            joints.insert(0, bodies.parent[joints[0]])
    return None


@dataclass(frozen=True, eq=False)
class Culler:
    """The culling state of one engine: the bodies, the exact-clearance ``margin`` and the
    float32 error ``err``. Each body pair carries the bounding spheres of its two sides."""

    kin: KinematicModel
    varying: IntArray
    bodies: Bodies
    local: FloatArray  # [S, 3] sphere centres in their body frames (float64)
    margin: float
    err: float

    def reach(self, bp: Sided) -> float:
        """Bounding-sphere centre distance beyond which ``bp`` is farther apart than the
        margin, float32 error included."""
        return float(bp.bound_a[3] + bp.bound_b[3]) + self.margin + (4 * self.err)

    def gaps2(self, R: F32, t: F32, pairs: Sequence[Sided]) -> F32:
        """float32 squared distance between the bounding-sphere centres of each pair's sides
        [P, B], in cache-sized column blocks. Each distinct centre is placed once per
        configuration, however many pairs share it."""
        out = np.empty((len(pairs), R.shape[-1]), dtype=np.float32)
        for sl, g in self._gap_blocks(R, t, pairs):
            out[:, sl] = g
        return out

    def _gap_blocks(self, R: F32, t: F32, pairs: Sequence[Sided]) -> Iterator[tuple[slice, F32]]:
        """:meth:`gaps2` one column block at a time: (columns, their squared gaps [P, n])."""
        index: dict[tuple[int, tuple[float, ...]], int] = {}
        ends = []
        for bp in pairs:
            for body, bound in ((bp.a, bp.bound_a), (bp.b, bp.bound_b)):
                ends.append(index.setdefault((body, tuple(bound[:3].tolist())), len(index)))
        ia, ib = np.array(ends[0::2], dtype=np.intp), np.array(ends[1::2], dtype=np.intp)
        by_body: dict[int, list[int]] = {}
        for (body, _), i in index.items():
            by_body.setdefault(body, []).append(i)
        pts = np.array([c for _, c in index], dtype=np.float32).reshape(-1, 3)
        poses = {b: (R[b], t[b]) for b in by_body if b != 0}
        B = R.shape[-1]
        step = max(_GAP_MIN_BLOCK, _GAP_ELEMENTS // len(pairs))
        for s0 in range(0, B, step):
            sl = slice(s0, min(B, s0 + step))
            n = sl.stop - sl.start
            W = np.empty((len(pts), 3, n), dtype=np.float32)
            for body, rows in by_body.items():
                P = pts[rows]
                if body == 0:  # the static body: its pose is the identity
                    W[rows] = P[:, :, None]
                    continue
                Rb, tb = poses[body]
                Rk = np.ascontiguousarray(Rb[:, :, sl].transpose(1, 0, 2)).reshape(3, 3 * n)
                W[rows] = (P @ Rk).reshape(len(rows), 3, n) + tb[:, sl]
            g = np.empty((len(pairs), n), dtype=np.float32)
            for i in range(3):
                D = W[ia, i] - W[ib, i]
                if i == 0:
                    np.multiply(D, D, out=g)
                else:
                    D *= D
                    g += D
            yield sl, g

    def choose(self, pairs: list[BodyPair]) -> list[BodyPair]:
        """Give body pairs a cell grid (one or two joints between them, and within reach in
        some configuration of a fixed pilot sample) or, when the pilot finds them mostly out of
        reach, a bounding-sphere cull."""
        if not pairs or len(self.varying) == 0:
            return pairs
        lo = self.kin.lower[self.varying]
        hi = self.kin.upper[self.varying]
        q = np.random.default_rng(12345).uniform(lo, hi, size=(_PILOT, len(self.varying)))
        R, t = body_fk(self.bodies, q)
        reach = np.array([self.reach(bp) for bp in pairs])
        g2 = self.gaps2(R, t, pairs)  # [P, pilot]: every pair at once
        within = np.mean(g2 <= (reach**2).astype(np.float32)[:, None], axis=1)
        out = []
        for bp, near in zip(pairs, within.tolist(), strict=True):
            # bodies the pilot never finds within reach: culling skips nearly every
            # configuration at one test each, less than a grid costs to build
            grid = self._grid_for(bp) if near > 0.0 else None
            if grid is not None and grid.far_fraction >= _GRID_MIN_FAR:
                out.append(replace(bp, grid=grid))
                continue
            cull = near < _CULL_FRACTION
            out.append(bp if bp.cull == cull else replace(bp, cull=cull))
        return out

    def _grid_for(self, bp: BodyPair) -> PairGrid | None:
        path = _path_joints(self.bodies, bp.a, bp.b)
        n_pairs = bp.n_sphere_pairs
        if path is None or not _GRID_MIN_PAIRS <= n_pairs <= _GRID_MAX_PAIRS:
            return None
        anc, joints = path
        p, q = self.local[bp.ia], self.local[bp.ib]  # each side in its own body frame
        rsum = bp.ra64[:, None] + bp.rb64[None, :]
        relevant = bp.relevant()
        if anc != bp.a:
            p, q, rsum, relevant = q, p, rsum.T, relevant.T
        b = self.bodies
        cols = [int(b.col[j]) for j in joints]
        vcols = self.varying[cols]
        return build_pair_grid(
            [b.consts[j] for j in joints],
            cols,
            [float(b.mult[j]) for j in joints],
            [float(b.off[j]) for j in joints],
            self.kin.lower[vcols].tolist(),
            self.kin.upper[vcols].tolist(),
            p,
            q,
            rsum,
            relevant,
            self.margin,
            _GRID_MIN_FAR,
        )

    def plan(self, culled: list[BodyPair]) -> CullPlan:
        """Group the ``culled`` body pairs that share one side (the same bounding sphere on
        the same body): such a group is first tested as one, that side against a sphere
        around all their other sides (TIAGo's arm: its hand's 30 finger links against each
        link of the rest, 16 groups instead of 656 tests per configuration)."""
        by_side: dict[tuple[int, int, tuple[float, ...]], list[int]] = {}
        for row, bp in enumerate(culled):
            lo = min(bp.a, bp.b)
            key = tuple((bp.bound_a if bp.a == lo else bp.bound_b).tolist())
            by_side.setdefault((lo, max(bp.a, bp.b), key), []).append(row)
        single: list[int] = []
        groups: list[tuple[_Sides, list[int]]] = []
        for (lo, hi, shared), rows in by_side.items():
            if len(rows) < _GROUP_MIN:
                single.extend(rows)
                continue
            other = np.array([_other_side(culled[r], lo) for r in rows])
            c, rad = bounding_sphere(other[:, :3], other[:, 3])
            groups.append((_Sides(lo, hi, np.array(shared), np.array([*c, rad])), rows))
        single_rows = np.array(sorted(single), dtype=np.intp)
        if not groups:
            return CullPlan(tuple(culled), single_rows)
        sides = tuple(g for g, _ in groups)
        return CullPlan(tuple(culled), single_rows, sides, self._table(culled, groups))

    def _table(self, culled: list[BodyPair], groups: list[tuple[_Sides, list[int]]]) -> GroupTable:
        """The groups' members, flattened for :func:`~.cullgroups.grouped_near`."""
        rows = [r for _, members in groups for r in members]
        group = np.repeat(np.arange(len(groups)), [len(m) for _, m in groups])
        sides = [g for g, _ in groups]
        at = zip(rows, group.tolist(), strict=True)
        other = np.array([_other_side(culled[r], sides[g].a) for r, g in at])
        outer = np.array([s.bound_b for s in sides])[group]
        # how far inside the group's sphere each member's side stays
        gap = np.linalg.norm(other[:, :3] - outer[:, :3], axis=1) + other[:, 3]
        return GroupTable(
            lo=np.array([s.a for s in sides], dtype=np.intp),
            hi=np.array([s.b for s in sides], dtype=np.intp),
            shared=np.array([s.bound_a[:3] for s in sides], dtype=np.float32),
            group_reach=np.array([self.reach(s) for s in sides]),
            starts=np.r_[0, np.cumsum([len(m) for _, m in groups])].astype(np.intp),
            row=np.array(rows, dtype=np.intp),
            group=group,
            centre=other[:, :3].astype(np.float32),
            reach=np.array([self.reach(culled[r]) for r in rows]),
            inside=np.maximum(outer[:, 3] - gap, 0.0),
        )

    def culled_near(self, plan: CullPlan, R: F32, t: F32) -> tuple[BoolArray, FloatArray]:
        """For the culled body pairs of ``plan`` and body poses ``R``, ``t`` (:func:`body_fk`
        views of a chunk): the configurations within reach [P, B], and per pair a lower bound
        of the clearance of the others [P]. The pairs of a group are tested where the group
        needs them (:func:`~.cullgroups.grouped_near`): the configurations within reach are
        those of testing every pair everywhere, a group member's bound may be lower."""
        P, B = len(plan.pairs), R.shape[-1]
        near = np.zeros((P, B), dtype=np.bool_)
        low = np.full(P, np.inf)
        if len(plan.single):
            single = [plan.pairs[r] for r in plan.single.tolist()]
            near[plan.single], low[plan.single] = self._near_blocks(single, R, t)
        if plan.table is not None:
            g2 = self.gaps2(R, t, plan.sides)
            rows, cols, low_m = grouped_near(plan.table, g2, R, t, self.margin)
            near[rows, cols] = True
            low[plan.table.row] = low_m
        return near, low

    def _near_blocks(self, pairs: Sequence[Sided], R: F32, t: F32) -> tuple[BoolArray, FloatArray]:
        """:meth:`_near` of ``pairs`` at every configuration, a column block at a time (the
        gaps of the whole chunk are never held at once)."""
        reach = np.array([self.reach(bp) for bp in pairs])
        reach2 = (reach**2).astype(np.float32)[:, None]
        near = np.empty((len(pairs), R.shape[-1]), dtype=np.bool_)
        far_min = np.full(len(pairs), np.inf, dtype=np.float32)
        for sl, g in self._gap_blocks(R, t, pairs):
            np.less_equal(g, reach2, out=near[:, sl])
            np.minimum(far_min, np.min(g, axis=1, where=~near[:, sl], initial=np.inf), out=far_min)
        low: FloatArray = np.sqrt(far_min.astype(np.float64)) - reach + self.margin
        return near, low

    def select(
        self,
        bp: BodyPair,
        q: FloatArray,
        culled: tuple[BoolArray, float] | None,
        bound: FloatArray,
    ) -> IntArray | None:
        """Configurations of the chunk ``q`` to evaluate for ``bp`` (None: all of them).

        ``culled``: the pair's row of :meth:`culled_near` when it is culled. The skipped
        configurations are farther apart than the margin; their clearance lower bound goes
        into ``bound`` [K] (the chunk's bounds).
        """
        if bp.grid is not None:
            near = bp.grid.near(q)
            low = bp.grid.far_bound
        elif bp.cull and culled is not None:
            near, low = culled
        else:
            return None
        sel = np.flatnonzero(near)
        if len(sel) == len(near):
            return None
        for k, _, _ in bp.blocks:
            bound[k] = min(bound[k], low)
        return sel
