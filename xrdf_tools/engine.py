"""The counting engine behind ``xrdf report``: exact per-frame-pair collision counts, fast.

:class:`CountEngine` answers, for a chunk of configurations, which frame pairs of a
:class:`~xrdf_tools.collision.SphereSet` collide (exactly, as the float64 brute force
``‖c_a − c_b‖ < r_a + r_b`` does) and keeps exact minimum clearances. It is built once per
report; only the c-space joints (``varying``) change between configurations, every other joint
stays at the base configuration. How it gets its speed (see ``docs/report.md``):

1. **Moving bodies.** Frames joined by joints that do not vary (fixed joints, joints outside
   the c-space held at their defaults) are folded into one rigid *body*; sphere centres are
   stored in their body's frame. Forward kinematics runs over bodies only, in float32.
2. **Constant pairs.** Two frames on the same body never move relative to each other: the
   pair is decided once, exactly, at the base configuration.
3. **Body pairs.** Frame pairs between the same two bodies share one relative transform. The
   spheres of body B are moved into the frame of body A with one GEMM, and every sphere pair's
   ``d² − (r_a + r_b)²`` comes out of one more GEMM (the expanded distance
   ``|p|² + |q|² − 2 p·q − r_a² − 2 r_a r_b − r_b²`` with the rank-one radius term folded in),
   in blocks small enough for the CPU cache.
4. **Culling.** Body pairs that are usually far apart first test one bounding sphere per body;
   only configurations within reach (plus the exact-clearance margin) are evaluated.
5. **Exactness.** float32 values carry an error bounded by ``delta`` (a bound derived from
   the robot's size and float32 precision); a frame pair whose smallest ``d² − (r_a + r_b)²``
   lies within ``± delta`` of zero is re-decided in float64 with the plain formula, and so are
   the few configurations that may hold a frame pair's minimum clearance (when it is below the
   margin). Counts therefore equal the float64 brute force, clearances are float64-exact.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Iterator
from concurrent.futures import ProcessPoolExecutor, as_completed
from contextlib import contextmanager
from dataclasses import dataclass, field, replace
from multiprocessing import get_context

import numpy as np
import numpy.typing as npt

from .collision import SphereSet, sphere_world_centers
from .engine_grid import PairGrid, build_pair_grid
from .kinematics import JointType, KinematicModel, fk
from .sampling import Method, sample_rows

F32 = npt.NDArray[np.float32]
FloatArray = npt.NDArray[np.float64]
IntArray = npt.NDArray[np.intp]
BoolArray = npt.NDArray[np.bool_]

__all__ = ["MIN_SAMPLES_PER_JOB", "CountEngine", "EngineTotals", "count_sampled", "default_jobs"]

_EPS32 = float(np.finfo(np.float32).eps)
_ROOT, _ROT, _PRISM = 0, 1, 2
_MOVABLE = (JointType.REVOLUTE, JointType.CONTINUOUS, JointType.PRISMATIC)
#: float32 elements of one distance block (E = [m_a, m_b, n]): sized for a 512 KB L2 cache.
_BLOCK_ELEMENTS = 1 << 15
#: A body pair is culled when fewer than this fraction of pilot configurations is within reach.
_CULL_FRACTION = 0.5
_PILOT = 512
_CULL_SLACK = 1e-6
#: Body pairs with one or two revolute joints between them and at least this many counted
#: sphere pairs get a cell grid (see :mod:`xrdf_tools.engine_grid`).
_GRID_MIN_PAIRS = 1
_GRID_MAX_JOINTS = 2
_GRID_MIN_FAR = 0.25  # a grid whose cells are mostly near saves too little
_ANGLE_MAX = 2 * np.pi
_FK_BLOCK = 8192  # configurations per forward-kinematics block (cache-sized)


# ------------------------------------------------------------------------------------------
# Bodies: rigid groups of frames, float32 forward kinematics
# ------------------------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class _Bodies:
    """Moving bodies in topological order (body 0 is the root frame).

    Each body's frame is turned so that its joint axis is ``z`` (``G`` [nb, 3, 3] maps body
    coordinates to the joint frame's). Body ``j > 0`` then moves as
    ``T_j = T_parent · C_j · Z(θ_j)`` with ``Z`` a rotation about (or a translation along)
    ``z`` by ``θ_j = mult_j · q[col_j] + off_j``: per configuration one small matmul with the
    constant ``C_j`` and a 2-column rotation. ``consts`` [nb, 4, 4] holds ``C_j`` (float64).
    """

    parent: tuple[int, ...]
    kind: tuple[int, ...]
    consts: FloatArray
    consts_t: tuple[F32, ...]  # (4, 4): C_j transposed, for the stacked matmul
    consts_root: tuple[F32, ...]  # (3, 4, 1): the product when the parent is the root
    G: FloatArray
    col: IntArray  # [nb] column of the varying values (-1 for the root)
    mult: FloatArray
    off: FloatArray
    lever: float  # upper bound on the distance of any sphere centre from the origin (m)

    @property
    def n(self) -> int:
        return len(self.parent)

    @property
    def plain(self) -> bool:
        """No mimic factors: joint values are the configuration values themselves."""
        return bool(np.all(self.mult == 1.0) and np.all(self.off == 0.0))


def _z_to(axis: FloatArray) -> FloatArray:
    """A rotation whose third column is the unit vector ``axis``."""
    a = axis / np.linalg.norm(axis)
    helper = np.array([1.0, 0.0, 0.0]) if abs(a[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    x = np.cross(helper, a)
    x /= np.linalg.norm(x)
    return np.column_stack([x, np.cross(a, x), a])


def _body_roots(kin: KinematicModel, varying: IntArray) -> tuple[list[int], IntArray]:
    """Kinematic frames that start a body, and the body of every kinematic frame."""
    var = set(varying.tolist())
    roots = [0]
    body_of = np.zeros(kin.n_frames, dtype=np.intp)
    for f in range(1, kin.n_frames):
        moving = int(kin.joint_type[f]) in _MOVABLE and int(kin.q_index[f]) in var
        if moving:
            body_of[f] = len(roots)
            roots.append(f)
        else:
            body_of[f] = body_of[int(kin.parent[f])]
    return roots, body_of


def _build_bodies(
    kin: KinematicModel,
    varying: IntArray,
    T: FloatArray,
    roots: list[int],
    body_of: IntArray,
    max_local: float,
) -> _Bodies:
    """``T`` [F, 4, 4]: kinematic frames at the base configuration."""
    col_of = {int(c): i for i, c in enumerate(varying.tolist())}
    G = [np.eye(3)] + [_z_to(kin.axis[f]) for f in roots[1:]]
    parent, kind, consts = [-1], [_ROOT], [np.eye(4)]
    cols, mult, off = [-1], [1.0], [0.0]
    lever = max_local
    for j, f in enumerate(roots[1:], start=1):
        pf = int(kin.parent[f])
        pb = int(body_of[pf])
        C = np.linalg.inv(T[roots[pb]]) @ T[pf] @ kin.origin[f]
        C[:3, 3] = G[pb].T @ C[:3, 3]
        C[:3, :3] = G[pb].T @ C[:3, :3] @ G[j]
        parent.append(pb)
        kind.append(_PRISM if int(kin.joint_type[f]) == JointType.PRISMATIC else _ROT)
        consts.append(C)
        cols.append(col_of[int(kin.q_index[f])])
        mult.append(float(kin.mimic_multiplier[f]))
        off.append(float(kin.mimic_offset[f]))
        lever += float(np.linalg.norm(C[:3, 3]))
        if kind[-1] == _PRISM:
            q = int(kin.q_index[f])
            lever += abs(mult[-1]) * max(abs(kin.lower[q]), abs(kin.upper[q])) + abs(off[-1])
    return _Bodies(
        parent=tuple(parent),
        kind=tuple(kind),
        consts=np.array(consts),
        consts_t=tuple(np.ascontiguousarray(c.T, dtype=np.float32) for c in consts),
        consts_root=tuple(np.ascontiguousarray(c[:3, :, None], dtype=np.float32) for c in consts),
        G=np.array(G),
        col=np.array(cols, dtype=np.intp),
        mult=np.array(mult),
        off=np.array(off),
        lever=lever,
    )


def _joint_values(bodies: _Bodies, q_var: FloatArray) -> F32:
    """float32 joint values [nb − 1, B]; angles beyond ±2π are first reduced in float64."""
    if bodies.plain:
        v32: F32 = np.ascontiguousarray(q_var.astype(np.float32).T[bodies.col[1:]])
        ext = np.maximum(v32.max(axis=1), -v32.min(axis=1))
        if not np.any((np.array(bodies.kind[1:]) == _ROT) & (ext > _ANGLE_MAX)):
            return v32
    v64 = np.ascontiguousarray(q_var.T[bodies.col[1:]])
    v64 *= bodies.mult[1:, None]
    v64 += bodies.off[1:, None]
    wide = (np.array(bodies.kind[1:]) == _ROT) & (
        (v64.max(axis=1) > _ANGLE_MAX) | (v64.min(axis=1) < -_ANGLE_MAX)
    )
    if wide.any():
        v64[wide] = np.remainder(v64[wide] + np.pi, 2 * np.pi) - np.pi
    out: F32 = v64.astype(np.float32)
    return out


def _body_fk(bodies: _Bodies, q_var: FloatArray) -> tuple[F32, F32]:
    """float32 rotations [nb, 3, 3, B] and translations [nb, 3, B] of every body (views of
    :func:`_body_poses`)."""
    T = _body_poses(bodies, q_var)
    return T[:, :, :3], T[:, :, 3]


def _body_poses(bodies: _Bodies, q_var: FloatArray) -> F32:
    """float32 poses [nb, 3, 4, B] (``[R | t]`` per body), computed in cache-sized column
    blocks written straight into the result."""
    B = q_var.shape[0]
    T = np.empty((bodies.n, 3, 4, B), dtype=np.float32)
    T[0] = np.eye(3, 4, dtype=np.float32)[:, :, None]
    if bodies.n > 1:
        for s0 in range(0, B, _FK_BLOCK):
            sl = slice(s0, min(B, s0 + _FK_BLOCK))
            _body_fk_block(bodies, q_var[sl], T[..., sl])
    return T


def _body_fk_block(bodies: _Bodies, q_var: FloatArray, T: F32) -> None:
    """``T_f = T_parent · C_f · Z(θ_f)``: one matmul with ``C_f``, then Z on columns x, y."""
    vals = _joint_values(bodies, q_var)
    sin, cos = np.sin(vals), np.cos(vals)
    tmp = np.empty((2, 3, q_var.shape[0]), dtype=np.float32)
    for f in range(1, bodies.n):
        p = bodies.parent[f]
        Y = T[f]
        if p == 0:
            Y[...] = bodies.consts_root[f]
        else:
            np.matmul(bodies.consts_t[f], T[p], out=Y)
        if bodies.kind[f] == _ROT:  # x' = x cos + y sin, y' = y cos − x sin
            c, s = cos[f - 1], sin[f - 1]
            x, y = Y[:, 0], Y[:, 1]
            np.multiply(x, s, out=tmp[0])
            np.multiply(y, s, out=tmp[1])
            x *= c
            x += tmp[1]
            y *= c
            y -= tmp[0]
        else:  # slides along z
            np.multiply(Y[:, 2], vals[f - 1], out=tmp[0])
            Y[:, 3] += tmp[0]


# ------------------------------------------------------------------------------------------
# Body pairs
# ------------------------------------------------------------------------------------------
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


def _bounding(p: FloatArray, r: FloatArray) -> FloatArray:
    c = ((p - r[:, None]).min(axis=0) + (p + r[:, None]).max(axis=0)) / 2
    rad = float(np.max(np.linalg.norm(p - c, axis=1) + r))
    return np.array([*c, rad])


def _position_error(bodies: _Bodies) -> float:
    """Bound (m) on the float32 error of a sphere centre in another body's frame.

    Each body step rounds every rotation entry a few times (a 3-term dot product and the
    Rodrigues combination, ≤ 4 eps relative), the joint angle is rounded once (≤ eps/2 · 2π,
    angles being reduced to ±2π) and translations carry those rotation errors times the lever
    arm (``bodies.lever`` bounds every centre's distance from the origin). A relative transform
    combines two such chains: ``8 eps (n + 2) lever`` covers it with room to spare (the tests
    check that the observed error stays far below).
    """
    return 8.0 * _EPS32 * (bodies.n + 2) * max(bodies.lever, 1e-3)


def _delta(p_a: FloatArray, r_max: float, err: float) -> float:
    """Bound on |float32 − exact| of ``d² − R²`` wherever that value is near zero.

    Near zero ``d ≤ R + err``: a position error ``err`` moves ``d²`` by at most
    ``2 (R + err) err``; the GEMM's own rounding is bounded by a few float32 ulps of the
    largest term, ``(2|p| + R)²``. Doubled for safety.
    """
    pmax = float(np.max(np.linalg.norm(p_a, axis=1))) if len(p_a) else 0.0
    return 2.0 * (2.0 * (r_max + err) * err + 16.0 * _EPS32 * (2.0 * pmax + r_max + err) ** 2)


# ------------------------------------------------------------------------------------------
# Running totals
# ------------------------------------------------------------------------------------------
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


@dataclass
class _Chunk:
    """One chunk: verdicts [K, B], clearance bounds [K], body poses, the configurations, the
    culled pairs' bounding-sphere gaps, and the (frame pair, configuration) entries queued
    for the float64 recheck."""

    hits: BoolArray
    bound: FloatArray
    T: F32 = field(repr=False)  # [nb, 3, 4, B] body poses [R | t]
    q: FloatArray = field(repr=False)
    gaps: F32 | None = field(repr=False)
    prev: FloatArray = field(repr=False)  # [K] exact minimum clearances of earlier chunks
    re_k: list[IntArray] = field(default_factory=list, repr=False)
    re_b: list[IntArray] = field(default_factory=list, repr=False)


# ------------------------------------------------------------------------------------------
# The engine
# ------------------------------------------------------------------------------------------
class CountEngine:
    """Exact per-frame-pair collision counting for configurations that vary ``varying``.

    ``spheres``: the frame pairs to count (e.g. a :meth:`SphereSet.select_frame_pairs`
    selection). ``varying``: indices into the actuated joints that change (the c-space);
    every other joint stays at ``q_base`` [n]. ``margin``: minimum clearances below it are
    exact (float64), larger ones may come back as lower bounds.
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
        self.varying = np.asarray(varying, dtype=np.intp)
        self.q_base = np.asarray(q_base, dtype=np.float64).copy()
        self.margin = max(float(margin), 0.0)
        self.K = spheres.n_frame_pairs
        T = fk(kin, self.q_base)  # [F, 4, 4]
        roots, body_of = _body_roots(kin, self.varying)
        self.sphere_body, self.local = self._local_centers(T, roots, body_of)
        max_local = float(np.max(np.linalg.norm(self.local, axis=1))) if len(self.local) else 0.0
        self.bodies = _build_bodies(kin, self.varying, T, roots, body_of, max_local)
        self.err = _position_error(self.bodies)
        self.body_bound = self._body_bounds()
        self.const_k, self.const_hit, self.const_clear = self._constant_pairs()
        self.pairs = self._body_pairs()
        self.delta_k, self.rlo_k, self.rhi_k = self._pair_constants()

    # --- construction --------------------------------------------------------------------
    def _local_centers(
        self, T: FloatArray, roots: list[int], body_of: IntArray
    ) -> tuple[IntArray, FloatArray]:
        s = self.spheres
        kf = s.kin_frame
        body = body_of[kf]
        inv = {int(b): np.linalg.inv(T[roots[int(b)]]) for b in np.unique(body)}
        G = [np.eye(3)] + [_z_to(self.kin.axis[f]) for f in roots[1:]]
        for b, M in inv.items():  # into the z-aligned body frame
            M[:3, :] = G[b].T @ M[:3, :]
        local = np.empty((s.n_spheres, 3))
        for i in range(s.n_spheres):
            M = inv[int(body[i])] @ T[int(kf[i])]
            local[i] = M[:3, :3] @ s.local_centers[i] + M[:3, 3]
        return body, local

    def _body_bounds(self) -> FloatArray:
        """Bounding sphere [nb, 4] (centre in the body frame, radius) of each body's spheres."""
        out = np.zeros((self.bodies.n, 4))
        sr = self.spheres.self_radii
        for b in np.unique(self.sphere_body).tolist():
            mine = self.sphere_body == b
            out[b] = _bounding(self.local[mine], sr[mine])
        out[:, 3] += _CULL_SLACK
        return out

    def _frame_body(self, f: int) -> int:
        sl = self.spheres.spheres_of(f)
        return int(self.sphere_body[sl.start])

    def _constant_pairs(self) -> tuple[IntArray, BoolArray, FloatArray]:
        s = self.spheres
        ks = [
            k
            for k in range(self.K)
            if self._frame_body(int(s.frame_pair_a[k])) == self._frame_body(int(s.frame_pair_b[k]))
        ]
        karr = np.array(ks, dtype=np.intp)
        if not ks:
            return karr, np.zeros(0, dtype=np.bool_), np.zeros(0)
        hit, clr = self._exact(karr, np.zeros(len(ks), dtype=np.intp), self.q_base[None, :])
        return karr, hit, clr

    def _body_pairs(self) -> list[_BodyPair]:
        s = self.spheres
        groups: dict[tuple[int, int], list[int]] = {}
        const = set(self.const_k.tolist())
        for k in range(self.K):
            if k in const:
                continue
            ba = self._frame_body(int(s.frame_pair_a[k]))
            bb = self._frame_body(int(s.frame_pair_b[k]))
            groups.setdefault((min(ba, bb), max(ba, bb)), []).append(k)
        pairs = [self._make_pair(key, ks) for key, ks in groups.items()]
        return self._choose_culling(pairs)

    def _make_pair(self, key: tuple[int, int], ks: list[int]) -> _BodyPair:
        s = self.spheres
        side: dict[int, list[int]] = {key[0]: [], key[1]: []}
        for k in ks:
            for f in (int(s.frame_pair_a[k]), int(s.frame_pair_b[k])):
                lst = side[self._frame_body(f)]
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
        p, ra = self.local[ia], s.self_radii[ia]
        q, rb = self.local[ib], s.self_radii[ib]
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
            delta=_delta(p, r_max, self.err),
            relevant=_relevant(len(ia), len(ib), blocks),
        )

    def _choose_culling(self, pairs: list[_BodyPair]) -> list[_BodyPair]:
        """Give body pairs a cell grid (one or two joints between them) or, when a fixed pilot
        sample finds them mostly out of reach, a bounding-sphere cull."""
        if not pairs or len(self.varying) == 0:
            return pairs
        lo = self.kin.lower[self.varying]
        hi = self.kin.upper[self.varying]
        q = np.random.default_rng(12345).uniform(lo, hi, size=(_PILOT, len(self.varying)))
        R, t = _body_fk(self.bodies, q)
        out = []
        for bp in pairs:
            grid = self._grid_for(bp)
            if grid is not None and grid.far_fraction >= _GRID_MIN_FAR:
                out.append(replace(bp, grid=grid))
                continue
            g2 = self._gaps2(R, t, [bp])[0]
            near = float(np.mean(g2 <= self._cull_reach(bp) ** 2))
            out.append(replace(bp, cull=near < _CULL_FRACTION))
        return out

    def _grid_for(self, bp: _BodyPair) -> PairGrid | None:
        path = _path_joints(self.bodies, bp.a, bp.b)
        if path is None or int(bp.relevant.sum()) < _GRID_MIN_PAIRS:
            return None
        anc, joints = path
        p, q = self._pair_points(bp)
        rsum, relevant = bp.rsum.astype(np.float64), bp.relevant
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
        )

    def _pair_points(self, bp: _BodyPair) -> tuple[FloatArray, FloatArray]:
        """float64 sphere centres of both sides of ``bp`` in their own body frames."""
        return self.local[bp.ia], self.local[bp.ib]

    def _pair_constants(self) -> tuple[FloatArray, FloatArray, FloatArray]:
        s = self.spheres
        delta = np.zeros(self.K)
        rlo = np.zeros(self.K)
        rhi = np.zeros(self.K)
        for bp in self.pairs:
            for k, _, _ in bp.blocks:
                lo, hi = int(s.pair_start[k]), int(s.pair_start[k + 1])
                rs = s.self_radii[s.pair_i[lo:hi]] + s.self_radii[s.pair_j[lo:hi]]
                delta[k] = bp.delta
                rlo[k], rhi[k] = float(rs.min()), float(rs.max())
        return delta, rlo, rhi

    # --- per chunk -----------------------------------------------------------------------
    def _gaps2(self, R: F32, t: F32, pairs: list[_BodyPair]) -> F32:
        """float32 squared distance between the bounding-sphere centres of each pair's bodies
        [P, B], in cache-sized column blocks."""
        ia = [bp.a for bp in pairs]
        ib = [bp.b for bp in pairs]
        c = self.body_bound[:, :3].astype(np.float32)
        B = R.shape[-1]
        out = np.empty((len(pairs), B), dtype=np.float32)
        for s0 in range(0, B, _FK_BLOCK):
            sl = slice(s0, min(B, s0 + _FK_BLOCK))
            Rs = R[..., sl]
            W = t[..., sl] + Rs[:, :, 0] * c[:, 0, None, None]  # [nb, 3, n]
            W += Rs[:, :, 1] * c[:, 1, None, None]
            W += Rs[:, :, 2] * c[:, 2, None, None]
            g = out[:, sl]
            for i in range(3):
                D = W[ia, i] - W[ib, i]
                if i == 0:
                    np.multiply(D, D, out=g)
                else:
                    D *= D
                    g += D
        return out

    def _cull_reach(self, bp: _BodyPair) -> float:
        """Bounding-sphere centre distance beyond which ``bp`` is farther apart than the
        margin, float32 error included."""
        return (
            float(self.body_bound[bp.a, 3] + self.body_bound[bp.b, 3])
            + self.margin
            + (4 * self.err)
        )

    def count(self, q_var: npt.ArrayLike, totals: EngineTotals | None = None) -> BoolArray:
        """Collision flags [K, B] of configurations ``q_var`` [B, n_varying] (float64).

        When ``totals`` is given, the chunk's counts and clearances are added to it.
        """
        q = np.asarray(q_var, dtype=np.float64)
        if q.ndim != 2 or q.shape[1] != len(self.varying):
            raise ValueError(f"q_var must be [B, {len(self.varying)}], got {list(q.shape)}")
        B = q.shape[0]
        T = _body_poses(self.bodies, q)
        culled = [bp for bp in self.pairs if bp.cull]
        gaps = self._gaps2(T[:, :, :3], T[:, :, 3], culled) if culled else None
        hits = np.zeros((self.K, B), dtype=np.bool_)
        # the best clearance so far only narrows the candidates (it never changes a result)
        prev = totals.min_clearance if totals is not None else np.full(self.K, np.inf)
        ch = _Chunk(hits, np.full(self.K, np.inf), T, q, gaps, prev)
        row = 0
        for bp in self.pairs:
            sel = self._select(bp, ch, row)
            row += bp.cull
            if sel is None or len(sel):
                self._classify(bp, ch, sel, self._evaluate(bp, ch, sel))
        best = np.full(self.K, np.inf)
        n_exact = self._recheck(ch, best)
        if len(self.const_k):
            hits[self.const_k] = self.const_hit[:, None]
            best[self.const_k] = self.const_clear
        if totals is not None:
            totals.hits += hits.sum(axis=1)
            np.minimum(totals.min_clearance, best, out=totals.min_clearance)
            np.minimum(totals.clearance_bound, ch.bound, out=totals.clearance_bound)
            totals.configurations += B
            totals.rechecked += n_exact
        return hits

    def _select(self, bp: _BodyPair, ch: _Chunk, row: int) -> IntArray | None:
        """Configurations of the chunk to evaluate for ``bp`` (None: all of them).

        The skipped ones are farther apart than the margin; their clearance lower bound goes
        into the chunk's bounds.
        """
        if bp.grid is not None:
            near = bp.grid.near(ch.q)
            low = bp.grid.far_bound
        elif bp.cull and ch.gaps is not None:
            g2 = ch.gaps[row]
            reach = self._cull_reach(bp)
            near = g2 <= np.float32(reach**2)
            far_min = float(np.min(g2, where=~near, initial=np.inf))
            low = math.sqrt(far_min) - reach + self.margin
        else:
            return None
        sel = np.flatnonzero(near)
        if len(sel) == len(near):
            return None
        for k, _, _ in bp.blocks:
            ch.bound[k] = min(ch.bound[k], low)
        return sel

    def _evaluate(self, bp: _BodyPair, ch: _Chunk, sel: IntArray | None) -> F32:
        """float32 minima of ``d² − R²`` [blocks, n] per frame pair of ``bp`` for the selected
        configurations (all when ``sel`` is None)."""
        Trel = self._pair_transform(bp, ch, sel)  # [3, 4, n]
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

    def _pair_transform(self, bp: _BodyPair, ch: _Chunk, sel: IntArray | None) -> F32:
        """``T_a⁻¹ T_b`` [3, 4, n] at the selected configurations (all when None)."""
        Ta, Tb = ch.T[bp.a], ch.T[bp.b]
        if sel is not None:
            Ta, Tb = np.take(Ta, sel, axis=-1), np.take(Tb, sel, axis=-1)
        return _relative(Ta[:, :3], Ta[:, 3], Tb[:, :3], Tb[:, 3])

    def _classify(self, bp: _BodyPair, ch: _Chunk, sel: IntArray | None, em: F32) -> None:
        """Verdicts from the float32 minima ``em`` [blocks, n]; queue the float64 rechecks.

        Entries within ``± delta`` of zero are unsure. For the minimum clearance, every
        configuration whose clearance may lie below ``min(margin, an upper bound of the
        chunk's smallest)`` is a candidate; candidates are narrowed in float32
        (:meth:`_refine`). Everything not rechecked has a clearance of at least the bound
        recorded for its frame pair.
        """
        ks = np.array([k for k, _, _ in bp.blocks], dtype=np.intp)
        d = np.float32(bp.delta)
        cols = np.arange(em.shape[1]) if sel is None else sel
        hit = em < -d
        for i, k in enumerate(ks.tolist()):
            ch.hits[k, cols] = hit[i]
        e_min = em.min(axis=1).astype(np.float64)
        rlo, rhi = self.rlo_k[ks], self.rhi_k[ks]
        thr = np.minimum(self.margin, _clearance_hi(e_min + bp.delta, rlo, rhi))
        np.minimum(thr, ch.prev[ks], out=thr)
        e_star = (_energy_at(thr, rlo, rhi) + bp.delta).astype(np.float32)
        cand = em <= e_star[:, None]
        has_cand = cand.any(axis=1)
        low = np.where(has_cand, thr, _clearance_lo(e_min - bp.delta, rlo, rhi))
        np.minimum(ch.bound[ks], low, out=low)
        ch.bound[ks] = low
        unsure = np.abs(em) <= d
        if has_cand.any():
            cand = self._refine(bp, ch, cols, cand, ks)
        bi, bj = np.nonzero(unsure | cand)
        if len(bi):
            ch.re_k.append(ks[bi])
            ch.re_b.append(cols[bj])

    def _refine(
        self, bp: _BodyPair, ch: _Chunk, cols: IntArray, cand: BoolArray, ks: IntArray
    ) -> BoolArray:
        """Narrow minimum-clearance candidates with float32 clearances (error ≤ ``tau``).

        ``d² − R²`` ranks configurations only roughly when a frame pair's radii differ, so the
        candidates' clearances are computed directly; only those that can be within ``tau``
        of the smallest are kept for float64. The dropped ones' clearances exceed the limit
        recorded in the frame pair's bound.
        """
        tau = 2.0 * self.err + 8.0 * _EPS32 * self.bodies.lever
        idx = np.flatnonzero(cand.any(axis=0))
        clr = self._direct(bp, ch, cols[idx])
        kept = np.zeros_like(cand)
        for i, (k, _, _) in enumerate(bp.blocks):
            ci = cand[i, idx]
            if not ci.any():
                continue
            ck = np.where(ci, clr[i], np.inf)
            lim = min(self.margin, float(ch.prev[k]), float(ck.min()) + tau)
            kept[i, idx[ck - tau <= lim]] = True
            ch.bound[k] = min(ch.bound[k], lim)
        return kept

    def _recheck(self, ch: _Chunk, best: FloatArray) -> int:
        """Decide the queued entries in float64: exact verdicts into ``ch.hits``, exact
        clearances into ``best``. Returns how many entries were redone."""
        if not ch.re_k:
            return 0
        ks, bs = np.concatenate(ch.re_k), np.concatenate(ch.re_b)
        ub, inv = np.unique(bs, return_inverse=True)
        qf = np.repeat(self.q_base[None, :], len(ub), axis=0)
        qf[:, self.varying] = ch.q[ub]
        hit, clr = self._exact(ks, inv, qf)
        ch.hits[ks, bs] = hit
        np.minimum.at(best, ks, clr)
        return len(ks)

    def _direct(self, bp: _BodyPair, ch: _Chunk, cols: IntArray) -> F32:
        """float32 clearance [blocks, n] of each frame pair of ``bp`` at configurations
        ``cols`` (every sphere pair computed directly, in cache-sized column blocks)."""
        out = np.empty((len(bp.blocks), len(cols)), dtype=np.float32)
        step = max(1, _BLOCK_ELEMENTS // bp.rsum.size)
        for s0 in range(0, len(cols), step):
            c = cols[s0 : s0 + step]
            qp = np.matmul(bp.q_aug, self._pair_transform(bp, ch, c))  # [3, m_b, w]
            diff = qp[:, None, :, :] - bp.p32.T[:, :, None, None]
            d = np.sqrt(np.einsum("kijn,kijn->ijn", diff, diff))
            d -= bp.rsum[:, :, None]
            for i, (_, rows, cs) in enumerate(bp.blocks):
                np.min(d[rows, cs], axis=(0, 1), out=out[i, s0 : s0 + len(c)])
        return out

    def _exact(
        self, ks: IntArray, rows: IntArray, q_full: FloatArray
    ) -> tuple[BoolArray, FloatArray]:
        """float64 verdicts and clearances of frame pairs ``ks`` at ``q_full[rows]``."""
        s = self.spheres
        c = sphere_world_centers(self.kin, s, q_full)  # [U, S, 3]
        hit = np.zeros(len(ks), dtype=np.bool_)
        clr = np.zeros(len(ks))
        order = np.argsort(ks, kind="stable")
        uk, starts = np.unique(ks[order], return_index=True)
        ends = np.append(starts[1:], len(order))
        for k, s0, s1 in zip(uk.tolist(), starts.tolist(), ends.tolist(), strict=True):
            lo, hi = int(s.pair_start[k]), int(s.pair_start[k + 1])
            pi, pj = s.pair_i[lo:hi], s.pair_j[lo:hi]
            rs = s.self_radii[pi] + s.self_radii[pj]
            step = max(1, _BLOCK_ELEMENTS // (hi - lo))
            for e0 in range(s0, s1, step):  # bounded memory
                ent = order[e0 : min(s1, e0 + step)]
                cc = c[rows[ent]]
                diff = cc[:, pi] - cc[:, pj]
                d2 = np.einsum("bpk,bpk->bp", diff, diff)
                hit[ent] = (d2 < rs * rs).any(axis=1)
                clr[ent] = (np.sqrt(d2) - rs).min(axis=1)
        return hit, clr


def _relevant(m_a: int, m_b: int, blocks: list[tuple[int, slice, slice]]) -> BoolArray:
    out = np.zeros((m_a, m_b), dtype=np.bool_)
    for _, rows, cols in blocks:
        out[rows, cols] = True
    return out


def _path_joints(bodies: _Bodies, a: int, b: int) -> tuple[int, list[int]] | None:
    """(ancestor, bodies whose revolute joints lie between a and b, outer first) when one body
    is an ancestor of the other at most two joints away; None otherwise."""
    for anc, desc in ((a, b), (b, a)):
        joints = [desc]
        while len(joints) <= _GRID_MAX_JOINTS and bodies.parent[joints[0]] >= 0:
            if bodies.parent[joints[0]] == anc:
                if all(bodies.kind[j] == _ROT for j in joints):
                    return anc, joints
                return None
            joints.insert(0, bodies.parent[joints[0]])
    return None


def _side_rows(s: SphereSet, frames: list[int]) -> tuple[IntArray, dict[int, slice]]:
    """Sphere indices of ``frames`` (in frame order) and each frame's slice of them."""
    idx: list[int] = []
    where: dict[int, slice] = {}
    for f in sorted(frames):
        sl = s.spheres_of(f)
        where[f] = slice(len(idx), len(idx) + sl.stop - sl.start)
        idx.extend(range(sl.start, sl.stop))
    return np.array(idx, dtype=np.intp), where


def _replace_cull(bp: _BodyPair, cull: bool) -> _BodyPair:
    return replace(bp, cull=cull)


def _relative(Ra: F32, ta: F32, Rb: F32, tb: F32) -> F32:
    """``[Ra^T Rb | Ra^T (tb − ta)]`` per configuration: [3, 4, n]."""
    TB = np.empty((3, 4, Rb.shape[-1]), dtype=np.float32)
    TB[:, :3] = Rb
    np.subtract(tb, ta, out=TB[:, 3])
    out: F32 = np.einsum("lkn,lmn->kmn", Ra, TB)
    return out


def _energy_at(c: FloatArray, rlo: FloatArray, rhi: FloatArray) -> FloatArray:
    """Largest ``e`` with ``_clearance_lo(e) <= c`` (the inverse of that monotone bound)."""
    with np.errstate(invalid="ignore"):
        neg = np.where(c >= -rlo, (c + rlo) ** 2 - rlo**2, -(c**2))
        e = np.where(c >= 0, (c + rhi) ** 2 - rhi**2, np.where(c < -rhi, -np.inf, neg))
    return np.where(np.isfinite(c), e, np.inf)


def _clearance_lo(e: FloatArray, rlo: FloatArray, rhi: FloatArray) -> FloatArray:
    """Lower bound of ``d − R`` given ``d² − R² >= e`` and ``R`` in [rlo, rhi]."""
    with np.errstate(invalid="ignore"):
        pos = np.sqrt(np.maximum(e + rhi**2, 0.0)) - rhi
        neg = np.where(e <= -(rlo**2), -np.sqrt(np.maximum(-e, 0.0)), np.sqrt(e + rlo**2) - rlo)
    out = np.where(e >= 0, pos, np.maximum(neg, -rhi))
    return np.where(np.isfinite(e), out, np.inf)


def _clearance_hi(e: FloatArray, rlo: FloatArray, rhi: FloatArray) -> FloatArray:
    """Upper bound of ``d − R`` given ``d² − R² <= e`` for one pair, ``R`` in [rlo, rhi]."""
    with np.errstate(invalid="ignore"):
        pos = np.sqrt(np.maximum(e + rlo**2, 0.0)) - rlo
        neg = np.sqrt(np.maximum(e + rhi**2, 0.0)) - rhi
    out = np.where(e >= 0, pos, neg)
    return np.where(np.isfinite(e), out, np.inf)


# ------------------------------------------------------------------------------------------
# Sampling driver, one process or several
# ------------------------------------------------------------------------------------------
#: Below this many samples per worker, starting a worker process costs more than it saves.
MIN_SAMPLES_PER_JOB = 1_000_000
_BLAS_VARS = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMEXPR_NUM_THREADS")
ProgressFn = Callable[[int, int], None]
_WORKER: dict[str, CountEngine] = {}


def default_jobs() -> int:
    """The CPU cores this process may run on."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


def count_sampled(
    engine: CountEngine,
    lower: npt.ArrayLike,
    upper: npt.ArrayLike,
    n: int,
    *,
    method: Method,
    seed: int,
    chunk: int,
    jobs: int = 1,
    progress: ProgressFn | None = None,
) -> EngineTotals:
    """Count ``n`` samples of the stream ``sample_rows(lower, upper, …, method, seed)``.

    The sample is cut into chunks of ``chunk`` rows; with ``jobs > 1`` the chunks go to worker
    processes (each pinned to one BLAS thread). Totals are sums and minima over chunks, so the
    result is identical for any ``jobs``. Fewer workers are started when the sample is small
    (at least :data:`MIN_SAMPLES_PER_JOB` samples each).
    """
    starts = list(range(0, n, chunk))
    tasks = [(s0, min(chunk, n - s0)) for s0 in starts]
    workers = max(1, min(jobs, n // MIN_SAMPLES_PER_JOB, len(tasks)))
    totals = EngineTotals.empty(engine.K)
    lo, hi = np.asarray(lower, dtype=np.float64), np.asarray(upper, dtype=np.float64)
    done = 0
    if workers == 1:
        parts: Iterator[EngineTotals] = (
            _count_rows(engine, lo, hi, s0, m, method, seed) for s0, m in tasks
        )
        for part in parts:
            totals.merge(part)
            done += part.configurations
            if progress is not None:
                progress(done, n)
        return totals
    with (
        _one_blas_thread(),
        ProcessPoolExecutor(
            max_workers=workers,
            mp_context=get_context("spawn"),
            initializer=_worker_init,
            initargs=(engine,),
        ) as pool,
    ):
        futures = [pool.submit(_worker_rows, lo, hi, s0, m, method, seed) for s0, m in tasks]
        for fut in as_completed(futures):
            part = fut.result()
            totals.merge(part)
            done += part.configurations
            if progress is not None:
                progress(done, n)
    return totals


def _count_rows(
    engine: CountEngine,
    lo: FloatArray,
    hi: FloatArray,
    start: int,
    m: int,
    method: Method,
    seed: int,
) -> EngineTotals:
    totals = EngineTotals.empty(engine.K)
    engine.count(sample_rows(lo, hi, start, m, method=method, seed=seed), totals)
    return totals


def _worker_init(engine: CountEngine) -> None:
    _WORKER["engine"] = engine


def _worker_rows(
    lo: FloatArray, hi: FloatArray, start: int, m: int, method: Method, seed: int
) -> EngineTotals:
    return _count_rows(_WORKER["engine"], lo, hi, start, m, method, seed)


@contextmanager
def _one_blas_thread() -> Iterator[None]:
    """Worker processes inherit this environment: one BLAS/OpenMP thread each."""
    saved = {v: os.environ.get(v) for v in _BLAS_VARS}
    os.environ.update(dict.fromkeys(_BLAS_VARS, "1"))
    try:
        yield
    finally:
        for v, old in saved.items():
            if old is None:
                os.environ.pop(v, None)
            else:
                os.environ[v] = old
