"""Body pairs: the frame pairs between two moving bodies, evaluated as one distance matrix.

Frame pairs between the same two bodies share one relative transform. :func:`body_pairs`
groups the engine's frame pairs that way (frame pairs inside one body are constant and decided
elsewhere) and precomputes, per :class:`BodyPair`, the augmented sphere matrices that give
every sphere pair's ``d² − (r_a + r_b)²`` as one GEMM in the frame of body ``a``
(:func:`evaluate_pair`, in blocks sized for the CPU cache), with each sphere pair's minimum
over the configurations. :func:`sphere_pair_clearances` computes float32 clearances of chosen
sphere pairs for the minimum-clearance bookkeeping.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ...util.arrays import BoolArray, FloatArray, IntArray
from ..collision import SphereSet
from .bodies import F32, Bodies, chain_pose
from .grid import PairGrid

#: float32 elements of one distance block (E = [m_a, m_b, n]): 512 KB. Larger than the 128 KB that
#: fit the L2 cache best on franka alone: on robots with many small body pairs, fewer numpy calls
#: per pair matter more (PR2 two arms 29 % faster, franka unchanged, bench_report).
_BLOCK_ELEMENTS = 1 << 17
#: Fewest configurations per block: below this, per-call overhead outweighs the cache.
_MIN_STEP = 64


@dataclass(frozen=True, eq=False)
class BodyPair:
    """Frame pairs between body ``a`` (spheres kept in its frame) and body ``b``.

    ``p_aug`` [m_a, 6] = ``[−2p, 1, |p|² − r², −2r]`` per sphere of ``a``; ``q_aug`` [m_b, 4] =
    ``[q, 1]`` per sphere of ``b``; with ``Q = [q', |q'|² − r_b², 1, r_b]`` (``q'`` the centres
    of ``b`` in the frame of ``a``), ``p_aug @ Q = d² − (r_a + r_b)²`` for every sphere pair.
    ``blocks``: (frame pair, rows, columns) of each frame pair in that matrix. The rows (and the
    columns) are cut into one segment per frame (``row_starts``, ``col_starts``); block ``i``
    is segment ``seg_a[i]`` × ``seg_b[i]``. Only the spheres that can come within reach of the
    other body are here (:mod:`.reach`). ``bound_a``/``bound_b`` [4]: a bounding sphere of each
    side's spheres (centre in its body frame, radius + slack), for culling.
    """

    a: int
    b: int
    ia: IntArray  # sphere indices of a's side
    ib: IntArray
    p_aug: F32
    q_aug: F32
    ra64: FloatArray  # [m_a] radii of a's spheres (float64)
    rb64: FloatArray  # [m_b]
    r_b: F32  # [m_b, 1]
    r2_b: F32  # [m_b, 1]
    blocks: tuple[tuple[int, slice, slice], ...]
    row_starts: IntArray
    col_starts: IntArray
    seg_a: IntArray
    seg_b: IntArray
    p32: F32  # [m_a, 3] centres of a's spheres
    delta: float
    bound_a: FloatArray
    bound_b: FloatArray
    cull: bool = False
    grid: PairGrid | None = None
    #: The bodies from the two bodies' lowest common ancestor down to ``a`` and to ``b`` when
    #: the pair's relative pose is composed from them (few joints between the bodies: a much
    #: smaller float32 error than through the world frame); None: through the world frame.
    path: tuple[tuple[int, ...], tuple[int, ...]] | None = None
    #: float32 error bound (m) of a clearance computed by :func:`sphere_pair_clearances` (see
    #: ``delta`` for ``d² − R²``).
    tau: float = 0.0

    @cached_property
    def frame_pairs(self) -> IntArray:
        """[blocks]: the frame pair of each block."""
        return np.array([k for k, _, _ in self.blocks], dtype=np.intp)

    @property
    def n_sphere_pairs(self) -> int:
        return sum((r.stop - r.start) * (c.stop - c.start) for _, r, c in self.blocks)

    def relevant(self) -> BoolArray:
        """[m_a, m_b]: the sphere pairs of a counted frame pair."""
        out = np.zeros((len(self.ia), len(self.ib)), dtype=np.bool_)
        for _, rows, cols in self.blocks:
            out[rows, cols] = True
        return out


def frame_bodies(spheres: SphereSet, sphere_body: IntArray) -> IntArray:
    """The body of every sphere frame [Fs] (a frame's spheres all sit on one body)."""
    starts = [spheres.spheres_of(f).start for f in range(len(spheres.frame_names))]
    return sphere_body[np.array(starts, dtype=np.intp)]


def pair_constants(
    spheres: SphereSet, pairs: list[BodyPair]
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Per frame pair [K]: the float32 error bound ``delta`` of its body pair and the smallest
    and largest radius sum of its sphere pairs (0 for frame pairs in no body pair)."""
    s = spheres
    K = s.n_frame_pairs
    delta = np.zeros(K)
    rlo = np.zeros(K)
    rhi = np.zeros(K)
    r = s.self_radii
    for bp in pairs:
        for k, _, _ in bp.blocks:
            ra = r[s.spheres_of(int(s.frame_pair_a[k]))]
            rb = r[s.spheres_of(int(s.frame_pair_b[k]))]
            delta[k] = max(delta[k], bp.delta)  # a frame pair may have several parts
            rlo[k], rhi[k] = float(ra.min() + rb.min()), float(ra.max() + rb.max())
    return delta, rlo, rhi


def _relative(Ra: F32, ta: F32, Rb: F32, tb: F32) -> F32:
    """``[Ra^T Rb | Ra^T (tb − ta)]`` per configuration: [3, 4, n]."""
    TB = np.empty((3, 4, Rb.shape[-1]), dtype=np.float32)
    TB[:, :3] = Rb
    np.subtract(tb, ta, out=TB[:, 3])
    out: F32 = np.einsum("lkn,lmn->kmn", Ra, TB)
    return out


@dataclass(frozen=True, eq=False)
class ChunkPoses:
    """A chunk's float32 body poses ``T`` [nb, 3, 4, B] and joint values ``vals`` [nb − 1, B]."""

    bodies: Bodies
    T: F32
    vals: F32


def pair_transform(bp: BodyPair, poses: ChunkPoses, sel: IntArray | None) -> F32:
    """``T_a⁻¹ T_b`` [3, 4, n] at the selected configurations (all when None): composed
    along ``bp.path`` when it has one, else from the body poses."""
    if bp.path is not None:
        vals = poses.vals if sel is None else np.take(poses.vals, sel, axis=-1)
        chain_a, chain_b = bp.path
        Tb = chain_pose(poses.bodies, chain_b, vals)
        if not chain_a:
            return Tb
        Ta = chain_pose(poses.bodies, chain_a, vals)  # (an empty chain is the identity)
    else:
        Tb = poses.T[bp.b] if sel is None else np.take(poses.T[bp.b], sel, axis=-1)
        if bp.a == 0:  # the static body's pose is the identity: T_a⁻¹ T_b is T_b
            return Tb
        Ta = poses.T[bp.a] if sel is None else np.take(poses.T[bp.a], sel, axis=-1)
    return _relative(Ta[:, :3], Ta[:, 3], Tb[:, :3], Tb[:, 3])


def _energies(bp: BodyPair, trel: F32, Q: F32, E: F32, rows: slice, cols: slice) -> None:
    """``d² − R²`` [rows, cols · w] of the spheres ``rows`` of ``a`` and ``cols`` of ``b`` at
    the poses ``trel`` [3, 4, w] into ``E``: one GEMM of ``p_aug`` with
    ``Q = [q', |q'|² − r_b², 1, r_b]`` (``Q`` [6, cols, w], rows 4 and 5 already filled)."""
    np.matmul(bp.q_aug[cols], trel, out=Q[:3])
    np.einsum("kjn,kjn->jn", Q[:3], Q[:3], out=Q[3])
    Q[3] -= bp.r2_b[cols]
    np.matmul(bp.p_aug[rows], Q.reshape(6, -1), out=E)


def _q_buffer(bp: BodyPair, cols: slice, w: int) -> F32:
    Q = np.empty((6, cols.stop - cols.start, w), dtype=np.float32)
    Q[4] = 1.0
    Q[5] = bp.r_b[cols]
    return Q


def evaluate_pair(bp: BodyPair, poses: ChunkPoses, sel: IntArray | None) -> F32:
    """float32 minima of ``d² − R²`` [blocks, n] per frame pair of ``bp`` for the selected
    configurations (all when ``sel`` is None).

    Each block of configurations is one GEMM; the per-frame-pair minima are two segmented
    reductions over contiguous rows (``minimum.reduceat`` over ``a``'s frames, then over
    ``b``'s), so their cost follows the sphere pairs, not the number of frame pairs."""
    Trel = pair_transform(bp, poses, sel)  # [3, 4, n]
    n = Trel.shape[-1]
    out = np.empty((len(bp.blocks), n), dtype=np.float32)
    m_a, m_b = bp.p_aug.shape[0], bp.q_aug.shape[0]
    every_a, every_b = slice(0, m_a), slice(0, m_b)
    step = max(1, _BLOCK_ELEMENTS // (m_a * m_b))
    if m_a * m_b <= _BLOCK_ELEMENTS // 8:
        step = max(step, _MIN_STEP)  # small blocks: fewer calls matter more than the cache
    buf = _q_buffer(bp, every_b, min(step, n))
    E = np.empty((m_a, m_b * min(step, n)), dtype=np.float32)
    starts = bp.row_starts.tolist()
    row_segs = list(zip(starts, [*starts[1:], m_a], strict=True))
    rows = np.empty((len(row_segs), m_b * min(step, n)), dtype=np.float32)
    one_col = len(bp.col_starts) == 1
    for s0 in range(0, n, step):
        s1 = min(n, s0 + step)
        w = s1 - s0
        Q = buf if w == buf.shape[-1] else buf[:, :, :w].copy()
        Ew = E if w == buf.shape[-1] else np.empty((m_a, m_b * w), dtype=np.float32)
        _energies(bp, Trel[:, :, s0:s1], Q, Ew, every_a, every_b)
        for i, (r0, r1) in enumerate(row_segs):  # contiguous rows: a fast reduction
            np.min(Ew[r0:r1], axis=0, out=rows[i, : m_b * w])
        R3 = rows[:, : m_b * w].reshape(len(row_segs), m_b, w)
        if one_col:
            seg = R3.min(axis=1)[:, None, :]
        else:
            seg = np.minimum.reduceat(R3, bp.col_starts, axis=1)
        out[:, s0:s1] = seg[bp.seg_a, bp.seg_b]
    return out


def sphere_pair_minima(bp: BodyPair, trel: F32, rows: slice, cols: slice) -> F32:
    """Per sphere pair of ``a``'s spheres ``rows`` and ``b``'s ``cols``, the float32 minimum
    of ``d² − R²`` [rows, cols] over the poses ``trel`` [3, 4, n] (for one sphere pair,
    ``d² − R²`` orders the configurations as its clearance does), in cache-sized blocks."""
    m_r, m_c = rows.stop - rows.start, cols.stop - cols.start
    out = np.full((m_r, m_c), np.inf, dtype=np.float32)
    n = trel.shape[-1]
    step = max(1, _BLOCK_ELEMENTS // (m_r * m_c))
    part = np.empty_like(out)
    for s0 in range(0, n, step):
        w = min(n, s0 + step) - s0
        E = np.empty((m_r, m_c * w), dtype=np.float32)
        _energies(bp, trel[:, :, s0 : s0 + w], _q_buffer(bp, cols, w), E, rows, cols)
        np.min(E.reshape(m_r, m_c, w), axis=2, out=part)
        np.minimum(out, part, out=out)
    return out


def sphere_pair_clearances(bp: BodyPair, trel: F32, ia: IntArray, ib: IntArray) -> F32:
    """float32 clearances [len(ia), n] of the sphere pairs (``ia``, ``ib``) (rows of ``a``'s
    and of ``b``'s spheres in ``bp``) at the poses ``trel`` [3, 4, n] (:func:`pair_transform`),
    computed directly (error at most ``bp.tau``), in cache-sized column blocks."""
    n = trel.shape[-1]
    out = np.empty((len(ia), n), dtype=np.float32)
    if not len(ia):
        return out
    ub, inv = np.unique(ib, return_inverse=True)
    rsum = (bp.ra64[ia] + bp.rb64[ib]).astype(np.float32)[:, None]
    pa = bp.p32[ia].T[:, :, None]  # [3, r, 1]
    step = max(1, _BLOCK_ELEMENTS // (4 * len(ia)))
    for s0 in range(0, n, step):
        sl = slice(s0, min(n, s0 + step))
        qb = np.matmul(bp.q_aug[ub], trel[:, :, sl])  # [3, |ub|, w]
        diff = qb[:, inv, :] - pa
        d = np.sqrt(np.einsum("krn,krn->rn", diff, diff))
        np.subtract(d, rsum, out=out[:, sl])
    return out
