"""Moving bodies: rigid groups of frames and their float32 forward kinematics.

Frames joined by joints that do not vary (fixed joints, joints outside the c-space held at
their defaults) are folded into one rigid *body*; sphere centres are stored in their body's
frame (:func:`body_local_centers`). Each body's frame is turned so that its joint axis is ``z``,
which makes a joint step one small matmul with a constant plus a 2-column rotation
(:func:`body_poses`). :func:`position_error` bounds the float32 error this introduces; the
engine's guard band is derived from it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from ...robot.kinematics import JointType, KinematicModel
from ...util.arrays import FloatArray, IntArray, sorted_unique
from ..collision import SphereSet

F32 = npt.NDArray[np.float32]

EPS32 = float(np.finfo(np.float32).eps)
#: Body kinds: the root, a revolute/continuous joint (turns about z), a prismatic one (slides).
ROOT, ROT, PRISM = 0, 1, 2
_MOVABLE = (JointType.REVOLUTE, JointType.CONTINUOUS, JointType.PRISMATIC)
_ANGLE_MAX = 2 * np.pi
_FK_BLOCK = 8192  # configurations per forward-kinematics block (cache-sized)


@dataclass(frozen=True, eq=False)
class Bodies:
    """Moving bodies in topological order (body 0 is the root frame).

    Each body's frame is turned so that its joint axis is ``z`` (``G`` [nb, 3, 3] maps body
    coordinates to the joint frame's). Body ``j > 0`` then moves as
    ``T_j = T_parent · C_j · Z(θ_j)`` with ``Z`` a rotation about (or a translation along)
    ``z`` by ``θ_j = mult_j · q[col_j] + off_j``: per configuration one small matmul with the
    constant ``C_j`` and a 2-column rotation. ``consts`` [nb, 4, 4] holds ``C_j`` (float64).
    """

    parent: tuple[int, ...]
    depth: tuple[int, ...]  # joints between the root and each body
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


def relative_columns(kin: KinematicModel, varying: IntArray, frames: IntArray) -> IntArray:
    """Positions in ``varying`` of the joints that move some of the kinematic frames
    ``frames`` relative to the others (directly or through a mimic follower). A joint above
    all of them (a mobile base carrying the whole arm) or above none moves them all alike: no
    distance between them depends on it."""
    inside = np.zeros(kin.n_frames, dtype=np.intp)  # frames of ``frames`` in each subtree
    inside[sorted_unique(np.asarray(frames, dtype=np.intp))] = 1
    total = int(inside.sum())
    for f in range(kin.n_frames - 1, 0, -1):  # a parent comes before its children
        inside[int(kin.parent[f])] += inside[f]
    moves = {
        int(kin.q_index[f])
        for f in range(1, kin.n_frames)
        if int(kin.joint_type[f]) in _MOVABLE and 0 < inside[f] < total
    }
    return np.array([i for i, v in enumerate(varying.tolist()) if v in moves], dtype=np.intp)


def body_roots(kin: KinematicModel, varying: IntArray) -> tuple[list[int], IntArray]:
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


def _axis_frames(kin: KinematicModel, roots: list[int]) -> list[FloatArray]:
    """Per body, the rotation from its z-aligned body frame to its joint frame (``Bodies.G``)."""
    return [np.eye(3)] + [_z_to(kin.axis[f]) for f in roots[1:]]


def body_local_centers(
    kin: KinematicModel,
    spheres: SphereSet,
    T: FloatArray,
    roots: list[int],
    body_of: IntArray,
) -> tuple[IntArray, FloatArray]:
    """Body of every sphere [S] and its centre in that body's z-aligned frame [S, 3] (float64),
    from the kinematic frames ``T`` [F, 4, 4] at the base configuration."""
    kf = spheres.kin_frame
    body = body_of[kf]
    inv = {int(b): np.linalg.inv(T[roots[int(b)]]) for b in sorted_unique(body)}
    G = _axis_frames(kin, roots)
    for b, M in inv.items():  # into the z-aligned body frame
        M[:3, :] = G[b].T @ M[:3, :]
    local = np.empty((spheres.n_spheres, 3))
    for i in range(spheres.n_spheres):
        M = inv[int(body[i])] @ T[int(kf[i])]
        local[i] = M[:3, :3] @ spheres.local_centers[i] + M[:3, 3]
    return body, local


def build_bodies(
    kin: KinematicModel,
    varying: IntArray,
    T: FloatArray,
    roots: list[int],
    body_of: IntArray,
    max_local: float,
) -> Bodies:
    """``T`` [F, 4, 4]: kinematic frames at the base configuration."""
    col_of = {int(c): i for i, c in enumerate(varying.tolist())}
    G = _axis_frames(kin, roots)
    parent, depth, kind, consts = [-1], [0], [ROOT], [np.eye(4)]
    cols, mult, off = [-1], [1.0], [0.0]
    lever = max_local
    for j, f in enumerate(roots[1:], start=1):
        pf = int(kin.parent[f])
        pb = int(body_of[pf])
        C = np.linalg.inv(T[roots[pb]]) @ T[pf] @ kin.origin[f]
        C[:3, 3] = G[pb].T @ C[:3, 3]
        C[:3, :3] = G[pb].T @ C[:3, :3] @ G[j]
        parent.append(pb)
        depth.append(depth[pb] + 1)
        kind.append(PRISM if int(kin.joint_type[f]) == JointType.PRISMATIC else ROT)
        consts.append(C)
        cols.append(col_of[int(kin.q_index[f])])
        mult.append(float(kin.mimic_multiplier[f]))
        off.append(float(kin.mimic_offset[f]))
        lever += float(np.linalg.norm(C[:3, 3]))
        if kind[-1] == PRISM:
            q = int(kin.q_index[f])
            lever += abs(mult[-1]) * max(abs(kin.lower[q]), abs(kin.upper[q])) + abs(off[-1])
    return Bodies(
        parent=tuple(parent),
        depth=tuple(depth),
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


def joint_values(bodies: Bodies, q_var: FloatArray) -> F32:
    """float32 joint values [nb − 1, B]; angles beyond ±2π are first reduced in float64."""
    if bodies.plain:
        v32: F32 = np.ascontiguousarray(q_var.astype(np.float32).T[bodies.col[1:]])
        ext = np.maximum(v32.max(axis=1), -v32.min(axis=1))
        if not np.any((np.array(bodies.kind[1:]) == ROT) & (ext > _ANGLE_MAX)):
            return v32
    v64 = np.ascontiguousarray(q_var.T[bodies.col[1:]])
    v64 *= bodies.mult[1:, None]
    v64 += bodies.off[1:, None]
    wide = (np.array(bodies.kind[1:]) == ROT) & (
        (v64.max(axis=1) > _ANGLE_MAX) | (v64.min(axis=1) < -_ANGLE_MAX)
    )
    if wide.any():
        v64[wide] = np.remainder(v64[wide] + np.pi, 2 * np.pi) - np.pi
    out: F32 = v64.astype(np.float32)
    return out


def body_fk(bodies: Bodies, q_var: FloatArray) -> tuple[F32, F32]:
    """float32 rotations [nb, 3, 3, B] and translations [nb, 3, B] of every body (views of
    :func:`body_poses`)."""
    T = body_poses(bodies, q_var)
    return T[:, :, :3], T[:, :, 3]


def body_poses(bodies: Bodies, q_var: FloatArray) -> F32:
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


def _body_fk_block(bodies: Bodies, q_var: FloatArray, T: F32) -> None:
    """``T_f = T_parent · C_f · Z(θ_f)``: one matmul with ``C_f``, then Z on columns x, y."""
    vals = joint_values(bodies, q_var)
    sin, cos = np.sin(vals), np.cos(vals)
    tmp = np.empty((2, 3, q_var.shape[0]), dtype=np.float32)
    for f in range(1, bodies.n):
        p = bodies.parent[f]
        Y = T[f]
        if p == 0:
            Y[...] = bodies.consts_root[f]
        else:
            np.matmul(bodies.consts_t[f], T[p], out=Y)
        if bodies.kind[f] == ROT:  # x' = x cos + y sin, y' = y cos − x sin
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


def body_chains(bodies: Bodies, a: int, b: int) -> tuple[tuple[int, ...], tuple[int, ...]]:
    """The bodies from the lowest common ancestor of ``a`` and ``b`` (excluded) down to ``a``
    and down to ``b``, top first (a walk up from both as long as the path between them)."""
    up_a, up_b = [], []
    depth = bodies.depth
    while a != b:
        if depth[a] >= depth[b]:
            up_a.append(a)
            a = bodies.parent[a]
        else:
            up_b.append(b)
            b = bodies.parent[b]
    return tuple(up_a[::-1]), tuple(up_b[::-1])


def chain_pose(bodies: Bodies, chain: tuple[int, ...], vals: F32) -> F32:
    """float32 poses [3, 4, n] of the last body of ``chain`` in the frame of the first one's
    parent, ``C_1 Z(θ_1) C_2 Z(θ_2) …``, from joint values ``vals`` [nb − 1, n] (as
    :func:`_body_fk_block` steps, but from that parent instead of the root)."""
    n = vals.shape[-1]
    Y = np.empty((3, 4, n), dtype=np.float32)
    if not chain:
        Y[...] = np.eye(3, 4, dtype=np.float32)[:, :, None]
        return Y
    Y[...] = bodies.consts_root[chain[0]]
    _turn(bodies, chain[0], vals, Y)
    for j in chain[1:]:
        Y = np.matmul(bodies.consts_t[j], Y)
        _turn(bodies, j, vals, Y)
    return Y


def _turn(bodies: Bodies, j: int, vals: F32, Y: F32) -> None:
    """Apply body ``j``'s joint motion ``Z(θ_j)`` to the poses ``Y`` [3, 4, n] in place."""
    v = vals[j - 1]
    if bodies.kind[j] == ROT:
        c, s = np.cos(v), np.sin(v)
        x, y = Y[:, 0].copy(), Y[:, 1]
        Y[:, 0] = x * c + y * s
        y *= c
        y -= x * s
    else:
        Y[:, 3] += Y[:, 2] * v


