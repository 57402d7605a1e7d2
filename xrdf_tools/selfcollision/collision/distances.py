"""Distances between spheres: world centres, the pair test, contacts at one configuration.

The pair semantics live here and nowhere else (docs/report.md): spheres ``i`` and ``j`` of a
:class:`~xrdf_tools.selfcollision.collision.spheres.SphereSet` collide when ``‖c_i − c_j‖² < (sr_i +
sr_j)²`` (:func:`touching`, squared so that no square root rounds a verdict) and their clearance is
``‖c_i − c_j‖ − (sr_i + sr_j)``. Everything is float64 and batched:

* :func:`sphere_world_centers` places the spheres for configurations (one GEMM per frame);
* :func:`pair_clearance` / :func:`pair_hits` evaluate every sphere pair of the set;
* :func:`frame_pair_verdicts` decides chosen (frame pair, configuration) entries: the float64
  reference that the engine's float32 path falls back on near the boundary;
* :func:`contacts` / :func:`colliding_frame_pairs` answer "what collides at this q" (lint's
  default-pose rule, viz, the report's default configuration).
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from ...robot.kinematics import KinematicModel, fk_batch_last
from ...util.arrays import BoolArray, FloatArray, IntArray, ragged_index, sorted_unique
from ...xrdf.model import Xrdf
from .spheres import SphereSet, build_sphere_set

__all__ = [
    "Contact",
    "colliding_frame_pairs",
    "colliding_sphere_pairs",
    "contacts",
    "contacts_of_pairs",
    "frame_pair_clearances",
    "frame_pair_verdicts",
    "pair_clearance",
    "pair_hits",
    "sphere_world_centers",
    "squared_distances",
    "touching",
]

#: Sphere-pair evaluations per block of :func:`frame_pair_verdicts` (bounded memory).
_BLOCK_ELEMENTS = 1 << 15
#: Sphere pairs per block of the one-configuration functions (all frame pairs in one flat pass).
_PAIR_BLOCK = 1 << 16
#: float64 pose entries per block of :func:`frame_pair_verdicts` (12 per frame and configuration).
_POSE_ELEMENTS = 1 << 20


# ------------------------------------------------------------------------------------------
# The pair test
# ------------------------------------------------------------------------------------------
def squared_distances(centers: FloatArray, i: IntArray, j: IntArray) -> FloatArray:
    """``‖c_i − c_j‖²`` [..., P] for index arrays ``i``, ``j`` [P] into ``centers`` [..., S, 3]."""
    diff = centers[..., i, :] - centers[..., j, :]
    out: FloatArray = np.einsum("...k,...k->...", diff, diff)
    return out


def touching(d2: FloatArray, radius_sum: FloatArray) -> BoolArray:
    """The collision test of every counter: ``d² < (r_i + r_j)²`` (strict: touching spheres
    with zero clearance do not collide)."""
    out: BoolArray = d2 < radius_sum * radius_sum
    return out


# ------------------------------------------------------------------------------------------
# Plain batched building blocks
# ------------------------------------------------------------------------------------------
def centers_batch_last(
    kin: KinematicModel, spheres: SphereSet, q2: FloatArray, extra: FloatArray | None = None
) -> FloatArray:
    """Sphere centres [S (+ Fs), 3, B]; with ``extra`` [Fs, 3] one more point per frame."""
    S, Fs = spheres.n_spheres, len(spheres.frame_names)
    B = q2.shape[0]
    rows = S + (Fs if extra is not None else 0)
    out = np.empty((rows, 3, B))
    if Fs == 0:
        return out
    if kin.n_frames <= 2 * Fs:
        # all frames: no gather copy, little extra work
        R, t = fk_batch_last(kin, q2)
        fidx = spheres.frame_kin_index.tolist()
    else:
        R, t = fk_batch_last(kin, q2, spheres.frame_kin_index)
        fidx = list(range(Fs))
    for f, kf in enumerate(fidx):
        sl = spheres.spheres_of(f)
        _place(spheres.local_centers[sl], R[kf], t[kf], out[sl])
        if extra is not None:
            _place(extra[f : f + 1], R[kf], t[kf], out[S + f : S + f + 1])
    return out


def _place(local: FloatArray, R: FloatArray, t: FloatArray, out: FloatArray) -> None:
    """``out`` [m, 3, B] = the points ``local`` [m, 3] placed by rotations ``R`` [3, 3, B] and
    translations ``t`` [3, B]: ``out[s, i, b] = Σ_k local[s, k] R[i, k, b] + t[i, b]``, summed
    term by term in a fixed order. Every centre of every counter is computed by this one
    function, so that they agree to the last bit, whichever configurations are placed
    together (a BLAS product's last bit may depend on the batch around a configuration)."""
    term = np.empty_like(out)
    np.multiply(local[:, None, 0, None], R[None, :, 0, :], out=out)
    for k in (1, 2):
        np.multiply(local[:, None, k, None], R[None, :, k, :], out=term)
        out += term
    out += t


def as_q2(kin: KinematicModel, q_full: npt.ArrayLike) -> tuple[FloatArray, bool]:
    q = np.asarray(q_full, dtype=np.float64)
    n = kin.n_actuated
    if q.ndim == 1 and q.shape[0] == n:
        return q[None, :], True
    if q.ndim == 2 and q.shape[1] == n:
        return q, False
    raise ValueError(
        f"q must have shape [{n}] or [B, {n}] (actuated joints: "
        f"{', '.join(kin.actuated_joints) or 'none'}), got {list(q.shape)}"
    )


def sphere_world_centers(
    kin: KinematicModel, spheres: SphereSet, q_full: npt.ArrayLike
) -> FloatArray:
    """World (base-frame) centres [B, S, 3] of the spheres for configurations ``q_full``.

    ``q_full``: [B, n] (or [n], giving [S, 3]) values of every actuated joint, in
    ``kin.actuated_joints`` order (see :func:`~xrdf_tools.robot.kinematics.full_configuration`).
    """
    q2, single = as_q2(kin, q_full)
    c = centers_batch_last(kin, spheres, q2).transpose(2, 0, 1)
    return c[0] if single else np.ascontiguousarray(c)


def pair_clearance(spheres: SphereSet, centers: npt.ArrayLike) -> FloatArray:
    """Signed clearance [B, P] (or [P]) of every sphere pair of the set.

    ``centers``: [B, S, 3] (or [S, 3]). Clearance is ``‖c_i − c_j‖ − (sr_i + sr_j)`` with the
    buffered self-collision radii ``sr``; negative means the pair collides.
    """
    c = np.asarray(centers, dtype=np.float64)
    if c.shape[-2:] != (spheres.n_spheres, 3) or c.ndim not in (2, 3):
        raise ValueError(f"centers must be [B, {spheres.n_spheres}, 3], got {list(c.shape)}")
    d = np.linalg.norm(c[..., spheres.pair_i, :] - c[..., spheres.pair_j, :], axis=-1)
    out: FloatArray = d - spheres.pair_radius_sum
    return out


def pair_hits(spheres: SphereSet, centers: npt.ArrayLike) -> BoolArray:
    """Collision flags [B, P] (or [P]) with the counting comparison :func:`touching`."""
    c = np.asarray(centers, dtype=np.float64)
    return touching(squared_distances(c, spheres.pair_i, spheres.pair_j), spheres.pair_radius_sum)


def frame_pair_verdicts(
    kin: KinematicModel,
    spheres: SphereSet,
    q_full: FloatArray,
    ks: IntArray,
    rows: IntArray,
) -> tuple[BoolArray, FloatArray]:
    """float64 verdict and clearance of frame pair ``ks[e]`` at configuration ``rows[e]``.

    ``q_full`` [U, n]: configurations of every actuated joint. Entry ``e`` asks whether any
    sphere pair of frame pair ``ks[e]`` collides at ``q_full[rows[e]]`` (:func:`touching`)
    and for its smallest clearance. The frames of the asked pairs are posed a block of
    configurations at a time; within a block every frame pair places its two frames' spheres
    only at the configurations asked for it, so the work follows the entries and memory stays
    bounded whatever the number of spheres, frames or entries.
    """
    s = spheres
    hit = np.zeros(len(ks), dtype=np.bool_)
    clr = np.zeros(len(ks))
    if len(ks) == 0:
        return hit, clr
    frames = sorted_unique(np.concatenate([s.frame_pair_a[ks], s.frame_pair_b[ks]]))
    slot = {int(f): i for i, f in enumerate(frames.tolist())}
    step = max(1, _POSE_ELEMENTS // (12 * len(frames)))
    by_row = np.argsort(rows, kind="stable")
    bounds = np.searchsorted(rows[by_row], np.arange(0, len(q_full) + step, step))
    for u0, e0, e1 in zip(range(0, len(q_full), step), bounds[:-1], bounds[1:], strict=False):
        if e0 == e1:
            continue
        R, t = fk_batch_last(kin, q_full[u0 : u0 + step], s.frame_kin_index[frames])
        ents = by_row[e0:e1]
        _decide_block(s, (R, t), slot, ks[ents], rows[ents] - u0, hit, clr, ents)
    return hit, clr


def _decide_block(
    s: SphereSet,
    poses: tuple[FloatArray, FloatArray],
    slot: dict[int, int],
    ks: IntArray,
    rows: IntArray,
    hit: BoolArray,
    clr: FloatArray,
    out_at: IntArray,
) -> None:
    """Entries ``(ks[e], rows[e])`` of one block of posed configurations (``poses``: the
    frames' rotations [nf, 3, 3, w] and translations [nf, 3, w], frame ``f`` at ``slot[f]``):
    the two frames' spheres placed once per entry, then every sphere pair of every entry in
    one flat pass (blocks of about :data:`_PAIR_BLOCK` sphere pairs), reduced per entry."""
    R, t = poses
    where = np.full(len(s.frame_names), -1, dtype=np.intp)
    for f, i in slot.items():
        where[f] = i
    na, nb = s.frame_sizes[s.frame_pair_a[ks]], s.frame_sizes[s.frame_pair_b[ks]]
    for e0, e1 in entry_slices(na * nb + na + nb, _PAIR_BLOCK):
        _decide_entries(s, (R, t), where, ks[e0:e1], rows[e0:e1], hit, clr, out_at[e0:e1])


def _decide_entries(
    s: SphereSet,
    poses: tuple[FloatArray, FloatArray],
    where: IntArray,
    ks: IntArray,
    rows: IntArray,
    hit: BoolArray,
    clr: FloatArray,
    out_at: IntArray,
) -> None:
    """:func:`_decide_block` for a few entries (one large one: in blocks of sphere pairs)."""
    R, t = poses
    start = s.frame_start
    fa, fb = s.frame_pair_a[ks], s.frame_pair_b[ks]
    na, nb = s.frame_sizes[fa], s.frame_sizes[fb]
    pa = _place_each(s, start[fa], na, R[where[fa], :, :, rows], t[where[fa], :, rows])
    pb = _place_each(s, start[fb], nb, R[where[fb], :, :, rows], t[where[fb], :, rows])
    a_at, b_at = np.cumsum(na) - na, np.cumsum(nb) - nb  # each entry's first placed sphere
    m = na * nb
    offs = np.cumsum(m) - m
    for p0 in range(0, int(m.sum()), _PAIR_BLOCK):
        rep, pos = _entries_of(m, offs, p0)
        row, col = np.divmod(pos, nb[rep])
        diff = pa[a_at[rep] + row] - pb[b_at[rep] + col]
        d2 = np.einsum("...k,...k->...", diff, diff)
        rs = s.self_radii[start[fa[rep]] + row] + s.self_radii[start[fb[rep]] + col]
        first = np.flatnonzero(np.r_[True, rep[1:] != rep[:-1]])
        at = out_at[rep[first]]
        h = np.logical_or.reduceat(touching(d2, rs), first)
        c = np.minimum.reduceat(np.sqrt(d2) - rs, first)
        fresh = pos[first] == 0  # the entry's first sphere pairs: overwrite
        hit[at] = np.where(fresh, h, hit[at] | h)
        clr[at] = np.where(fresh, c, np.minimum(clr[at], c))


def entry_slices(cost: IntArray, limit: int) -> Iterator[tuple[int, int]]:
    """Consecutive ranges ``(e0, e1)`` of entries whose ``cost`` adds up to at most ``limit``
    (an entry that costs more alone): work in bounded memory, in few numpy calls."""
    ends = np.cumsum(cost)
    e0 = 0
    while e0 < len(cost):
        base = int(ends[e0 - 1]) if e0 else 0
        e1 = max(e0 + 1, int(np.searchsorted(ends, base + limit, side="right")))
        yield e0, e1
        e0 = e1


def _entries_of(m: IntArray, offs: IntArray, p0: int) -> tuple[IntArray, IntArray]:
    """For the flat sphere pairs ``p0 … p0 + _PAIR_BLOCK`` of entries with ``m`` [E] sphere
    pairs each starting at ``offs`` [E]: each one's entry and its index within the entry."""
    flat = np.arange(p0, min(int(m.sum()), p0 + _PAIR_BLOCK))
    which = np.searchsorted(offs, flat, side="right") - 1
    return which, flat - offs[which]


def _place_each(
    s: SphereSet, first: IntArray, count: IntArray, R: FloatArray, t: FloatArray
) -> FloatArray:
    """The spheres ``first[e] … first[e] + count[e]`` placed by ``R[e]`` [3, 3] and ``t[e]``
    [3], entry after entry [Σ count, 3], summed term by term as :func:`_place` does (the same
    bits)."""
    e, rank = ragged_index(count)
    local = s.local_centers[first[e] + rank]
    Rk, tk = R[e], t[e]
    out: FloatArray = local[:, 0, None] * Rk[:, :, 0]
    for k in (1, 2):
        out += local[:, k, None] * Rk[:, :, k]
    out += tk
    return out


# ------------------------------------------------------------------------------------------
# One configuration: what collides?
# ------------------------------------------------------------------------------------------
# ------------------------------------------------------------------------------------------
# One configuration: what collides?
# ------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Contact:
    """A colliding frame pair at one configuration.

    ``clearance`` (negative, metres) is that of the worst sphere pair, ``sphere_a`` and
    ``sphere_b`` its positions in the frames' sphere lists; ``n_sphere_pairs`` counts the
    colliding sphere pairs of the frame pair. ``masked`` is True when ``ignore`` disables the
    pair (only reported when asked for).
    """

    frame_a: str
    frame_b: str
    clearance: float
    sphere_a: int
    sphere_b: int
    n_sphere_pairs: int = 1
    masked: bool = False


def _sphere_pair_blocks(
    spheres: SphereSet, c: FloatArray
) -> Iterator[tuple[IntArray, IntArray, IntArray, FloatArray, FloatArray]]:
    """Every sphere pair of every frame pair, in the flat order (frame pair by frame pair,
    row-major), in blocks of at most :data:`_PAIR_BLOCK`: ``(k, i, j, diff, rs)`` with the
    frame pair [m], the two spheres [m], centre differences [m, 3] and radius sums [m]."""
    s = spheres
    total = s.n_pairs
    for p0 in range(0, total, _PAIR_BLOCK):
        p = np.arange(p0, min(total, p0 + _PAIR_BLOCK))
        k = np.searchsorted(s.pair_start, p, side="right") - 1
        fa, fb = s.frame_pair_a[k], s.frame_pair_b[k]
        a0, b0 = s.frame_start[fa], s.frame_start[fb]
        row, col = np.divmod(p - s.pair_start[k], s.frame_sizes[fb])
        i, j = a0 + row, b0 + col
        yield k, i, j, c[i] - c[j], s.self_radii[i] + s.self_radii[j]


def _runs(k: IntArray) -> IntArray:
    """Where each run of equal values of ``k`` starts."""
    out: IntArray = np.flatnonzero(np.r_[True, k[1:] != k[:-1]])
    return out


def frame_pair_clearances(spheres: SphereSet, centers: npt.ArrayLike) -> FloatArray:
    """Smallest clearance [K] of every frame pair at one configuration's centres [S, 3]
    (+inf for a frame pair without sphere pairs), in bounded memory."""
    c = _one_configuration(spheres, centers)
    out = np.full(spheres.n_frame_pairs, np.inf)
    for k, _, _, diff, rs in _sphere_pair_blocks(spheres, c):
        starts = _runs(k)
        low = np.minimum.reduceat(np.linalg.norm(diff, axis=-1) - rs, starts)
        np.minimum(out[k[starts]], low, out=low)
        out[k[starts]] = low
    return out


def colliding_sphere_pairs(
    spheres: SphereSet, centers: npt.ArrayLike
) -> list[tuple[int, int, int, float]]:
    """``(frame pair, sphere i, sphere j, clearance)`` of every colliding sphere pair at one
    configuration's centres [S, 3] (:func:`touching`), in frame-pair order, bounded memory."""
    c = _one_configuration(spheres, centers)
    out: list[tuple[int, int, int, float]] = []
    for k, i, j, diff, rs in _sphere_pair_blocks(spheres, c):
        (at,) = np.nonzero(touching(np.einsum("...k,...k->...", diff, diff), rs))
        clr = np.linalg.norm(diff[at], axis=-1) - rs[at]
        out.extend(zip(k[at].tolist(), i[at].tolist(), j[at].tolist(), clr.tolist(), strict=True))
    return out


def _one_configuration(spheres: SphereSet, centers: npt.ArrayLike) -> FloatArray:
    c = np.asarray(centers, dtype=np.float64)
    if c.shape != (spheres.n_spheres, 3):
        raise ValueError(f"centers must be [{spheres.n_spheres}, 3], got {list(c.shape)}")
    return c


def contacts(spheres: SphereSet, centers: npt.ArrayLike) -> list[Contact]:
    """Colliding frame pairs of ``spheres`` for one configuration's centres [S, 3].

    One :class:`Contact` per colliding frame pair of the set (masked pairs only if the set
    was built with ``include_masked=True``), worst (most negative clearance) first. Memory
    stays bounded whatever the number of spheres per frame.
    """
    return contacts_of_pairs(spheres, colliding_sphere_pairs(spheres, centers))


def contacts_of_pairs(
    spheres: SphereSet, found: Sequence[tuple[int, int, int, float]]
) -> list[Contact]:
    """The :func:`contacts` of one configuration from its :func:`colliding_sphere_pairs`
    ``found`` (for a caller that needs both: the pairs are computed once)."""
    worst: dict[int, tuple[float, int, int, int]] = {}
    for k, i, j, clr in found:
        old = worst.get(k)
        if old is None:
            worst[k] = (clr, i, j, 1)
        else:
            best = (clr, i, j) if clr < old[0] else old[:3]
            worst[k] = (*best, old[3] + 1)
    out = [
        Contact(
            frame_a=spheres.frame_names[spheres.frame_pair_a[k]],
            frame_b=spheres.frame_names[spheres.frame_pair_b[k]],
            clearance=clr,
            sphere_a=int(spheres.sphere_index[i]),
            sphere_b=int(spheres.sphere_index[j]),
            n_sphere_pairs=n,
            masked=bool(spheres.frame_pair_masked[k]),
        )
        for k, (clr, i, j, n) in worst.items()
    ]
    out.sort(key=lambda c_: (c_.clearance, c_.frame_a, c_.frame_b))
    return out


def colliding_frame_pairs(
    kin: KinematicModel,
    xrdf: Xrdf,
    q_full: npt.ArrayLike,
    *,
    include_masked: bool = False,
) -> list[Contact]:
    """Frame pairs in self-collision at one configuration ``q_full`` [n], worst first.

    ``q_full`` holds every actuated joint of ``kin`` (e.g. from
    :func:`~xrdf_tools.robot.kinematics.default_configuration`). Masked pairs are skipped unless
    ``include_masked``. For repeated queries build the :class:`SphereSet` once and use
    :func:`sphere_world_centers` + :func:`contacts`.
    """
    spheres, _ = build_sphere_set(kin, xrdf, include_masked=include_masked)
    q2, single = as_q2(kin, q_full)
    if not single:
        raise ValueError("colliding_frame_pairs takes one configuration [n]")
    return contacts(spheres, sphere_world_centers(kin, spheres, q2[0]))
