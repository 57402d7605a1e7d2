"""Reach: the spheres of a body pair that can ever come within the margin of each other.

A body's spheres can only move as far as the joints between it and another body let them.
Seen from the lowest common ancestor ``L`` of two bodies, a body ``d`` below ``L`` turns (or
slides) about the joint of ``top``, the child of ``L`` on the path to ``d``: every sphere
surface of ``d`` stays inside a *reach ball* around that joint's origin, whose radius adds up
the translations of the joints from ``top`` down to ``d``, the prismatic travel, and the
sphere's own distance from its body origin plus its radius (rotations keep lengths). A body
that *is* ``L`` (for instance the static body, every frame the c-space does not move) keeps its
exact sphere positions.

:func:`prune` compares the two sides in float64: a sphere of the ancestor whose surface stays
farther than the margin from the other body's reach ball, or two reach balls that are that far
apart, can never collide and never hold a minimum clearance below the margin. Such sphere pairs
are dropped from the sampled work once, at build time; their gap is a lower bound of the
clearance of every pair they belong to. Counts do not change (the dropped pairs cannot
collide), only the work does: the legs of a humanoid whose c-space is one arm are never
evaluated.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ...robot.kinematics import KinematicModel
from ...util.ancestry import Ancestry
from ...util.arrays import BoolArray, FloatArray, IntArray
from .bodies import PRISM, Bodies

__all__ = ["Meet", "Reach", "SidePrune"]


@dataclass(frozen=True)
class SidePrune:
    """One side of a body pair after :meth:`Reach.prune`: which of its spheres are kept, and a
    lower bound of the clearance of every pair a dropped sphere is in (``gap`` [m]; +inf for
    kept spheres)."""

    keep: BoolArray
    gap: FloatArray


@dataclass(frozen=True)
class Meet:
    """Where the chains of bodies ``a`` and ``b`` meet: their lowest common ancestor ``lca``,
    the child of ``lca`` on the path to each (``top_a``, ``top_b``; -1 for a body that is the
    ancestor) and the number of bodies on the two chains below ``lca`` (``joints``)."""

    a: int
    b: int
    lca: int
    top_a: int
    top_b: int
    joints: int


@dataclass(frozen=True, eq=False)
class Reach:
    """The bodies of an engine with the range ``[lo, hi]`` of every body's joint value
    (``θ = mult · q + off`` over the joint limits; body 0 has none) and their ancestry."""

    bodies: Bodies
    lo: FloatArray
    hi: FloatArray
    tree: Ancestry
    #: the length of each body's joint translation ``|C_j t|`` (m)
    shift: tuple[float, ...]
    #: ``_ball``'s extra radius for (top, body), filled by :meth:`meets`
    _ext: dict[tuple[int, int], float] = field(default_factory=dict, repr=False)

    @classmethod
    def of(cls, kin: KinematicModel, varying: IntArray, bodies: Bodies) -> Reach:
        lo = np.zeros(bodies.n)
        hi = np.zeros(bodies.n)
        for j in range(1, bodies.n):
            v = int(varying[int(bodies.col[j])])
            with np.errstate(invalid="ignore", over="ignore"):
                ends = bodies.mult[j] * np.array([kin.lower[v], kin.upper[v]]) + bodies.off[j]
            lo[j], hi[j] = float(np.min(ends)), float(np.max(ends))
        shift = tuple(float(np.linalg.norm(c[:3, 3])) for c in bodies.consts)
        return cls(bodies, lo, hi, Ancestry(bodies.parent), shift)

    def travel(self) -> FloatArray:
        """Each body's prismatic travel (largest |joint value|; 0 for revolute joints) [nb]."""
        prism = np.array([k == PRISM for k in self.bodies.kind])
        return np.where(prism, np.maximum(np.abs(self.lo), np.abs(self.hi)), 0.0)

    def meets(self, keys: list[tuple[int, int]]) -> list[Meet]:
        """Where the chains of each body pair ``(a, b)`` of ``keys`` meet, all at once; the
        reach balls :meth:`prune` needs for them are computed here, one walk up per body."""
        if not keys:
            return []
        a = np.array([k[0] for k in keys], dtype=np.intp)
        b = np.array([k[1] for k in keys], dtype=np.intp)
        depth = self.tree.depth
        lca = self.tree.lca(a, b)
        below = depth[lca] + 1
        top_a = np.where(a == lca, -1, self.tree.ancestor(a, np.minimum(below, depth[a])))
        top_b = np.where(b == lca, -1, self.tree.ancestor(b, np.minimum(below, depth[b])))
        joints = depth[a] + depth[b] - 2 * depth[lca]
        out = [
            Meet(*row)
            for row in zip(
                a.tolist(),
                b.tolist(),
                lca.tolist(),
                top_a.tolist(),
                top_b.tolist(),
                joints.tolist(),
                strict=True,
            )
        ]
        wanted: dict[int, set[int]] = {}
        for m in out:
            for top, d in ((m.top_a, m.a), (m.top_b, m.b)):
                if top >= 0:
                    wanted.setdefault(d, set()).add(top)
        for d, tops in wanted.items():
            self._walk_up(d, tops)
        return out

    def _walk_up(self, d: int, tops: set[int]) -> None:
        """The extra radius of :meth:`_ball` for body ``d`` below each of ``tops`` (``d`` or
        its ancestors), in one walk from ``d`` up, summed in the order of that walk."""
        b = self.bodies
        left = set(tops) - {top for top in tops if (top, d) in self._ext}
        ext = 0.0
        k = d
        while left and k >= 0:
            if k in left:
                self._ext[k, d] = ext
                left.discard(k)
            ext += self.shift[k]
            if b.kind[k] == PRISM:
                ext += max(abs(float(self.lo[k])), abs(float(self.hi[k])))
            k = b.parent[k]

    def _ball(self, top: int, d: int) -> tuple[FloatArray, float]:
        """Centre (in the frame of ``top``'s parent) and extra radius of a ball that holds a
        point of body ``d`` at distance ``ρ`` from its body origin within ``ρ + extra`` for
        every value of the joints from ``top`` down to ``d``: the extra radius adds up the
        translations of those joints and their prismatic travel."""
        b = self.bodies
        if (top, d) not in self._ext:
            self._walk_up(d, {top})
        ext = self._ext[top, d]
        C = b.consts[top]
        centre = C[:3, 3].copy()
        if b.kind[top] == PRISM:
            centre += C[:3, 2] * (self.lo[top] + self.hi[top]) / 2.0
            ext += (self.hi[top] - self.lo[top]) / 2.0
        return centre, ext

    def prune(
        self,
        meet: Meet,
        xa: FloatArray,
        ra: FloatArray,
        xb: FloatArray,
        rb: FloatArray,
        limit: float,
    ) -> tuple[SidePrune, SidePrune]:
        """Which spheres of bodies ``meet.a`` and ``meet.b`` (centres in their body frames,
        radii) can come within ``limit`` of a sphere of the other body; the rest are dropped."""
        a, b, lca = meet.a, meet.b, meet.lca
        with np.errstate(invalid="ignore", over="ignore"):
            if lca not in (a, b):
                ca, ea = self._ball(meet.top_a, a)
                cb, eb = self._ball(meet.top_b, b)
                far = float(np.linalg.norm(ca - cb)) - ea - eb
                ga = far - (np.linalg.norm(xa, axis=1) + ra) - float(np.max(_extent(xb, rb)))
                gb = far - (np.linalg.norm(xb, axis=1) + rb) - float(np.max(_extent(xa, ra)))
                return _side(ga, limit), _side(gb, limit)
            swap = lca == b
            top = meet.top_a if swap else meet.top_b
            if swap:  # the ancestor side first
                a, b, xa, ra, xb, rb = b, a, xb, rb, xa, ra
            if top == b and self.bodies.kind[b] != PRISM:
                g_anc, g_desc = self._circles(b, xa, ra, xb, rb)
            else:
                centre, ext = self._ball(top, b)
                u = np.linalg.norm(xa - centre, axis=1) - ra  # [m_a]
                v = _extent(xb, rb) + ext  # [m_b]
                g_anc, g_desc = u - float(np.max(v)), float(np.min(u)) - v
        anc, desc = _side(g_anc, limit), _side(g_desc, limit)
        return (desc, anc) if swap else (anc, desc)

    def on_axis(
        self, a: int, b: int, xa: FloatArray, xb: FloatArray
    ) -> tuple[BoolArray, BoolArray]:
        """Spheres of ``a`` and ``b`` (centres in their body frames) whose distance to every
        sphere of the other body never changes: when one body turns about a revolute joint of
        the other, a centre on that joint's axis keeps its distance to everything across it.
        Such sphere pairs are decided once instead of sampled. Both masks are all False unless
        one body is the other's child."""
        none_a, none_b = np.zeros(len(xa), dtype=np.bool_), np.zeros(len(xb), dtype=np.bool_)
        bd = self.bodies
        for anc, desc, x_anc, x_desc, swap in ((a, b, xa, xb, False), (b, a, xb, xa, True)):
            if desc == 0 or bd.parent[desc] != anc or bd.kind[desc] == PRISM:
                continue
            C = bd.consts[desc]
            y = (x_anc - C[:3, 3]) @ C[:3, :3]  # the ancestor's centres in the joint frame
            on_anc = np.hypot(y[:, 0], y[:, 1]) <= _ON_AXIS
            on_desc = np.hypot(x_desc[:, 0], x_desc[:, 1]) <= _ON_AXIS
            return (on_desc, on_anc) if swap else (on_anc, on_desc)
        return none_a, none_b

    def _circles(
        self, j: int, xa: FloatArray, ra: FloatArray, xb: FloatArray, rb: FloatArray
    ) -> tuple[FloatArray, FloatArray]:
        """Body ``j`` turns about one revolute joint of body ``a``: each sphere centre of ``j``
        sweeps a circle about the joint axis. Smallest gap of each sphere of ``a`` [m_a] and of
        ``j`` [m_b] to any sphere of the other side over the whole turn."""
        C = self.bodies.consts[j]
        y = (xa - C[:3, 3]) @ C[:3, :3]  # a's centres in the joint frame
        rho_a, z_a = np.hypot(y[:, 0], y[:, 1]), y[:, 2]
        rho_b, z_b = np.hypot(xb[:, 0], xb[:, 1]), xb[:, 2]
        g_a = np.full(len(ra), np.inf)
        g_b = np.full(len(rb), np.inf)
        step = max(1, _BLOCK // max(1, len(rb)))
        for s0 in range(0, len(ra), step):
            sl = slice(s0, s0 + step)
            d = np.hypot(rho_a[sl, None] - rho_b[None, :], z_a[sl, None] - z_b[None, :])
            d -= ra[sl, None] + rb[None, :]
            g_a[sl] = d.min(axis=1)
            np.minimum(g_b, d.min(axis=0), out=g_b)
        return g_a, g_b


#: A centre this close to a joint axis (m) is on it: its distances across the joint change by
#: less than float64 rounding of a report's clearances.
_ON_AXIS = 1e-15
#: Sphere pairs per block of the build-time gap computation (bounded memory).
_BLOCK = 1 << 18


def _extent(x: FloatArray, r: FloatArray) -> FloatArray:
    """Distance of each sphere surface from its body origin."""
    out: FloatArray = np.linalg.norm(x, axis=1) + r
    return out


def _side(gap: FloatArray, limit: float) -> SidePrune:
    """Keep a sphere whose smallest gap may be within ``limit`` (or is not finite)."""
    keep = ~(gap > limit)
    return SidePrune(keep, np.where(keep, np.inf, gap))