def chain_error(
    bodies: Bodies, chains: tuple[tuple[int, ...], ...], travel: FloatArray, reach: float
) -> tuple[float, float]:
    """Bound (m) on the float32 error of a sphere centre moved along ``chains`` (see
    :func:`position_error`: the same bound with the chains' own lever arm), and that lever
    arm. ``reach``: the largest distance of a sphere centre from its body origin; ``travel``
    [nb]: each body's prismatic travel (0 for a revolute joint)."""
    bodies_on = [j for chain in chains for j in chain]
    lever = reach + sum(
        float(np.linalg.norm(bodies.consts[j][:3, 3])) + float(travel[j]) for j in bodies_on
    )
    lever = max(lever, 1e-3)
    return 8.0 * EPS32 * (len(bodies_on) + 2) * lever, lever


def position_error(bodies: Bodies) -> float:
    """Bound (m) on the float32 error of a sphere centre in another body's frame.

    Each body step rounds every rotation entry a few times (a 3-term dot product and the
    Rodrigues combination, ≤ 4 eps relative), the joint angle is rounded once (≤ eps/2 · 2π,
    angles being reduced to ±2π) and translations carry those rotation errors times the lever
    arm (``bodies.lever`` bounds every centre's distance from the origin). A relative transform
    combines two such chains: ``8 eps (n + 2) lever`` covers it with room to spare (the tests
    check that the observed error stays far below).
    """
    return 8.0 * EPS32 * (bodies.n + 2) * max(bodies.lever, 1e-3)
