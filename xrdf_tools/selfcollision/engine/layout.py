"""Layout: the engine's frame pairs cut into body pairs, each one distance matrix.

:func:`body_pairs` groups the frame pairs that are not constant by their two bodies, drops
the spheres that can never come within the margin of the other body (:mod:`.reach`) and cuts
a side with many spheres (or the static body, which holds everything the c-space does not
move) into its frames, so that each part is culled with its own bounding sphere
(:mod:`.culling`). A frame pair may thus be spread over several body pairs; the engine takes
the smallest value over its parts and OR-s their verdicts. Every part is laid out as
:class:`~.pairs._BodyPair` expects: rows and columns one contiguous segment per frame.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ...util.arrays import BoolArray, FloatArray, IntArray
from ..collision import CULL_SLACK, SphereSet, bounding_sphere
from .bodies import EPS32, F32, body_chains, chain_error
from .bounds import energy_error
from .pairs import BodyPair
from .reach import Meet, Reach

#: Body pairs at most this many joints apart have their relative pose composed from those
#: joints (a float32 error that follows the pair, not the whole robot).
_LOCAL_JOINTS = 2
#: A side with more spheres than this is cut into its frames.
_SPLIT_SPHERES = 48
#: At most this many spheres of one frame in one part (a large link is cut into pieces).
_MAX_SIDE = 512
#: Frames of a side that is cut are packed into parts of at most this many spheres.
_PACK_SPHERES = 16


@dataclass
class Layout:
    """The engine's sampled work and what was decided without sampling.

    ``pairs``: the body pairs to evaluate. ``out_of_reach``: per frame pair that lost sphere
    pairs to :meth:`Reach.prune`, a lower bound of their clearance (a frame pair that lost all
    of them is in no body pair: it cannot come within the limit). ``fixed_i``/``fixed_j``/
    ``fixed_k``: sphere pairs whose distance no joint changes (:meth:`Reach.on_axis`) and their
    frame pairs; they are decided once and never sampled.
    """

    pairs: list[BodyPair] = field(default_factory=list)
    out_of_reach: dict[int, float] = field(default_factory=dict)
    fixed_i: list[int] = field(default_factory=list)
    fixed_j: list[int] = field(default_factory=list)
    fixed_k: list[int] = field(default_factory=list)


def body_pairs(
    spheres: SphereSet,
    frame_body: IntArray,
    local: FloatArray,
    err: float,
    skip: set[int],
    reach: Reach,
    limit: float,
) -> Layout:
    """The frame pairs of ``spheres`` (except those in ``skip``) laid out as body pairs.

    ``frame_body`` [Fs]: each frame's body; ``local`` [S, 3]: each sphere's centre in its
    body frame; ``err``: the float32 position error bound (:func:`~.bodies._position_error`).
    """
    s = spheres
    groups: dict[tuple[int, int], list[int]] = {}
    for k in range(s.n_frame_pairs):
        if k in skip:
            continue
        ba, bb = int(frame_body[s.frame_pair_a[k]]), int(frame_body[s.frame_pair_b[k]])
        groups.setdefault((min(ba, bb), max(ba, bb)), []).append(k)
    out = Layout()
    sides: dict[bytes, _Side] = {}
    for meet, ks in zip(reach.meets(list(groups)), groups.values(), strict=True):
        out.pairs.extend(_split_pair(s, frame_body, local, err, reach, limit, meet, ks, out, sides))
    return out


def _split_pair(
    s: SphereSet,
    frame_body: IntArray,
    local: FloatArray,
    err: float,
    reach: Reach,
    limit: float,
    meet: Meet,
    ks: list[int],
    layout: Layout,
    sides: dict[bytes, _Side],
) -> list[BodyPair]:
    a, b = meet.a, meet.b
    side: dict[int, list[int]] = {a: [], b: []}
    for k in ks:
        for f in (int(s.frame_pair_a[k]), int(s.frame_pair_b[k])):
            if f not in side[int(frame_body[f])]:
                side[int(frame_body[f])].append(f)
    ia, wa = _side_rows(s, side[a])
    ib, wb = _side_rows(s, side[b])
    r = s.self_radii
    pa, pb = reach.prune(meet, local[ia], r[ia], local[ib], r[ib], limit)
    fixed_a, fixed_b = reach.on_axis(a, b, local[ia], local[ib])
    sampled_a, sampled_b = pa.keep & ~fixed_a, pb.keep & ~fixed_b
    fix_a, fix_b = pa.keep & fixed_a, pb.keep & fixed_b
    any_fixed = bool(fix_a.any() or fix_b.any())
    # per frame of each side: the smallest gap of its dropped spheres, whether it has sampled ones
    gap_a = {f: float(pa.gap[sl].min()) for f, sl in wa.items()}
    gap_b = {f: float(pb.gap[sl].min()) for f, sl in wb.items()}
    any_a = {f: bool(sampled_a[sl].any()) for f, sl in wa.items()}
    any_b = {f: bool(sampled_b[sl].any()) for f, sl in wb.items()}
    kept: list[tuple[int, int, int]] = []  # (frame pair, frame on a, frame on b)
    for k in ks:
        fa, fb = int(s.frame_pair_a[k]), int(s.frame_pair_b[k])
        if fa not in wa:
            fa, fb = fb, fa
        low = min(gap_a[fa], gap_b[fb])
        if low < np.inf:
            layout.out_of_reach[k] = low
        if any_fixed:
            _fix(layout, k, ia[wa[fa]], ib[wb[fb]], fix_a[wa[fa]], pb.keep[wb[fb]])
            _fix(layout, k, ib[wb[fb]], ia[wa[fa]], fix_b[wb[fb]], sampled_a[wa[fa]])
        if any_a[fa] and any_b[fb]:
            kept.append((k, fa, fb))
    keep = set(ia[sampled_a].tolist()) | set(ib[sampled_b].tolist())
    parts_a, parts_b = _both_parts(s, (a, b), kept, keep, local)
    # the frame pairs of each (part of a, part of b), in the order of ``kept``
    part_of_a, part_of_b = _part_index(parts_a), _part_index(parts_b)
    by_parts: dict[tuple[int, int], list[tuple[int, int, int]]] = {}
    for k, fa, fb in kept:
        for at_a in part_of_a[fa]:
            for at_b in part_of_b[fb]:
                by_parts.setdefault((at_a, at_b), []).append((k, fa, fb))
    made = (parts_a, parts_b)
    return _assemble_parts(s, local, err, reach, meet, made, by_parts, sides)


def _assemble_parts(
    s: SphereSet,
    local: FloatArray,
    err: float,
    reach: Reach,
    meet: Meet,
    parts: tuple[list[tuple[set[int], set[int]]], list[tuple[set[int], set[int]]]],
    by_parts: dict[tuple[int, int], list[tuple[int, int, int]]],
    sides: dict[bytes, _Side],
) -> list[BodyPair]:
    """One body pair per (part of ``a``, part of ``b``) with frame pairs between them; each
    side (the same spheres of the same frames) is made once, however many body pairs it is
    in (``sides``: those made so far, shared by every body pair of the layout)."""

    def side(which: int, at: int) -> _Side:
        frames, keep = parts[which][at]
        return _side(s, local, frames, keep, sides)

    out = []
    for at_a in range(len(parts[0])):
        for at_b in range(len(parts[1])):
            mine = by_parts.get((at_a, at_b))
            if mine:
                out.append(_assemble(err, reach, meet, (side(0, at_a), side(1, at_b)), mine))
    return out


def _part_index(parts: list[tuple[set[int], set[int]]]) -> dict[int, list[int]]:
    """The parts (indices into ``parts``) each frame belongs to (a large frame: several)."""
    out: dict[int, list[int]] = {}
    for i, (frames, _) in enumerate(parts):
        for f in frames:
            out.setdefault(f, []).append(i)
    return out


def _fix(
    layout: Layout, k: int, mine: IntArray, theirs: IntArray, fixed: BoolArray, other: BoolArray
) -> None:
    """Record the sphere pairs of frame pair ``k`` between the fixed spheres of one side and
    the kept spheres of the other (each such pair once)."""
    for i in mine[fixed].tolist():
        for j in theirs[other].tolist():
            layout.fixed_i.append(i)
            layout.fixed_j.append(j)
            layout.fixed_k.append(k)


def _both_parts(
    s: SphereSet,
    key: tuple[int, int],
    kept: list[tuple[int, int, int]],
    keep: set[int],
    local: FloatArray,
) -> tuple[list[tuple[set[int], set[int]]], list[tuple[set[int], set[int]]]]:
    """The parts of both sides of a body pair (:func:`_parts`). When both sides are moving
    and cut into several parts (two hands of 30 finger links each: 900 body pairs), nearby
    frames are packed into parts of at most :data:`_PACK_SPHERES` spheres on both sides."""
    a, b = key
    frames_a = sorted({fa for _, fa, _ in kept})
    frames_b = sorted({fb for _, _, fb in kept})
    parts_a = _parts(s, a, frames_a, keep, local, 0)
    parts_b = _parts(s, b, frames_b, keep, local, 0)
    if a != 0 and b != 0 and len(parts_a) > 1 and len(parts_b) > 1:
        parts_a = _parts(s, a, frames_a, keep, local, _PACK_SPHERES)
        parts_b = _parts(s, b, frames_b, keep, local, _PACK_SPHERES)
    return parts_a, parts_b


def _parts(
    s: SphereSet, body: int, frames: list[int], keep: set[int], local: FloatArray, pack: int
) -> list[tuple[set[int], set[int]]]:
    """The frames of one side as parts ``(frames, spheres)`` when the side is the static body
    or holds many spheres, so that each part is culled with its own bounding sphere and a
    distance block stays small: one part per frame, or with ``pack``, frames near each other
    (``local``: sphere centres in the body frame) packed into parts of at most ``pack``
    spheres; a frame with more is cut into pieces of at most :data:`_MAX_SIDE`."""
    mine = {
        f: [i for i in range(*s.spheres_of(f).indices(s.n_spheres)) if i in keep] for f in frames
    }
    if body != 0 and sum(len(v) for v in mine.values()) <= _SPLIT_SPHERES:
        return [(set(frames), keep)]
    out = [
        ({f}, set(idx[i : i + _MAX_SIDE]))
        for f, idx in mine.items()
        if len(idx) > pack
        for i in range(0, len(idx), _MAX_SIDE)
    ]
    small = [f for f, idx in mine.items() if 0 < len(idx) <= pack]
    centre = {f: local[mine[f]].mean(axis=0) for f in small}
    while small:  # the first frame left and the frames nearest to it, while they fit
        first = small.pop(0)
        near = sorted(small, key=lambda f: float(np.linalg.norm(centre[f] - centre[first])))
        part, size = {first}, len(mine[first])
        for f in near:
            if size + len(mine[f]) <= pack:
                part.add(f)
                size += len(mine[f])
        small = [f for f in small if f not in part]
        out.append((part, {i for f in part for i in mine[f]}))
    return out


@dataclass(frozen=True, eq=False)
class _Side:
    """One side of body pairs: its spheres (``idx``, each frame's slice of them in ``where``,
    the first row of each frame in ``starts``), their centres in the body frame and radii,
    its bounding sphere, and what :class:`BodyPair` holds of it as either side: ``p_aug``
    and ``p32`` as side ``a``, ``q_aug``, ``r32`` and ``r2_32`` as side ``b``
    (:class:`~.pairs.BodyPair`); ``reach`` is the largest distance of a centre from the body
    origin."""

    idx: IntArray
    where: dict[int, slice]
    starts: IntArray
    centres: FloatArray
    radii: FloatArray
    bound: FloatArray
    p_aug: F32
    p32: F32
    q_aug: F32
    r32: F32
    r2_32: F32
    reach: float
    r_max: float


def _side(
    s: SphereSet,
    local: FloatArray,
    frames: set[int],
    keep: set[int],
    made: dict[bytes, _Side],
) -> _Side:
    """The spheres of ``frames`` that are in ``keep``, as one side of body pairs (from
    ``made`` when a body pair before had the same side)."""
    idx, where = _side_rows(s, sorted(frames), keep)
    key = idx.tobytes()  # the spheres give their frames' slices
    if key not in made:
        made[key] = _new_side(s, local, idx, where)
        for value in vars(made[key]).values():  # shared by body pairs: never written
            if isinstance(value, np.ndarray):
                value.flags.writeable = False
    return made[key]


def _new_side(s: SphereSet, local: FloatArray, idx: IntArray, where: dict[int, slice]) -> _Side:
    p, r = local[idx], s.self_radii[idx]
    p_aug = np.hstack(
        [
            -2.0 * p,
            np.ones((len(p), 1)),
            (np.sum(p * p, axis=1) - r * r)[:, None],
            -2.0 * r[:, None],
        ]
    )
    return _Side(
        idx=idx,
        where=where,
        starts=np.array(sorted(sl.start for sl in where.values()), dtype=np.intp),
        centres=p,
        radii=r,
        bound=_bound(p, r),
        p_aug=p_aug.astype(np.float32),
        p32=p.astype(np.float32),
        q_aug=np.hstack([p, np.ones((len(p), 1))]).astype(np.float32),
        r32=r[:, None].astype(np.float32),
        r2_32=(r * r)[:, None].astype(np.float32),
        reach=float(np.max(np.linalg.norm(p, axis=1))) if len(p) else 0.0,
        r_max=float(r.max()) if len(r) else 0.0,
    )


def _assemble(
    err: float,
    reach: Reach,
    meet: Meet,
    sides: tuple[_Side, _Side],
    kept: list[tuple[int, int, int]],
) -> BodyPair:
    a, b = meet.a, meet.b
    sa, sb = sides
    blocks = [(k, sa.where[fa], sb.where[fb]) for k, fa, fb in kept]
    if len(sb.idx) > len(sa.idx):  # the side with more spheres stays put (fewer to transform)
        sa, sb, a, b = sb, sa, b, a
        blocks = [(k, cols, rows) for k, rows, cols in blocks]
    tau = 2.0 * err + 8.0 * EPS32 * reach.bodies.lever  # through the world frame
    path: tuple[tuple[int, ...], tuple[int, ...]] | None = None
    if meet.joints <= _LOCAL_JOINTS:
        path = body_chains(reach.bodies, a, b)
        reach_max = max(sa.reach, sb.reach)
        err_path, lever = chain_error(reach.bodies, path, reach.travel(), reach_max)
        tau_path = 2.0 * err_path + 8.0 * EPS32 * lever
        if tau_path < tau:
            err, tau = err_path, tau_path
        else:
            path = None
    return BodyPair(
        a=a,
        b=b,
        ia=sa.idx,
        ib=sb.idx,
        p_aug=sa.p_aug,
        q_aug=sb.q_aug,
        ra64=sa.radii,
        rb64=sb.radii,
        r_b=sb.r32,
        r2_b=sb.r2_32,
        blocks=tuple(blocks),
        row_starts=sa.starts,
        col_starts=sb.starts,
        seg_a=np.searchsorted(sa.starts, [rw.start for _, rw, _ in blocks]).astype(np.intp),
        seg_b=np.searchsorted(sb.starts, [cl.start for _, _, cl in blocks]).astype(np.intp),
        p32=sa.p32,
        delta=energy_error(sa.reach, sa.r_max + sb.r_max, err),
        bound_a=sa.bound,
        bound_b=sb.bound,
        path=path,
        tau=tau,
    )


def _bound(centers: FloatArray, radii: FloatArray) -> FloatArray:
    c, rad = bounding_sphere(centers, radii)
    return np.array([*c, rad + CULL_SLACK])


def _side_rows(
    s: SphereSet, frames: list[int], keep: set[int] | None = None
) -> tuple[IntArray, dict[int, slice]]:
    """Sphere indices of ``frames`` (in frame order; only those in ``keep`` when given) and
    each frame's slice of them (frames left without spheres have none)."""
    idx: list[int] = []
    where: dict[int, slice] = {}
    for f in sorted(frames):
        sl = s.spheres_of(f)
        mine = [i for i in range(sl.start, sl.stop) if keep is None or i in keep]
        if mine:
            where[f] = slice(len(idx), len(idx) + len(mine))
            idx.extend(mine)
    return np.array(idx, dtype=np.intp), where
