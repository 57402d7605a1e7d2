"""A chunk's verdicts from the float32 minima, and the entries queued for the float64 recheck.

After every body pair of a chunk is evaluated (:func:`~.pairs.evaluate_pair`), :func:`classify`
turns their float32 minima of ``d² − R²`` into verdicts: entries below ``−delta`` collide,
entries within ``± delta`` of zero are unsure and queued. For the minimum clearance, every
configuration that may hold a frame pair's smallest clearance below ``min(margin, an upper bound
of the chunk's smallest, the best so far)`` is queued too (:func:`_minimum_candidates`), and
every configuration left out has a clearance of at least the bound recorded for its frame pair.
The thresholds of every block of every body pair are computed together, in one vectorised pass.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ...util.arrays import BoolArray, FloatArray, IntArray
from .bodies import F32
from .bounds import clearance_hi, clearance_lo, energy_at
from .pairs import (
    BodyPair,
    ChunkPoses,
    pair_transform,
    sphere_pair_clearances,
    sphere_pair_minima,
)
from .sharpen import Sharpener

__all__ = ["Chunk", "Evaluated", "classify"]

#: Blocks with at most this many candidates for the minimum queue them all for the float64
#: look (:mod:`.sharpen`, a few µs each) instead of narrowing them first (about 100 µs).
_FEW_CANDIDATES = 4
#: A block still left with more candidates than this after the float32 narrowing (a sphere
#: near a joint axis: its clearance changes less than the float32 error) narrows them again
#: in float64 on the few sphere pairs that can hold the minimum.
_MANY_TIED = 64
#: float64 sphere-pair clearances computed per block of that narrowing (bounded memory).
_TIED_BLOCK = 1 << 15


@dataclass
class Chunk:
    """One chunk: verdicts of the sampled frame pairs [K_s, B] (frame pair ``k`` in row
    ``row_of[k]``), clearance bounds [K], body poses, the configurations, the best exact
    clearances known before it [K], and the (frame pair, configuration) entries queued for
    the float64 recheck."""

    hits: BoolArray
    row_of: IntArray = field(repr=False)
    bound: FloatArray
    poses: ChunkPoses = field(repr=False)
    q: FloatArray = field(repr=False)
    prev: FloatArray = field(repr=False)
    sharpener: Sharpener = field(repr=False)
    re_k: list[IntArray] = field(default_factory=list, repr=False)
    re_b: list[IntArray] = field(default_factory=list, repr=False)


@dataclass(frozen=True, eq=False)
class Evaluated:
    """The float32 minima [blocks, n] of body pair ``bp`` at the chunk's configurations
    ``cols`` [n]."""

    bp: BodyPair
    cols: IntArray
    minima: F32


def classify(
    ch: Chunk, done: list[Evaluated], margin: float, rlo_k: FloatArray, rhi_k: FloatArray
) -> None:
    """Record the verdicts of ``done`` in ``ch`` and queue what float32 cannot decide.

    ``rlo_k``, ``rhi_k`` [K]: the smallest and largest radius sum of each frame pair.
    """
    if not done:
        return
    ks = np.concatenate([ev.bp.frame_pairs for ev in done])
    delta = np.repeat([ev.bp.delta for ev in done], [len(ev.bp.blocks) for ev in done])
    e_min = np.concatenate([ev.minima.min(axis=1) for ev in done]).astype(np.float64)
    rlo, rhi = rlo_k[ks], rhi_k[ks]
    thr = np.minimum(margin, clearance_hi(e_min + delta, rlo, rhi))
    np.minimum(thr, ch.prev[ks], out=thr)
    e_star = (energy_at(thr, rlo, rhi) + delta).astype(np.float32)
    has_cand = np.empty(len(ks), dtype=np.bool_)
    start = 0
    for ev in done:
        sl = slice(start, start + len(ev.bp.blocks))
        start = sl.stop
        has_cand[sl] = _classify_pair(ch, ev, e_star[sl], thr[sl], margin)
    # configurations that are not candidates are above thr (a lower bound of the others)
    low = np.where(has_cand, thr, clearance_lo(e_min - delta, rlo, rhi))
    np.minimum.at(ch.bound, ks, low)


def _classify_pair(
    ch: Chunk, ev: Evaluated, e_star: F32, thr: FloatArray, margin: float
) -> BoolArray:
    """Verdicts and queued entries of one body pair; whether each block has candidates for
    the minimum (values at most ``e_star``: a clearance that may lie below ``thr``)."""
    bp, em, cols = ev.bp, ev.minima, ev.cols
    d = np.float32(bp.delta)
    bi, bj = np.nonzero(em < -d)
    ch.hits[ch.row_of[bp.frame_pairs[bi]], cols[bj]] = True  # (a frame pair may span several)
    cand = em <= e_star[:, None]
    has_cand: BoolArray = np.any(cand, axis=1)
    queued = np.abs(em) <= d
    for i in np.flatnonzero(has_cand).tolist():
        at = np.flatnonzero(cand[i])
        if len(at) <= _FEW_CANDIDATES:  # cheaper to look at each in float64 at once
            queued[i, at] = True
            continue
        trel = pair_transform(bp, ch.poses, cols[at])
        queued[i, at] |= _minimum_candidates(bp, ch, trel, cols[at], i, float(thr[i]), margin)
    bi, bj = np.nonzero(queued)
    if len(bi):
        ch.re_k.append(bp.frame_pairs[bi])
        ch.re_b.append(cols[bj])
    return has_cand


def _minimum_candidates(
    bp: BodyPair, ch: Chunk, trel: F32, at: IntArray, i: int, thr: float, margin: float
) -> BoolArray:
    """Which of the chunk's configurations ``at`` [n] (poses ``trel`` [3, 4, n]) may hold
    block ``i``'s smallest clearance below ``thr`` (at most the margin and the best so far;
    the other configurations of the chunk are above it).

    ``d² − R²`` ranks the configurations of one sphere pair as its clearance does, but not
    those of sphere pairs with other radii. So each sphere pair's smallest value bounds its
    smallest clearance from both sides (within ``delta``, with its own radius sum); the
    block's smallest clearance is at most the least upper bound, and only the sphere pairs
    whose lower bound does not exceed it can hold it. Only their clearances are computed
    directly (float32, error ``tau``); when more than :data:`_MANY_TIED` configurations still
    tie within that error, those again in float64 (:func:`_clearances64`). The configurations
    left out have a clearance above the
    limit recorded in the frame pair's bound.
    """
    k, rows, cs = bp.blocks[i]
    e = sphere_pair_minima(bp, trel, rows, cs).astype(np.float64)
    r = bp.ra64[rows, None] + bp.rb64[None, cs]
    r2 = r * r
    c_hi = np.sqrt(np.maximum(e + bp.delta + r2, 0.0)) - r
    lim = min(thr, margin, float(c_hi.min()))
    c_lo = np.sqrt(np.maximum(e - bp.delta + r2, 0.0)) - r
    ii, jj = np.nonzero(c_lo <= lim)
    if not len(ii):  # every configuration is above thr, which the bound holds already
        return np.zeros(trel.shape[-1], dtype=np.bool_)
    ia, ib = ii + rows.start, jj + cs.start
    clr = sphere_pair_clearances(bp, trel, ia, ib).min(axis=0)
    lim = min(lim, float(clr.min()) + bp.tau)
    ch.bound[k] = min(ch.bound[k], lim)
    kept: BoolArray = clr - bp.tau <= lim
    if np.count_nonzero(kept) > _MANY_TIED:
        tied = np.flatnonzero(kept)
        clr64 = _clearances64(bp, ch.sharpener, ch.q[at[tied]], ia, ib)
        tau = ch.sharpener.tau
        lim = min(lim, float(clr64.min()) + tau)
        ch.bound[k] = min(ch.bound[k], lim)
        kept[tied] = clr64 - tau <= lim
    return kept


def _clearances64(
    bp: BodyPair, sharpener: Sharpener, q: FloatArray, ia: IntArray, ib: IntArray
) -> FloatArray:
    """float64 smallest clearance [n] of the sphere pairs (``ia``, ``ib``) (rows of ``a``'s and
    of ``b``'s spheres in ``bp``) at the configurations ``q`` [n, varying], with the pose of
    ``b`` in ``a``'s frame composed along the tree path as :mod:`.sharpen` does (within
    ``sharpener.tau`` of the reference's clearance)."""
    pa = sharpener.local[bp.ia[ia]]  # [m, 3]
    pb = sharpener.local[bp.ib[ib]]
    rsum = bp.ra64[ia] + bp.rb64[ib]
    out = np.empty(len(q))
    step = max(1, _TIED_BLOCK // len(ia))
    for s0 in range(0, len(q), step):
        R, t = sharpener.relative(bp.a, bp.b, q[s0 : s0 + step])
        diff = np.einsum("nij,mj->nmi", R, pb) + t[:, None, :] - pa[None]
        d = np.sqrt(np.einsum("nmk,nmk->nm", diff, diff))
        out[s0 : s0 + step] = (d - rsum).min(axis=1)
    return out
