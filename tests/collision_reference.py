"""The reference counter: exact per-frame-pair hit flags, float64, bounding-sphere culling.

:func:`count_chunk` is what ``xrdf report`` ran before :mod:`xrdf_tools.selfcollision.engine`; it
stays as the plain, easily checked baseline that ``benchmarks/bench_report.py`` and the tests
compare the engine with. It takes its spheres, pairs and per-frame bounding spheres from the
:class:`~xrdf_tools.selfcollision.collision.spheres.SphereSet` and decides every pair with
:func:`~xrdf_tools.selfcollision.collision.distances.touching`, like the engine's float64 recheck.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from xrdf_tools.robot.kinematics import KinematicModel
from xrdf_tools.selfcollision.collision.distances import as_q2, centers_batch_last, touching
from xrdf_tools.selfcollision.collision.spheres import SphereSet

FloatArray = npt.NDArray[np.float64]
BoolArray = npt.NDArray[np.bool_]

__all__ = ["ChunkResult", "count_chunk"]


@dataclass(frozen=True)
class ChunkResult:
    """Per-frame-pair results for a chunk of ``B`` configurations.

    ``hits`` [K, B] bool: the frame pair collides in that configuration (exact).
    ``min_clearance`` [K]: smallest clearance among the sphere pairs that were evaluated
    exactly (``+inf`` if none). ``clearance_bound`` [K]: lower bound on the clearance of every
    sphere pair that culling skipped (``+inf`` if none was skipped). The true minimum over
    the chunk is ``min_clearance`` when ``min_clearance <= clearance_bound``; otherwise it
    lies in ``[clearance_bound, min_clearance]``.
    """

    hits: BoolArray
    min_clearance: FloatArray
    clearance_bound: FloatArray


def count_chunk(
    kin: KinematicModel, spheres: SphereSet, q_full: npt.ArrayLike, *, margin: float = 0.0
) -> ChunkResult:
    """Exact per-frame-pair collision flags for configurations ``q_full`` [B, n].

    Every frame pair of ``spheres`` is evaluated for every configuration (no early exit);
    the work is cut by conservative culling, which never changes a verdict:

    1. frame level: each frame's spheres lie inside one bounding sphere; when the bounding
       spheres of two frames are apart, none of their sphere pairs can touch;
    2. sphere level: for the frame pair's side with more spheres, a sphere that does not
       reach the other frame's bounding sphere touches none of its spheres;
    3. the remaining (sphere, configuration) rows are tested against every sphere of the
       other frame with ``d² < (sr_a + sr_b)²``.

    Culling only skips what is more than ``margin`` metres apart, so every clearance below
    ``margin`` is computed exactly (a larger margin costs time, buys exact minima).

    Chunk ``q_full`` yourself (a few thousand rows) to bound memory.
    """
    q2, _ = as_q2(kin, q_full)
    B = q2.shape[0]
    K = spheres.n_frame_pairs
    hits = np.zeros((K, B), dtype=np.bool_)
    min_clear = np.full(K, np.inf)
    bound = np.full(K, np.inf)
    if K == 0 or B == 0:
        return ChunkResult(hits, min_clear, bound)
    S = spheres.n_spheres
    C = centers_batch_last(kin, spheres, q2, extra=spheres._bound_center)
    X, Y, Z = C[:, 0, :], C[:, 1, :], C[:, 2, :]  # [S + Fs, B], rows contiguous
    sr = spheres.self_radii
    br = spheres._bound_radius
    m = max(float(margin), 0.0)
    fa, fb = spheres.frame_pair_a, spheres.frame_pair_b
    # Level 1 for all frame pairs at once: [K, B]
    ba, bb = S + fa, S + fb
    d1 = np.square(X[ba] - X[bb])
    d1 += np.square(Y[ba] - Y[bb])
    d1 += np.square(Z[ba] - Z[bb])
    reach1 = (br[fa] + br[fb])[:, None]
    cand1 = d1 < np.square(reach1 + m)
    for k in range(K):
        a, b = int(fa[k]), int(fb[k])
        ck = cand1[k]
        cols = np.flatnonzero(ck)
        if len(cols) < B:
            gap = np.sqrt(d1[k][~ck]) - reach1[k, 0]
            bound[k] = float(gap.min())
        if len(cols) == 0:
            continue
        sa, sb = spheres.spheres_of(a), spheres.spheres_of(b)
        # The larger side goes through the sphere-level cull.
        if sa.stop - sa.start < sb.stop - sb.start:
            sa, sb, b = sb, sa, a
        full = len(cols) == B
        Xa, Ya, Za = X[sa], Y[sa], Z[sa]
        if not full:
            Xa, Ya, Za = Xa[:, cols], Ya[:, cols], Za[:, cols]
        bxyz = (X[S + b], Y[S + b], Z[S + b])
        if not full:
            bxyz = (bxyz[0][cols], bxyz[1][cols], bxyz[2][cols])
        d2 = np.square(Xa - bxyz[0])
        d2 += np.square(Ya - bxyz[1])
        d2 += np.square(Za - bxyz[2])
        reach2 = (sr[sa] + br[b])[:, None]
        cand2 = d2 < np.square(reach2 + m)
        rows, cc = np.nonzero(cand2)  # sphere (local to sa) and column (into cols)
        if len(rows) < cand2.size:
            gap2 = np.sqrt(d2[~cand2]) - np.broadcast_to(reach2, d2.shape)[~cand2]
            bound[k] = min(bound[k], float(gap2.min()))
        if len(rows) == 0:
            continue
        xs, ys, zs = Xa[rows, cc], Ya[rows, cc], Za[rows, cc]  # [L]
        gcol = cc if full else cols[cc]  # configuration index of each row
        Xb, Yb, Zb = X[sb][:, gcol], Y[sb][:, gcol], Z[sb][:, gcol]  # [mb, L]
        d3 = np.square(Xb - xs)
        d3 += np.square(Yb - ys)
        d3 += np.square(Zb - zs)
        rs3 = sr[sb][:, None] + sr[sa.start + rows][None, :]
        hit_rows = touching(d3, rs3).any(axis=0)
        hits[k, gcol[hit_rows]] = True
        np.sqrt(d3, out=d3)
        d3 -= rs3
        min_clear[k] = float(d3.min())
    return ChunkResult(hits, min_clear, bound)
