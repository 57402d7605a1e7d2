"""The counting engine: float32 verdicts for every body pair, float64 rechecks at the boundary.

:class:`CountEngine` is built once per report (bodies, body pairs, culling, constant pairs) and
then counts chunks of configurations (:meth:`CountEngine.count`):

1. body poses for the whole chunk in float32 (:mod:`.bodies`);
2. per body pair, the configurations that culling keeps (:mod:`.culling`) are evaluated as
   one distance matrix per block (:mod:`.pairs`), giving per frame pair the float32 minimum
   of ``d² − R²``;
3. :func:`.classify.classify` turns those into verdicts, queueing every entry within the
   error bound ``± delta`` of zero (:mod:`.bounds`) and every configuration that may hold a
   frame pair's minimum clearance below the margin (and below the best found so far);
4. the queued entries get a float64 second look along the tree path (:mod:`.sharpen`), and
   those still undecided are re-decided with the reference pair test
   (:func:`~xrdf_tools.selfcollision.collision.frame_pair_verdicts`), so counts equal the
   float64 brute force and clearances are float64-exact.

:class:`EngineTotals` accumulates counts and clearances over chunks (and worker processes).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from ...robot.kinematics import KinematicModel, fk
from ...util.arrays import BoolArray, FloatArray, IntArray, sorted_unique
from ..collision import (
    CULL_SLACK,
    SphereSet,
    frame_pair_verdicts,
    sphere_world_centers,
    squared_distances,
    touching,
)
from .bodies import (
    body_local_centers,
    body_poses,
    body_roots,
    build_bodies,
    joint_values,
    position_error,
    relative_columns,
)
from .classify import Chunk, Evaluated, classify
from .culling import Culler
from .layout import Layout, body_pairs
from .pairs import (
    ChunkPoses,
    evaluate_pair,
    frame_bodies,
    pair_constants,
)
from .reach import Reach
from .sharpen import Sharpener

__all__ = ["CountEngine", "EngineTotals"]

#: What a chunk's arrays may take (bytes, about; with the minima held, 64 MB):
#: :meth:`CountEngine.chunk_limit`.
CHUNK_BYTES = 56 << 20
#: Bytes per configuration of a chunk's other temporaries (a body pair's poses, indices).
_CHUNK_SLACK = 256
#: float32 minima of evaluated body pairs held at once before they are classified (8 MB):
#: a chunk's memory does not grow with its number of body pairs.
_HELD_MINIMA = 1 << 21


class _Steps:
    """Calls ``on_step(done / total)`` each time another tenth of ``total`` items is done."""

    def __init__(self, total: int, on_step: Callable[[float], None] | None) -> None:
        self.total = max(total, 1)
        self.on_step = on_step
        self.next = 1

    def __call__(self, done: int) -> None:
        if self.on_step is not None and 10 * done >= self.next * self.total:
            self.next = 10 * done // self.total + 1
            self.on_step(done / self.total)


@dataclass
class EngineTotals:
    """Per frame pair (``K``): collision counts, exact minimum clearance and its bound.

    ``min_clearance`` is the smallest clearance evaluated exactly (float64); every
    configuration not evaluated exactly has a clearance of at least ``clearance_bound``, so
    the true minimum is ``min_clearance`` when ``min_clearance <= clearance_bound``.
    ``rechecked`` counts (frame pair, configuration) decisions redone in float64.
    """

    hits: npt.NDArray[np.int64]
    min_clearance: FloatArray
    clearance_bound: FloatArray
    configurations: int = 0
    rechecked: int = 0

    @classmethod
    def empty(cls, K: int) -> EngineTotals:
        return cls(np.zeros(K, dtype=np.int64), np.full(K, np.inf), np.full(K, np.inf))

    def clearance(self) -> tuple[FloatArray, BoolArray]:
        """Per frame pair: the minimum clearance and whether it is only a lower bound.

        Exact (float64) whenever the true minimum is below the margin; these values do not
        depend on how the configurations were split into chunks or workers.
        """
        exact = self.min_clearance <= self.clearance_bound
        return np.where(exact, self.min_clearance, self.clearance_bound), ~exact

    def merge(self, other: EngineTotals) -> None:
        """Add ``other`` (another share of the configurations) into these totals."""
        self.hits += other.hits
        np.minimum(self.min_clearance, other.min_clearance, out=self.min_clearance)
        np.minimum(self.clearance_bound, other.clearance_bound, out=self.clearance_bound)
        self.configurations += other.configurations
        self.rechecked += other.rechecked


class CountEngine:
    """Exact per-frame-pair collision counting for configurations that vary ``varying``.

    ``spheres``: the frame pairs to count (e.g. a :meth:`SphereSet.select_frame_pairs`
    selection). ``varying``: indices into the actuated joints that change (the c-space, kept
    as :attr:`cspace`); every other joint stays at ``q_base`` [n]. ``margin``: minimum
    clearances below it are exact (float64), larger ones may come back as lower bounds.

    Of the c-space, only the joints that move some sphere frames relative to others are
    modelled (:attr:`varying`, the c-space's columns :attr:`columns`): a mobile base's joints
    carry every sphere alike and change no distance, so they are held at ``q_base`` (their
    range, ±1e6 m for a base's "no limit", would otherwise swamp the float32 error bounds).
    """

    def __init__(
        self,
        kin: KinematicModel,
        spheres: SphereSet,
        varying: npt.ArrayLike,
        q_base: npt.ArrayLike,
        *,
        margin: float = 0.0,
    ) -> None:
        self.kin = kin
        self.spheres = spheres
        #: the c-space (indices into the actuated joints): the columns of a chunk
        self.cspace = np.asarray(varying, dtype=np.intp)
        #: the c-space columns whose joints move some sphere frames relative to others
        self.columns = relative_columns(kin, self.cspace, spheres.kin_frame)
        self.varying = self.cspace[self.columns]
        self.q_base = np.asarray(q_base, dtype=np.float64).copy()
        self.margin = max(float(margin), 0.0)
        self.K = spheres.n_frame_pairs
        T = fk(kin, self.q_base)  # [F, 4, 4]
        roots, body_of = body_roots(kin, self.varying)
        self.sphere_body, self.local = body_local_centers(kin, spheres, T, roots, body_of)
        max_local = float(np.max(np.linalg.norm(self.local, axis=1))) if len(self.local) else 0.0
        self.bodies = build_bodies(kin, self.varying, T, roots, body_of, max_local)
        self.err = position_error(self.bodies)
        self.culler = Culler(kin, self.varying, self.bodies, self.local, self.margin, self.err)
        self.frame_body = frame_bodies(spheres, self.sphere_body)
        self.const_k, self.const_hit, self.const_clear = self._constant_pairs()
        reach = Reach.of(kin, self.varying, self.bodies)
        layout = body_pairs(
            spheres,
            self.frame_body,
            self.local,
            self.err,
            set(self.const_k.tolist()),
            reach,
            self.margin + CULL_SLACK,
        )
        pairs = layout.pairs
        #: [K] lower bound of the clearance of the sphere pairs that can never come within the
        #: margin (+inf where there are none); they are never evaluated.
        self.reach_bound = np.full(self.K, np.inf)
        for k, low in layout.out_of_reach.items():
            self.reach_bound[k] = low
        #: [K] whether a sphere pair that no joint moves collides, and the smallest clearance
        #: of those pairs (+inf where there are none): decided once, never sampled.
        self.fixed_hit, self.fixed_clear = self._fixed_pairs(layout)
        self.pairs = self.culler.choose(pairs)
        self.cull_plan = self.culler.plan([bp for bp in self.pairs if bp.cull])
        self.sharpener = Sharpener.of(
            self.bodies, spheres, self.local, self.frame_body, kin.n_frames
        )
        self.delta_k, self.rlo_k, self.rhi_k = pair_constants(spheres, self.pairs)
        #: the frame pairs some body pair samples, and each one's row in a chunk's flags
        #: (-1 for the others, whose verdicts are the same in every configuration)
        every = [bp.frame_pairs for bp in self.pairs]
        self.sampled_k = sorted_unique(np.concatenate(every)) if every else np.zeros(0, np.intp)
        self.row_of = np.full(self.K, -1, dtype=np.intp)
        self.row_of[self.sampled_k] = np.arange(len(self.sampled_k))

    @property
    def steps_per_chunk(self) -> int:
        """How many times :meth:`count` calls its ``on_step`` per chunk (at most ten: one per
        tenth of the body pairs, the last at the end)."""
        return min(10, len(self.pairs))

    def chunk_limit(self, *, flags: bool = False) -> int:
        """The most configurations a chunk should hold for its arrays to stay within about
        :data:`CHUNK_BYTES` (a multiple of 1024, between 4,096 and 65,536): per configuration a
        chunk holds the flags of the sampled frame pairs (of every frame pair too with
        ``flags``, as :meth:`count` returns them), the culled pairs' verdicts and their
        groups' gaps, every body's pose and the configuration itself. It depends on the robot
        and the options only."""
        per = len(self.sampled_k) + len(self.cull_plan.pairs) + 52 * self.bodies.n
        per += 5 * len(self.cull_plan.sides)  # a group's squared gap and whether it is near
        per += 16 * len(self.cspace) + _CHUNK_SLACK + (self.K if flags else 0)
        return int(np.clip(CHUNK_BYTES // per // 1024 * 1024, 4096, 65536))

    def reported_clearance(self, totals: EngineTotals) -> tuple[FloatArray, BoolArray]:
        """Per frame pair: the minimum clearance a report shows, and whether it is a bound.

        Exact (float64) below the margin, and for the pairs decided once (their clearance is
        the same in every configuration). Every other pair is only known to stay at least the
        margin apart, and the margin is its bound: the gaps the float32 passes leave behind
        depend on the machine (its BLAS kernels and SIMD width) in their last bits, and on
        which configurations they skipped, so a bound taken from them would not give the same
        bytes on every machine; the margin does.
        """
        value, bound = totals.clearance()
        exact = ~bound & (value < self.margin)
        exact[self.const_k] = True
        return np.where(exact, value, self.margin), ~exact

    def _constant_pairs(self) -> tuple[IntArray, BoolArray, FloatArray]:
        """Frame pairs on one body: decided once, exactly, at the base configuration."""
        s = self.spheres
        fb = self.frame_body
        ks = [k for k in range(self.K) if fb[s.frame_pair_a[k]] == fb[s.frame_pair_b[k]]]
        karr = np.array(ks, dtype=np.intp)
        if not ks:
            return karr, np.zeros(0, dtype=np.bool_), np.zeros(0)
        hit, clr = self._exact(karr, np.zeros(len(ks), dtype=np.intp), self.q_base[None, :])
        return karr, hit, clr

    def _fixed_pairs(self, layout: Layout) -> tuple[BoolArray, FloatArray]:
        """Verdicts and clearances of the sphere pairs whose distance no joint changes, at the
        base configuration, with the reference pair test (exact for every configuration)."""
        hit = np.zeros(self.K, dtype=np.bool_)
        clear = np.full(self.K, np.inf)
        if not layout.fixed_k:
            return hit, clear
        i, j = np.array(layout.fixed_i), np.array(layout.fixed_j)
        k = np.array(layout.fixed_k, dtype=np.intp)
        c = sphere_world_centers(self.kin, self.spheres, self.q_base)
        r = self.spheres.self_radii[i] + self.spheres.self_radii[j]
        d2 = squared_distances(c, i, j)
        np.logical_or.at(hit, k, touching(d2, r))
        np.minimum.at(clear, k, np.sqrt(d2) - r)
        return hit, clear

    # --- per chunk -----------------------------------------------------------------------
    def count(
        self,
        q_var: npt.ArrayLike,
        totals: EngineTotals | None = None,
        *,
        known: FloatArray | None = None,
        on_step: Callable[[float], None] | None = None,
    ) -> BoolArray:
        """Collision flags [K, B] of configurations ``q_var`` [B, len(cspace)] (float64).

        When ``totals`` is given, the chunk's counts and clearances are added to it.
        ``known`` [K]: exact minimum clearances already found in other configurations (of the
        same count); like those of ``totals``, they only narrow the configurations looked at
        for the minimum. The totals are the same with or without them: a frame pair's
        minimum is exact whenever it lies below the margin and below every value known.
        ``on_step(fraction)`` is called as the chunk's body pairs are done (about every tenth
        of them), for progress within a large chunk.
        """
        hits, B = self._count(q_var, totals, known, on_step)
        out = np.zeros((self.K, B), dtype=np.bool_)
        out[self.sampled_k] = hits
        out |= self.fixed_hit[:, None]
        if len(self.const_k):
            out[self.const_k] = self.const_hit[:, None]
        return out

    def count_totals(
        self,
        q_var: npt.ArrayLike,
        totals: EngineTotals,
        *,
        known: FloatArray | None = None,
        on_step: Callable[[float], None] | None = None,
    ) -> None:
        """:meth:`count` into ``totals`` only, without the [K, B] flags: a chunk holds the
        flags of the sampled frame pairs alone."""
        self._count(q_var, totals, known, on_step)

    def _count(
        self,
        q_var: npt.ArrayLike,
        totals: EngineTotals | None,
        known: FloatArray | None,
        on_step: Callable[[float], None] | None,
    ) -> tuple[BoolArray, int]:
        """Flags [len(sampled_k), B] of the sampled frame pairs, and ``B``."""
        q = np.asarray(q_var, dtype=np.float64)
        if q.ndim != 2 or q.shape[1] != len(self.cspace):
            raise ValueError(f"q_var must be [B, {len(self.cspace)}], got {list(q.shape)}")
        if len(self.columns) < len(self.cspace):
            q = q[:, self.columns]
        B = q.shape[0]
        T = body_poses(self.bodies, q)
        poses = ChunkPoses(self.bodies, T, joint_values(self.bodies, q))
        hits = np.zeros((len(self.sampled_k), B), dtype=np.bool_)
        # the best clearance so far only narrows the candidates (it never changes a result)
        prev = self.fixed_clear.copy()
        if totals is not None:
            np.minimum(prev, totals.min_clearance, out=prev)
        if known is not None:
            np.minimum(prev, known, out=prev)
        ch = Chunk(hits, self.row_of, self.reach_bound.copy(), poses, q, prev, self.sharpener)
        if self.cull_plan.pairs:
            near, low = self.culler.culled_near(self.cull_plan, T[:, :, :3], T[:, :, 3])
        done: list[Evaluated] = []
        held = 0  # float32 minima held in ``done``: classified in batches, memory stays bounded
        row = 0
        step = _Steps(len(self.pairs), on_step)
        for i, bp in enumerate(self.pairs):
            rows = (near[row], float(low[row])) if bp.cull else None
            sel = self.culler.select(bp, ch.q, rows, ch.bound)
            row += bp.cull
            if sel is None or len(sel):
                cols = np.arange(B) if sel is None else sel
                done.append(Evaluated(bp, cols, evaluate_pair(bp, ch.poses, sel)))
                held += done[-1].minima.size
            if held >= _HELD_MINIMA:
                classify(ch, done, self.margin, self.rlo_k, self.rhi_k)
                done, held = [], 0
            step(i + 1)
        classify(ch, done, self.margin, self.rlo_k, self.rhi_k)
        best = self.fixed_clear.copy()
        n_exact = self._recheck(ch, best)
        if len(self.const_k):
            best[self.const_k] = self.const_clear
        if totals is not None:
            n = np.zeros(self.K, dtype=np.int64)
            n[self.sampled_k] = hits.sum(axis=1)
            n[self.fixed_hit] = B
            if len(self.const_k):
                n[self.const_k] = np.where(self.const_hit, B, 0)
            totals.hits += n
            np.minimum(totals.min_clearance, best, out=totals.min_clearance)
            np.minimum(totals.clearance_bound, ch.bound, out=totals.clearance_bound)
            totals.configurations += B
            totals.rechecked += n_exact
        return hits, B

    def _recheck(self, ch: Chunk, best: FloatArray) -> int:
        """Decide the queued entries: a float64 look along the tree path first
        (:mod:`.sharpen`), then the reference pair test for the verdicts still within its
        error of zero and the candidates still tied with a frame pair's smallest clearance.
        Exact verdicts go into ``ch.hits``, exact clearances into ``best``. Returns how many
        entries the reference test redid."""
        if not ch.re_k:
            return 0
        B = ch.q.shape[0]
        key = sorted_unique(np.concatenate(ch.re_k).astype(np.int64) * B + np.concatenate(ch.re_b))
        ks, bs = key // B, key % B  # sorted by frame pair, each entry once
        e_min, clear = self.sharpener.evaluate(ks, ch.q[bs])
        sure = np.abs(e_min) > self.sharpener.delta
        ch.hits[self.row_of[ks[sure]], bs[sure]] = e_min[sure] < 0.0
        need = ~sure | self._tied(ks, clear, ch)
        ks, bs = ks[need], bs[need]
        if not len(ks):
            return 0
        ub, inv = np.unique(bs, return_inverse=True)
        qf = np.repeat(self.q_base[None, :], len(ub), axis=0)
        qf[:, self.varying] = ch.q[ub]
        hit, clr = self._exact(ks, inv, qf)
        ch.hits[self.row_of[ks], bs] = hit
        np.minimum.at(best, ks, clr)
        return len(ks)

    def _tied(self, ks: IntArray, clear: FloatArray, ch: Chunk) -> BoolArray:
        """Entries (sorted by frame pair ``ks``) that may hold their frame pair's smallest
        clearance of the chunk below ``min(margin, the best so far)``. The others' clearances
        exceed that of an entry kept, or the frame pair's recorded bound."""
        tau = self.sharpener.tau
        starts = np.flatnonzero(np.r_[True, ks[1:] != ks[:-1]])
        c_min = np.minimum.reduceat(clear, starts)
        k_of = ks[starts]
        lim = np.minimum(self.margin, ch.prev[k_of])
        wanted = c_min - tau <= lim
        low = np.where(wanted, np.inf, c_min - tau)
        ch.bound[k_of] = np.minimum(ch.bound[k_of], low)
        counts = np.diff(np.r_[starts, len(ks)])
        thr = np.repeat(np.where(wanted, c_min + 2.0 * tau, -np.inf), counts)
        tied: BoolArray = clear <= thr
        return tied

    def _exact(
        self, ks: IntArray, rows: IntArray, q_full: FloatArray
    ) -> tuple[BoolArray, FloatArray]:
        """float64 verdicts and clearances of frame pairs ``ks`` at ``q_full[rows]``."""
        return frame_pair_verdicts(self.kin, self.spheres, q_full, ks, rows)
