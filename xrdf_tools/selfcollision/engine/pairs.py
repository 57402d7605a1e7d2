"""Body pairs: the frame pairs between two moving bodies, evaluated as one distance matrix.

Frame pairs between the same two bodies share one relative transform. :func:`_body_pairs`
groups the engine's frame pairs that way (frame pairs inside one body are constant and decided
elsewhere) and precomputes, per :class:`_BodyPair`, the augmented sphere matrices that give
every sphere pair's ``d² − (r_a + r_b)²`` as one GEMM in the frame of body ``a``
(:func:`_evaluate`, in blocks sized for the CPU cache). :func:`_direct` computes float32
clearances of chosen configurations for the minimum-clearance bookkeeping.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from ..collision import SphereSet
from .bodies import F32
from .bounds import _delta
from .grid import PairGrid

FloatArray = npt.NDArray[np.float64]
IntArray = npt.NDArray[np.intp]
BoolArray = npt.NDArray[np.bool_]

#: float32 elements of one distance block (E = [m_a, m_b, n]): sized for a 512 KB L2 cache.
_BLOCK_ELEMENTS = 1 << 15


@dataclass(frozen=True, eq=False)
class _BodyPair:
    """Frame pairs between body ``a`` (spheres kept in its frame) and body ``b``.

    ``p_aug`` [m_a, 6] = ``[−2p, 1, |p|² − r², −2r]`` per sphere of ``a``; ``q_aug`` [m_b, 4] =
    ``[q, 1]`` per sphere of ``b``; with ``Q = [q', |q'|² − r_b², 1, r_b]`` (``q'`` the centres
    of ``b`` in the frame of ``a``), ``p_aug @ Q = d² − (r_a + r_b)²`` for every sphere pair.
    ``blocks``: (frame pair, rows, columns) of each frame pair in that matrix.
    """

    a: int
    b: int
    ia: IntArray  # sphere indices of a's side
    ib: IntArray
    p_aug: F32
    q_aug: F32
    r_b: F32  # [m_b, 1]
    r2_b: F32  # [m_b, 1]
    blocks: tuple[tuple[int, slice, slice], ...]
    p32: F32  # [m_a, 3] centres of a's spheres
    rsum: F32  # [m_a, m_b] radius sums
    delta: float
    relevant: BoolArray  # [m_a, m_b]: sphere pairs of a counted frame pair
    cull: bool = False
    grid: PairGrid | None = None


def _frame_bodies(spheres: SphereSet, sphere_body: IntArray) -> IntArray:
    """The body of every sphere frame [Fs] (a frame's spheres all sit on one body)."""
    starts = [spheres.spheres_of(f).start for f in range(len(spheres.frame_names))]
    return sphere_body[np.array(starts, dtype=np.intp)]


def _body_pairs(
    spheres: SphereSet,
    frame_body: IntArray,
    local: FloatArray,
    err: float,
    skip: set[int],
) -> list[_BodyPair]:
    """The frame pairs of ``spheres`` (except those in ``skip``) grouped by their two bodies.

    ``frame_body`` [Fs]: each frame's body (:func:`_frame_bodies`); ``local`` [S, 3]: each
    sphere's centre in its body frame; ``err``: the float32 position error bound
    (:func:`~.bodies._position_error`).
    """
    s = spheres

    def body_of(f: int) -> int:
        return int(frame_body[f])

    groups: dict[tuple[int, int], list[int]] = {}
    for k in range(s.n_frame_pairs):
        if k in skip:
            continue
        ba, bb = body_of(int(s.frame_pair_a[k])), body_of(int(s.frame_pair_b[k]))
        groups.setdefault((min(ba, bb), max(ba, bb)), []).append(k)
    return [_make_pair(s, body_of, local, err, key, ks) for key, ks in groups.items()]


def _make_pair(
    s: SphereSet,
    body_of: Callable[[int], int],
    local: FloatArray,
    err: float,
    key: tuple[int, int],
    ks: list[int],
) -> _BodyPair:
    side: dict[int, list[int]] = {key[0]: [], key[1]: []}
    for k in ks:
        for f in (int(s.frame_pair_a[k]), int(s.frame_pair_b[k])):
            lst = side[body_of(f)]
            if f not in lst:
                lst.append(f)

    ia, wa = _side_rows(s, side[key[0]])
    ib, wb = _side_rows(s, side[key[1]])
    a, b = key
    if len(ib) > len(ia):  # the side with more spheres stays put (fewer to transform)
        ia, ib, wa, wb, a, b = ib, ia, wb, wa, b, a
    blocks = []
    for k in ks:
        fa, fb = int(s.frame_pair_a[k]), int(s.frame_pair_b[k])
        if fa not in wa:
            fa, fb = fb, fa
        blocks.append((k, wa[fa], wb[fb]))
    p, ra = local[ia], s.self_radii[ia]
    q, rb = local[ib], s.self_radii[ib]
    p_aug = np.hstack(
        [
            -2.0 * p,
            np.ones((len(p), 1)),
            (np.sum(p * p, axis=1) - ra * ra)[:, None],
            -2.0 * ra[:, None],
        ]
    )
    r_max = float(ra.max() + rb.max())
    return _BodyPair(
        a=a,
        b=b,
        ia=ia,
        ib=ib,
        p_aug=p_aug.astype(np.float32),
        q_aug=np.hstack([q, np.ones((len(q), 1))]).astype(np.float32),
        r_b=rb[:, None].astype(np.float32),
        r2_b=(rb * rb)[:, None].astype(np.float32),
        blocks=tuple(blocks),
        p32=p.astype(np.float32),
        rsum=(ra[:, None] + rb[None, :]).astype(np.float32),
        delta=_delta(p, r_max, err),
        relevant=_relevant(len(ia), len(ib), blocks),
    )


def _pair_constants(
    spheres: SphereSet, pairs: list[_BodyPair]
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Per frame pair [K]: the float32 error bound ``delta`` of its body pair and the smallest
    and largest radius sum of its sphere pairs (0 for constant frame pairs)."""
    s = spheres
    K = s.n_frame_pairs
    delta = np.zeros(K)
    rlo = np.zeros(K)
    rhi = np.zeros(K)
    for bp in pairs:
        for k, _, _ in bp.blocks:
            rs = s.pair_radius_sum[int(s.pair_start[k]) : int(s.pair_start[k + 1])]
            delta[k] = bp.delta
            rlo[k], rhi[k] = float(rs.min()), float(rs.max())
    return delta, rlo, rhi


def _relevant(m_a: int, m_b: int, blocks: list[tuple[int, slice, slice]]) -> BoolArray:
    out = np.zeros((m_a, m_b), dtype=np.bool_)
    for _, rows, cols in blocks:
        out[rows, cols] = True
    return out


def _side_rows(s: SphereSet, frames: list[int]) -> tuple[IntArray, dict[int, slice]]:
    """Sphere indices of ``frames`` (in frame order) and each frame's slice of them."""
    idx: list[int] = []
    where: dict[int, slice] = {}
    for f in sorted(frames):
        sl = s.spheres_of(f)
        where[f] = slice(len(idx), len(idx) + sl.stop - sl.start)
        idx.extend(range(sl.start, sl.stop))
    return np.array(idx, dtype=np.intp), where


def _relative(Ra: F32, ta: F32, Rb: F32, tb: F32) -> F32:
    """``[Ra^T Rb | Ra^T (tb − ta)]`` per configuration: [3, 4, n]."""
    TB = np.empty((3, 4, Rb.shape[-1]), dtype=np.float32)
    TB[:, :3] = Rb
    np.subtract(tb, ta, out=TB[:, 3])
    out: F32 = np.einsum("lkn,lmn->kmn", Ra, TB)
    return out


def _pair_transform(bp: _BodyPair, T: F32, sel: IntArray | None) -> F32:
    """``T_a⁻¹ T_b`` [3, 4, n] from body poses ``T`` [nb, 3, 4, B] at the selected
    configurations (all when None)."""
    Ta, Tb = T[bp.a], T[bp.b]
    if sel is not None:
        Ta, Tb = np.take(Ta, sel, axis=-1), np.take(Tb, sel, axis=-1)
    return _relative(Ta[:, :3], Ta[:, 3], Tb[:, :3], Tb[:, 3])


def _evaluate(bp: _BodyPair, T: F32, sel: IntArray | None) -> F32:
    """float32 minima of ``d² − R²`` [blocks, n] per frame pair of ``bp`` for the selected
    configurations (all when ``sel`` is None)."""
    Trel = _pair_transform(bp, T, sel)  # [3, 4, n]
    n = Trel.shape[-1]
    out = np.empty((len(bp.blocks), n), dtype=np.float32)
    m_a, m_b = bp.p_aug.shape[0], bp.q_aug.shape[0]
    step = max(16, _BLOCK_ELEMENTS // (m_a * m_b))
    buf = np.empty((6, m_b, min(step, n)), dtype=np.float32)
    buf[4] = 1.0
    buf[5] = bp.r_b
    E = np.empty((m_a, m_b * min(step, n)), dtype=np.float32)
    for s0 in range(0, n, step):
        s1 = min(n, s0 + step)
        w = s1 - s0
        Q = buf if w == buf.shape[-1] else buf[:, :, :w].copy()
        np.matmul(bp.q_aug, Trel[:, :, s0:s1], out=Q[:3])
        np.einsum("kjn,kjn->jn", Q[:3], Q[:3], out=Q[3])
        Q[3] -= bp.r2_b
        Ew = E if w == buf.shape[-1] else np.empty((m_a, m_b * w), dtype=np.float32)
        np.matmul(bp.p_aug, Q.reshape(6, m_b * w), out=Ew)
        E3 = Ew.reshape(m_a, m_b, w)
        for i, (_, rows, cs) in enumerate(bp.blocks):
            np.min(E3[rows, cs], axis=(0, 1), out=out[i, s0:s1])
    return out


def _direct(bp: _BodyPair, T: F32, cols: IntArray) -> F32:
    """float32 clearance [blocks, n] of each frame pair of ``bp`` at configurations
    ``cols`` (every sphere pair computed directly, in cache-sized column blocks)."""
    out = np.empty((len(bp.blocks), len(cols)), dtype=np.float32)
    step = max(1, _BLOCK_ELEMENTS // bp.rsum.size)
    for s0 in range(0, len(cols), step):
        c = cols[s0 : s0 + step]
        qp = np.matmul(bp.q_aug, _pair_transform(bp, T, c))  # [3, m_b, w]
        diff = qp[:, None, :, :] - bp.p32.T[:, :, None, None]
        d = np.sqrt(np.einsum("kijn,kijn->ijn", diff, diff))
        d -= bp.rsum[:, :, None]
        for i, (_, rows, cs) in enumerate(bp.blocks):
            np.min(d[rows, cs], axis=(0, 1), out=out[i, s0 : s0 + len(c)])
    return out
