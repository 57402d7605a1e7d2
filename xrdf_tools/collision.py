"""Self-collision of sphere models: active pairs as index arrays, batched distances, counting.

Semantics (docs/report.md): spheres ``a`` and ``b`` on *different* frames are in
self-collision when ``‖c_a − c_b‖ < (r_a + s_a) + (r_b + s_b)``, where ``s`` is the frame's
``self_collision.buffer_distance`` (default 0). Pairs on the same frame are never checked; a
pair whose frames are in ``self_collision.ignore`` (either direction) is masked. A sphere with a
raw radius ≤ −1 is an attached-object slot and takes part in no check; a small negative raw
radius becomes a real sphere once buffered (at least 1 mm, as cuRobo builds it). Mimic,
continuous and prismatic joints are handled by :mod:`xrdf_tools.kinematics`.

Layers:

* :func:`build_sphere_set` turns an :class:`~xrdf_tools.model.Xrdf` plus a
  :class:`~xrdf_tools.kinematics.KinematicModel` into a :class:`SphereSet` of flat arrays.
* :func:`sphere_world_centers` and :func:`pair_clearance` are the plain batched building
  blocks (every pair, float64, no culling).
* :func:`contacts` / :func:`colliding_frame_pairs` answer "what collides at this q" (lint's
  default-pose rule, viz).
* :func:`count_chunk` is the fast path for the report: exact per-frame-pair hit flags for a
  chunk of configurations using conservative bounding-sphere culling (see its docstring).

All arithmetic is float64. Counting compares squared distances with squared radius sums, so
a pair's verdict can only differ from an exact real-number evaluation when it is within a
few ulp (~1e-15 m) of touching.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import numpy.typing as npt

from .diagnostics import Diagnostic, Severity
from .errors import did_you_mean
from .kinematics import KinematicModel, fk_batch_last
from .model import Xrdf, clone_order

FloatArray = npt.NDArray[np.float64]
IntArray = npt.NDArray[np.intp]
BoolArray = npt.NDArray[np.bool_]

__all__ = [
    "ChunkResult",
    "Contact",
    "SphereSet",
    "build_sphere_set",
    "colliding_frame_pairs",
    "contacts",
    "count_chunk",
    "pair_clearance",
    "sphere_world_centers",
]

# Slack added to bounding radii so culling stays conservative under float rounding (metres).
_CULL_SLACK = 1e-6


def _ro(a: npt.ArrayLike, dtype: Any) -> Any:
    arr = np.array(a, dtype=dtype, copy=True)
    arr.flags.writeable = False
    return arr


@dataclass(frozen=True, eq=False)
class SphereSet:
    """The self-collision spheres of a robot as flat arrays.

    Frames (``Fs = len(frame_names)``): frames that carry at least one active sphere, in
    kinematic (topological) order; ``frame_kin_index`` [Fs] is each one's index in the
    :class:`~xrdf_tools.kinematics.KinematicModel`.

    Spheres (``S``), grouped by frame in that order (``frame_of_sphere`` is non-decreasing):
    ``frame_of_sphere`` [S] index into ``frame_names``; ``kin_frame`` [S] index into the
    kinematic model's frames; ``sphere_index`` [S] position of the sphere in its frame's list
    of the (clone-resolved) self-collision geometry group; ``local_centers`` [S, 3];
    ``radii`` [S] raw radius; ``self_radii`` [S] = raw radius + the frame's self-collision
    buffer.

    Frame pairs (``K``), ``frame_pair_a < frame_pair_b`` (indices into ``frame_names``), in
    lexicographic order: every pair of sphere frames that is checked, i.e. not masked, plus
    the masked ones when built with ``include_masked=True`` (``frame_pair_masked`` [K] says
    which); :meth:`select_frame_pairs` narrows them.

    Sphere pairs (``P``): ``pair_i < pair_j`` sphere indices on different frames, grouped by
    frame pair: ``pair_frame_pair`` [P] is the frame-pair index of each, so per-frame-pair
    counts are ``np.bincount(pair_frame_pair[hit], minlength=K)``; ``pair_start`` [K + 1]
    gives each frame pair's slice of the pair arrays.
    """

    frame_names: tuple[str, ...]
    frame_kin_index: IntArray
    frame_of_sphere: IntArray
    kin_frame: IntArray
    sphere_index: IntArray
    local_centers: FloatArray
    radii: FloatArray
    self_radii: FloatArray
    frame_pair_a: IntArray
    frame_pair_b: IntArray
    frame_pair_masked: BoolArray
    pair_i: IntArray
    pair_j: IntArray
    pair_frame_pair: IntArray
    pair_start: IntArray
    n_placeholders: int = 0
    _frame_start: IntArray = field(init=False, repr=False)
    _bound_center: FloatArray = field(init=False, repr=False)
    _bound_radius: FloatArray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        ints = (
            "frame_kin_index",
            "frame_of_sphere",
            "kin_frame",
            "sphere_index",
            "frame_pair_a",
            "frame_pair_b",
            "pair_i",
            "pair_j",
            "pair_frame_pair",
            "pair_start",
        )
        for name in ints:
            object.__setattr__(self, name, _ro(getattr(self, name), np.intp))
        for name in ("local_centers", "radii", "self_radii"):
            object.__setattr__(self, name, _ro(getattr(self, name), np.float64))
        object.__setattr__(self, "frame_pair_masked", _ro(self.frame_pair_masked, np.bool_))
        S, Fs, K = len(self.frame_of_sphere), len(self.frame_names), len(self.frame_pair_a)
        if self.local_centers.shape != (S, 3) or self.radii.shape != (S,):
            raise ValueError("SphereSet: local_centers must be [S, 3] and radii [S]")
        if self.pair_start.shape != (K + 1,) or self.frame_kin_index.shape != (Fs,):
            raise ValueError("SphereSet: pair_start must be [K + 1], frame_kin_index [Fs]")
        starts = np.searchsorted(self.frame_of_sphere, np.arange(Fs + 1))
        object.__setattr__(self, "_frame_start", _ro(starts, np.intp))
        # Per-frame bounding sphere of the self-collision spheres (frame coordinates).
        bc = np.zeros((Fs, 3))
        br = np.zeros(Fs)
        for f in range(Fs):
            sl = slice(int(starts[f]), int(starts[f + 1]))
            c, r = self.local_centers[sl], np.maximum(self.self_radii[sl], 0.0)
            bc[f] = ((c - r[:, None]).min(axis=0) + (c + r[:, None]).max(axis=0)) / 2
            br[f] = float(np.max(np.linalg.norm(c - bc[f], axis=1) + self.self_radii[sl]))
        object.__setattr__(self, "_bound_center", _ro(bc, np.float64))
        object.__setattr__(self, "_bound_radius", _ro(br + _CULL_SLACK, np.float64))

    # --- sizes and names -------------------------------------------------------------------
    @property
    def n_spheres(self) -> int:
        return len(self.frame_of_sphere)

    @property
    def n_pairs(self) -> int:
        return len(self.pair_i)

    @property
    def n_frame_pairs(self) -> int:
        return len(self.frame_pair_a)

    def spheres_of(self, frame: int) -> slice:
        """Slice of sphere indices on frame ``frame`` (index into ``frame_names``)."""
        return slice(int(self._frame_start[frame]), int(self._frame_start[frame + 1]))

    def sphere_counts(self) -> dict[str, int]:
        """Active spheres per frame."""
        return {
            f: int(n) for f, n in zip(self.frame_names, np.diff(self._frame_start), strict=True)
        }

    def sphere_label(self, s: int) -> str:
        """``frame[k]``: the sphere's frame and position in that frame's list."""
        return f"{self.frame_names[self.frame_of_sphere[s]]}[{self.sphere_index[s]}]"

    def select_frame_pairs(self, keep: npt.ArrayLike) -> SphereSet:
        """A copy that keeps only the frame pairs where ``keep`` [K] is True (same spheres)."""
        k = np.asarray(keep, dtype=np.bool_)
        if k.shape != (self.n_frame_pairs,):
            raise ValueError(f"keep must be [{self.n_frame_pairs}], got {list(k.shape)}")
        sel = k[self.pair_frame_pair]
        new_index = np.cumsum(k) - 1
        counts = np.diff(self.pair_start)[k]
        return SphereSet(
            frame_names=self.frame_names,
            frame_kin_index=self.frame_kin_index,
            frame_of_sphere=self.frame_of_sphere,
            kin_frame=self.kin_frame,
            sphere_index=self.sphere_index,
            local_centers=self.local_centers,
            radii=self.radii,
            self_radii=self.self_radii,
            frame_pair_a=self.frame_pair_a[k],
            frame_pair_b=self.frame_pair_b[k],
            frame_pair_masked=self.frame_pair_masked[k],
            pair_i=self.pair_i[sel],
            pair_j=self.pair_j[sel],
            pair_frame_pair=new_index[self.pair_frame_pair[sel]],
            pair_start=np.concatenate([[0], np.cumsum(counts)]),
            n_placeholders=self.n_placeholders,
        )

    def frame_pair_names(self) -> Iterator[tuple[str, str]]:
        for a, b in zip(self.frame_pair_a.tolist(), self.frame_pair_b.tolist(), strict=True):
            yield self.frame_names[a], self.frame_names[b]


#: cuRobo clamps a buffered radius in (−1, 0] to this (1 mm): the sphere stays a real one.
MIN_BUFFERED_RADIUS = 0.001


def self_radius(radius: float, buffer: float) -> float | None:
    """The self-collision radius of a sphere with raw ``radius`` and its frame's ``buffer``,
    or None for an attached-object slot (raw radius ≤ −1, cuRobo's ``extra_collision_spheres``)
    or a sphere buffered out of existence (buffered radius ≤ −1)."""
    if radius <= -1.0:
        return None
    buffered = radius + buffer
    if buffered > 0.0:
        return buffered
    return MIN_BUFFERED_RADIUS if buffered > -1.0 else None


def build_sphere_set(
    kin: KinematicModel, xrdf: Xrdf, *, include_masked: bool = False
) -> tuple[SphereSet, list[Diagnostic]]:
    """Flatten the self-collision spheres of ``xrdf`` for ``kin``.

    Uses the clone-resolved ``self_collision.geometry`` group. Attached-object slots (raw radius
    ≤ −1) are dropped (counted in ``n_placeholders``); a small negative raw radius is a real
    sphere once buffered, as cuRobo builds it (:func:`self_radius`). Spheres on a frame that the
    kinematic model does not have are dropped with a ``sphere-frame-unknown`` warning located
    at the frame's key in the geometry group. Without a ``self_collision`` section the set is
    empty.
    """
    diags: list[Diagnostic] = []
    sc = xrdf.self_collision
    spheres = xrdf.self_collision_spheres()
    path = xrdf.source.path
    per_frame: dict[int, list[tuple[int, tuple[float, float, float], float, float]]] = {}
    n_placeholders = 0
    for frame, sph in spheres.items():
        if not kin.has_frame(frame):
            group = _group_holding(xrdf, frame)
            kp = f"geometry.{group}.spheres.{frame}"
            line, col = xrdf.source.position(kp + "#key")
            why = (
                f"was removed by set_base_frame '{kin.base_frame}'"
                if frame in kin.pruned_frames
                else "is not a frame of the robot" + did_you_mean(frame, kin.frame_names)
            )
            diags.append(
                Diagnostic(
                    path,
                    line,
                    col,
                    "sphere-frame-unknown",
                    Severity.WARNING,
                    f"spheres on frame '{frame}' are not checked: the frame {why}",
                    kp,
                )
            )
            continue
        k = kin.frame_index(frame)
        buf = float(sc.buffer_distance.get(frame, 0.0)) if sc is not None else 0.0
        for i, s in enumerate(sph):
            r_self = self_radius(s.radius, buf)
            if r_self is None:
                n_placeholders += 1
                continue
            per_frame.setdefault(k, []).append((i, s.center, s.radius, r_self))
    kin_frames = sorted(per_frame)
    names = tuple(kin.frame_names[k] for k in kin_frames)
    fos: list[int] = []
    kfs: list[int] = []
    idx: list[int] = []
    centers: list[tuple[float, float, float]] = []
    radii: list[float] = []
    self_radii: list[float] = []
    for f, k in enumerate(kin_frames):
        for i, c, r, sr in per_frame[k]:
            fos.append(f)
            kfs.append(k)
            idx.append(i)
            centers.append(c)
            radii.append(r)
            self_radii.append(sr)
    starts = np.searchsorted(np.array(fos, dtype=np.intp), np.arange(len(names) + 1))
    fa: list[int] = []
    fb: list[int] = []
    masked: list[bool] = []
    pi: list[npt.NDArray[np.intp]] = []
    pj: list[npt.NDArray[np.intp]] = []
    pstart = [0]
    for a in range(len(names)):
        for b in range(a + 1, len(names)):
            m = sc is not None and sc.is_ignored(names[a], names[b])
            if m and not include_masked:
                continue
            fa.append(a)
            fb.append(b)
            masked.append(m)
            ia = np.arange(starts[a], starts[a + 1], dtype=np.intp)
            ib = np.arange(starts[b], starts[b + 1], dtype=np.intp)
            gi, gj = np.meshgrid(ia, ib, indexing="ij")
            pi.append(gi.ravel())
            pj.append(gj.ravel())
            pstart.append(pstart[-1] + gi.size)
    pair_i = np.concatenate(pi) if pi else np.zeros(0, dtype=np.intp)
    pair_j = np.concatenate(pj) if pj else np.zeros(0, dtype=np.intp)
    pair_fp = np.repeat(np.arange(len(fa), dtype=np.intp), np.diff(np.array(pstart)))
    sset = SphereSet(
        frame_names=names,
        frame_kin_index=np.array(kin_frames, dtype=np.intp),
        frame_of_sphere=np.array(fos, dtype=np.intp),
        kin_frame=np.array(kfs, dtype=np.intp),
        sphere_index=np.array(idx, dtype=np.intp),
        local_centers=np.array(centers, dtype=np.float64).reshape(-1, 3),
        radii=np.array(radii, dtype=np.float64),
        self_radii=np.array(self_radii, dtype=np.float64),
        frame_pair_a=np.array(fa, dtype=np.intp),
        frame_pair_b=np.array(fb, dtype=np.intp),
        frame_pair_masked=np.array(masked, dtype=np.bool_),
        pair_i=pair_i,
        pair_j=pair_j,
        pair_frame_pair=pair_fp,
        pair_start=np.array(pstart, dtype=np.intp),
        n_placeholders=n_placeholders,
    )
    return sset, diags


def _group_holding(xrdf: Xrdf, frame: str) -> str:
    sc = xrdf.self_collision
    geometry = xrdf.geometry
    if sc is None or geometry is None:
        return ""
    for g in clone_order(geometry, sc.geometry):
        if frame in geometry[g].spheres:
            return g
    return sc.geometry


# ------------------------------------------------------------------------------------------
# Plain batched building blocks
# ------------------------------------------------------------------------------------------
def _centers_batch_last(
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
        # out[s, i, b] = sum_k pts[s, k] * R[kf, i, k, b] + t[kf, i, b], as one GEMM
        Rk = np.ascontiguousarray(R[kf].transpose(1, 0, 2)).reshape(3, 3 * B)
        dst = out[sl].reshape(sl.stop - sl.start, 3 * B)
        np.matmul(spheres.local_centers[sl], Rk, out=dst)
        out[sl] += t[kf]
        if extra is not None:
            row = out[S + f].reshape(1, 3 * B)
            np.matmul(extra[f : f + 1], Rk, out=row)
            out[S + f] += t[kf]
    return out


def _as_q2(kin: KinematicModel, q_full: npt.ArrayLike) -> tuple[FloatArray, bool]:
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
    ``kin.actuated_joints`` order (see :func:`~xrdf_tools.kinematics.full_configuration`).
    """
    q2, single = _as_q2(kin, q_full)
    c = _centers_batch_last(kin, spheres, q2).transpose(2, 0, 1)
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
    out: FloatArray = d - (spheres.self_radii[spheres.pair_i] + spheres.self_radii[spheres.pair_j])
    return out


def pair_hits(spheres: SphereSet, centers: npt.ArrayLike) -> BoolArray:
    """Collision flags [B, P] (or [P]) with the counting comparison ``d² < (sr_i + sr_j)²``."""
    c = np.asarray(centers, dtype=np.float64)
    diff = c[..., spheres.pair_i, :] - c[..., spheres.pair_j, :]
    d2 = np.einsum("...k,...k->...", diff, diff)
    rs = spheres.self_radii[spheres.pair_i] + spheres.self_radii[spheres.pair_j]
    out: BoolArray = d2 < rs * rs
    return out


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


def contacts(spheres: SphereSet, centers: npt.ArrayLike) -> list[Contact]:
    """Colliding frame pairs of ``spheres`` for one configuration's centres [S, 3].

    One :class:`Contact` per colliding frame pair of the set (masked pairs only if the set
    was built with ``include_masked=True``), worst (most negative clearance) first.
    """
    c = np.asarray(centers, dtype=np.float64)
    if c.shape != (spheres.n_spheres, 3):
        raise ValueError(f"centers must be [{spheres.n_spheres}, 3], got {list(c.shape)}")
    hit = pair_hits(spheres, c)
    clr = pair_clearance(spheres, c)
    out: list[Contact] = []
    for k in np.unique(spheres.pair_frame_pair[hit]).tolist():
        lo, hi = int(spheres.pair_start[k]), int(spheres.pair_start[k + 1])
        h = hit[lo:hi]
        cl = np.where(h, clr[lo:hi], np.inf)
        w = lo + int(np.argmin(cl))
        out.append(
            Contact(
                frame_a=spheres.frame_names[spheres.frame_pair_a[k]],
                frame_b=spheres.frame_names[spheres.frame_pair_b[k]],
                clearance=float(clr[w]),
                sphere_a=int(spheres.sphere_index[spheres.pair_i[w]]),
                sphere_b=int(spheres.sphere_index[spheres.pair_j[w]]),
                n_sphere_pairs=int(np.count_nonzero(h)),
                masked=bool(spheres.frame_pair_masked[k]),
            )
        )
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
    :func:`~xrdf_tools.kinematics.default_configuration`). Masked pairs are skipped unless
    ``include_masked``. For repeated queries build the :class:`SphereSet` once and use
    :func:`sphere_world_centers` + :func:`contacts`.
    """
    spheres, _ = build_sphere_set(kin, xrdf, include_masked=include_masked)
    q2, single = _as_q2(kin, q_full)
    if not single:
        raise ValueError("colliding_frame_pairs takes one configuration [n]")
    return contacts(spheres, sphere_world_centers(kin, spheres, q2[0]))


# ------------------------------------------------------------------------------------------
# Fast counting over a chunk of configurations
# ------------------------------------------------------------------------------------------
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
    q2, _ = _as_q2(kin, q_full)
    B = q2.shape[0]
    K = spheres.n_frame_pairs
    hits = np.zeros((K, B), dtype=np.bool_)
    min_clear = np.full(K, np.inf)
    bound = np.full(K, np.inf)
    if K == 0 or B == 0:
        return ChunkResult(hits, min_clear, bound)
    S = spheres.n_spheres
    C = _centers_batch_last(kin, spheres, q2, extra=spheres._bound_center)
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
        hit_rows = (d3 < rs3 * rs3).any(axis=0)
        hits[k, gcol[hit_rows]] = True
        np.sqrt(d3, out=d3)
        d3 -= rs3
        min_clear[k] = float(d3.min())
    return ChunkResult(hits, min_clear, bound)
