"""A float64 second look at the entries the float32 path could not decide.

The float32 path's error grows with the robot: every body's pose carries the rounding of its
whole chain, times its distance from the root. Near a smooth extremum of a frame pair's
clearance (two links turning about an axis that passes near their spheres) many configurations
tie with the smallest one within that error, and every tie used to go to the float64 reference
test. Here the queued (frame pair, configuration) entries are evaluated again in float64, with
the pose of one body in the other's frame composed only from the joints between them (from
their lowest common ancestor down). That value differs from the reference's by ~1e-12 m at
most (:attr:`Sharpener.tau`), so only true touches and true ties still need the reference.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...util.arrays import FloatArray, IntArray, ragged_index
from ..collision import SphereSet
from ..collision.distances import entry_slices
from .bodies import PRISM, Bodies, body_chains

__all__ = ["Sharpener"]

_EPS64 = float(np.finfo(np.float64).eps)
#: Sphere-pair evaluations per block (bounded memory).
_BLOCK = 1 << 16
#: Frame pairs with at least this many entries (or more than :data:`_BLOCK` sphere pairs) are
#: evaluated one by one (broadcast over their entries, in bounded blocks); the others together
#: (:meth:`Sharpener._few`).
_MANY = 8


@dataclass(frozen=True, eq=False)
class Sharpener:
    """float64 frame-pair values from path-local poses.

    ``local`` [S, 3]: every sphere centre in its body's frame (float64); ``frame_body`` [Fs]:
    each sphere frame's body. ``tau`` bounds the difference between a clearance here and the
    reference's (both float64, different operation orders); ``delta`` bounds it for
    ``d² − R²`` near zero.
    """

    bodies: Bodies
    spheres: SphereSet
    local: FloatArray
    frame_body: IntArray
    tau: float
    delta: float

    @classmethod
    def of(
        cls,
        bodies: Bodies,
        spheres: SphereSet,
        local: FloatArray,
        frame_body: IntArray,
        n_frames: int,
    ) -> Sharpener:
        lever = max(bodies.lever, 1e-3)
        tau = 32.0 * _EPS64 * (n_frames + 2) * lever
        r_max = 2.0 * float(spheres.self_radii.max()) if spheres.n_spheres else 0.0
        delta = 2.0 * (2.0 * (r_max + tau) * tau + 16.0 * _EPS64 * (3.0 * lever + r_max) ** 2)
        return cls(bodies, spheres, local, frame_body, tau, delta)

    def evaluate(self, ks: IntArray, q: FloatArray) -> tuple[FloatArray, FloatArray]:
        """Smallest ``d² − R²`` and smallest clearance [E] of frame pair ``ks[e]`` at the
        configuration ``q[e]`` (values of the varying joints) over all its sphere pairs."""
        s = self.spheres
        e_min = np.empty(len(ks))
        clear = np.empty(len(ks))
        fa, fb = s.frame_pair_a[ks], s.frame_pair_b[ks]
        ba, bb = self.frame_body[fa], self.frame_body[fb]
        order = np.lexsort((ks, bb, ba))
        key = np.stack([ba[order], bb[order]], axis=1)
        cut = np.flatnonzero(np.any(key[1:] != key[:-1], axis=1)) + 1
        for grp in np.split(order, cut):
            a, b = int(ba[grp[0]]), int(bb[grp[0]])
            R, t = self.relative(a, b, q[grp])
            self._frame_pairs(ks[grp], R, t, grp, e_min, clear)
        return e_min, clear

    def _frame_pairs(
        self,
        ks: IntArray,
        R: FloatArray,
        t: FloatArray,
        at: IntArray,
        e_min: FloatArray,
        clear: FloatArray,
    ) -> None:
        """Entries ``at`` (sorted by frame pair ``ks``) whose body ``b`` sits at ``R``, ``t``
        [n, 3, 3], [n, 3] in the frame of body ``a``: frame pair by frame pair for those with
        many entries, all others together in one flat pass (:meth:`_few`)."""
        s = self.spheres
        cut = np.flatnonzero(ks[1:] != ks[:-1]) + 1
        parts = np.split(np.arange(len(ks)), cut)
        sizes = np.diff(s.pair_start)  # sphere pairs per frame pair
        alone = [len(p) >= _MANY or sizes[ks[p[0]]] > _BLOCK for p in parts]
        few = [p for p, one in zip(parts, alone, strict=True) if not one]
        if few:
            rows = np.concatenate(few)
            self._few(ks[rows], R[rows], t[rows], at[rows], e_min, clear)
        for part in (p for p, one in zip(parts, alone, strict=True) if one):
            k = int(ks[part[0]])
            sa = s.spheres_of(int(s.frame_pair_a[k]))
            sb = s.spheres_of(int(s.frame_pair_b[k]))
            pa, pb = self.local[sa], self.local[sb]
            ra, rb = s.self_radii[sa], s.self_radii[sb]
            row_step = max(1, _BLOCK // max(1, len(rb)))  # bounded memory, however many
            step = max(1, _BLOCK // (min(row_step, len(ra)) * max(1, len(rb))))
            for s0 in range(0, len(part), step):
                rows = part[s0 : s0 + step]
                qb = np.einsum("nij,mj->nmi", R[rows], pb) + t[rows][:, None, :]  # [n, m_b, 3]
                e = np.full(len(rows), np.inf)
                c = np.full(len(rows), np.inf)
                for i0 in range(0, len(ra), row_step):
                    rs = ra[i0 : i0 + row_step, None] + rb[None, :]
                    diff = pa[None, i0 : i0 + row_step, None, :] - qb[:, None, :, :]
                    d2 = np.einsum("nabk,nabk->nab", diff, diff)
                    np.minimum(e, (d2 - rs * rs).min(axis=(1, 2)), out=e)
                    np.minimum(c, (np.sqrt(d2) - rs).min(axis=(1, 2)), out=c)
                e_min[at[rows]] = e
                clear[at[rows]] = c

    def _few(
        self,
        ks: IntArray,
        R: FloatArray,
        t: FloatArray,
        at: IntArray,
        e_min: FloatArray,
        clear: FloatArray,
    ) -> None:
        """:meth:`_frame_pairs` for entries of frame pairs with few entries each and at most
        :data:`_BLOCK` sphere pairs: the spheres of ``b`` placed once per entry, every sphere
        pair of every entry in one flat pass (in blocks of about :data:`_BLOCK` sphere pairs),
        reduced per entry."""
        s = self.spheres
        start = s.frame_start
        na, nb = s.frame_sizes[s.frame_pair_a[ks]], s.frame_sizes[s.frame_pair_b[ks]]
        for e0, e1 in entry_slices(na * nb + nb, _BLOCK):
            sl = slice(e0, e1)
            a0, b0 = start[s.frame_pair_a[ks[sl]]], start[s.frame_pair_b[ks[sl]]]
            placed_at = np.cumsum(nb[sl]) - nb[sl]  # each entry's first placed sphere of b
            e, rank = ragged_index(nb[sl])
            jb = b0[e] + rank
            placed = np.einsum("cij,cj->ci", R[sl][e], self.local[jb]) + t[sl][e]
            m = na[sl] * nb[sl]
            offs = np.cumsum(m) - m
            rep, pos = ragged_index(m)
            row, col = np.divmod(pos, nb[sl][rep])
            diff = self.local[a0[rep] + row] - placed[placed_at[rep] + col]
            d2 = np.einsum("ck,ck->c", diff, diff)
            rs = s.self_radii[a0[rep] + row] + s.self_radii[b0[rep] + col]
            e_min[at[sl]] = np.minimum.reduceat(d2 - rs * rs, offs)
            clear[at[sl]] = np.minimum.reduceat(np.sqrt(d2) - rs, offs)

    def _pose(self, chain: tuple[int, ...], q: FloatArray) -> tuple[FloatArray, FloatArray]:
        """Poses [n, 3, 3], [n, 3] of the last body of ``chain`` in the frame of the first's
        parent: ``C_1 Z(θ_1) C_2 Z(θ_2) …``."""
        n = q.shape[0]
        bd = self.bodies
        first = bd.consts[chain[0]] if chain else np.eye(4)  # the identity times it: itself
        R = np.repeat(first[None, :3, :3], n, axis=0)
        t = np.repeat(first[None, :3, 3], n, axis=0)
        for at, j in enumerate(chain):
            C = bd.consts[j]
            theta = bd.mult[j] * q[:, bd.col[j]] + bd.off[j]
            if at:
                t = t + R @ C[:3, 3]
                R = R @ C[:3, :3]
            if bd.kind[j] == PRISM:
                t = t + R[:, :, 2] * theta[:, None]
            else:
                c, s = np.cos(theta), np.sin(theta)
                x, y = R[:, :, 0].copy(), R[:, :, 1].copy()
                R[:, :, 0] = x * c[:, None] + y * s[:, None]
                R[:, :, 1] = y * c[:, None] - x * s[:, None]
        return R, t

    def relative(self, a: int, b: int, q: FloatArray) -> tuple[FloatArray, FloatArray]:
        """Pose of body ``b`` in the frame of body ``a`` at configurations ``q`` [n, varying]:
        rotations [n, 3, 3] and translations [n, 3], float64."""
        chain_a, chain_b = body_chains(self.bodies, a, b)
        Rb, tb = self._pose(chain_b, q)
        if not chain_a:  # a is the common ancestor: b's pose is already in its frame
            return Rb, tb
        Ra, ta = self._pose(chain_a, q)
        RaT = Ra.transpose(0, 2, 1)
        return RaT @ Rb, np.einsum("nij,nj->ni", RaT, tb - ta)
