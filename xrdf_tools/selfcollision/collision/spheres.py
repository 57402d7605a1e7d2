"""Sphere sets: the self-collision spheres of a robot as flat arrays, and how they are built.

:func:`build_sphere_set` turns an :class:`~xrdf_tools.xrdf.model.Xrdf` plus a
:class:`~xrdf_tools.robot.kinematics.KinematicModel` into a :class:`SphereSet`: spheres grouped by
frame, the frame pairs that are checked (masked ones on request) and every sphere pair of
them as index arrays. Buffered radii follow cuRobo (:func:`self_radius`). Every consumer
(lint, viz, the report's :mod:`xrdf_tools.selfcollision.engine`, the reference counter
:func:`tests.collision_reference.count_chunk`, ``--certify``) starts from this one set, so they
agree on which sphere pairs exist and on their radii.

:func:`bounding_sphere` is the one enclosing-sphere construction used for culling, both per
frame here and per moving body in the engine.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import numpy.typing as npt

from ...diagnostics import Diagnostic, Severity
from ...robot.kinematics import KinematicModel
from ...util.arrays import BoolArray, FloatArray, IntArray
from ...util.errors import XrdfToolsError, did_you_mean
from ...xrdf.model import Xrdf, clone_order

__all__ = [
    "CULL_SLACK",
    "MAX_SPHERES",
    "MAX_SPHERE_FRAMES",
    "MIN_BUFFERED_RADIUS",
    "SphereLimitError",
    "SphereSet",
    "bounding_sphere",
    "build_sphere_set",
    "is_slot",
    "self_radius",
]

#: Ceilings of a sphere set (docs/security.md): memory and time stay bounded below them.
MAX_SPHERES = 50_000
MAX_SPHERE_FRAMES = 500

#: Slack (metres) added to every bounding radius so that culling stays conservative under
#: float rounding (used by the reference counter and by the engine alike).
CULL_SLACK = 1e-6


def bounding_sphere(centers: FloatArray, radii: FloatArray) -> tuple[FloatArray, float]:
    """A sphere (centre [3], radius) enclosing the spheres ``centers`` [m, 3] / ``radii`` [m].

    The centre is the middle of the spheres' axis-aligned bounding box; the radius reaches the
    farthest sphere surface from it. Not the smallest enclosing sphere, but cheap and tight
    enough for culling. Negative radii count as 0 for the box.
    """
    r = np.maximum(radii, 0.0)
    c: FloatArray = ((centers - r[:, None]).min(axis=0) + (centers + r[:, None]).max(axis=0)) / 2
    return c, float(np.max(np.linalg.norm(centers - c, axis=1) + radii))


def _ro(a: npt.ArrayLike, dtype: Any) -> Any:
    arr = np.array(a, dtype=dtype, copy=True)
    arr.flags.writeable = False
    return arr


@dataclass(frozen=True, eq=False)
class SphereSet:
    """The self-collision spheres of a robot as flat arrays.

    Frames (``Fs = len(frame_names)``): frames that carry at least one active sphere, in
    kinematic (topological) order; ``frame_kin_index`` [Fs] is each one's index in the
    :class:`~xrdf_tools.robot.kinematics.KinematicModel`.

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

    Sphere pairs (``P``): every sphere of frame ``a`` with every sphere of frame ``b`` of each
    frame pair. They are implicit (memory stays linear in the spheres): the library works per
    frame pair on :meth:`spheres_of` slices, in bounded blocks. ``pair_start`` [K + 1] gives
    each frame pair's range in the flat order (frame pair by frame pair, row-major);
    :meth:`frame_pair_sphere_pairs` materialises one frame pair, and ``pair_i``, ``pair_j``,
    ``pair_frame_pair``, ``pair_radius_sum`` [P] all of them (for small sets and tests).
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
    n_placeholders: int = 0
    _frame_start: IntArray = field(init=False, repr=False)
    _bound_center: FloatArray = field(init=False, repr=False)
    _bound_radius: FloatArray = field(init=False, repr=False)
    #: [K + 1] each frame pair's range in the flat (implicit) sphere-pair order.
    pair_start: IntArray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        ints = (
            "frame_kin_index",
            "frame_of_sphere",
            "kin_frame",
            "sphere_index",
            "frame_pair_a",
            "frame_pair_b",
        )
        for name in ints:
            object.__setattr__(self, name, _ro(getattr(self, name), np.intp))
        for name in ("local_centers", "radii", "self_radii"):
            object.__setattr__(self, name, _ro(getattr(self, name), np.float64))
        object.__setattr__(self, "frame_pair_masked", _ro(self.frame_pair_masked, np.bool_))
        S, Fs, K = len(self.frame_of_sphere), len(self.frame_names), len(self.frame_pair_a)
        if self.local_centers.shape != (S, 3) or self.radii.shape != (S,):
            raise ValueError("SphereSet: local_centers must be [S, 3] and radii [S]")
        if self.frame_pair_b.shape != (K,) or self.frame_kin_index.shape != (Fs,):
            raise ValueError("SphereSet: frame_pair_b must be [K], frame_kin_index [Fs]")
        starts = np.searchsorted(self.frame_of_sphere, np.arange(Fs + 1))
        object.__setattr__(self, "_frame_start", _ro(starts, np.intp))
        # Per-frame bounding sphere of the self-collision spheres (frame coordinates).
        bc = np.zeros((Fs, 3))
        br = np.zeros(Fs)
        for f in range(Fs):
            sl = slice(int(starts[f]), int(starts[f + 1]))
            bc[f], br[f] = bounding_sphere(self.local_centers[sl], self.self_radii[sl])
        object.__setattr__(self, "_bound_center", _ro(bc, np.float64))
        object.__setattr__(self, "_bound_radius", _ro(br + CULL_SLACK, np.float64))
        sizes = np.diff(starts)
        per_pair = sizes[self.frame_pair_a] * sizes[self.frame_pair_b]
        object.__setattr__(
            self, "pair_start", _ro(np.concatenate([[0], np.cumsum(per_pair)]), np.intp)
        )

    # --- sizes and names -------------------------------------------------------------------
    @property
    def n_spheres(self) -> int:
        return len(self.frame_of_sphere)

    @property
    def n_pairs(self) -> int:
        return int(self.pair_start[-1])

    def frame_pair_sphere_pairs(self, k: int) -> tuple[IntArray, IntArray, FloatArray]:
        """Sphere indices ``i`` [n], ``j`` [n] and radius sums [n] of every sphere pair of
        frame pair ``k`` (``n = |a| · |b|``, row-major: ``i`` varies slowest)."""
        sa = self.spheres_of(int(self.frame_pair_a[k]))
        sb = self.spheres_of(int(self.frame_pair_b[k]))
        gi, gj = np.meshgrid(
            np.arange(sa.start, sa.stop), np.arange(sb.start, sb.stop), indexing="ij"
        )
        i, j = gi.ravel().astype(np.intp), gj.ravel().astype(np.intp)
        return i, j, self.self_radii[i] + self.self_radii[j]

    def _all_pairs(self) -> tuple[IntArray, IntArray]:
        """Every sphere pair, materialised on first use and kept (O(P) memory)."""
        cached: tuple[IntArray, IntArray] | None = self.__dict__.get("_pairs_cache")
        if cached is not None:
            return cached
        parts = [self.frame_pair_sphere_pairs(k)[:2] for k in range(self.n_frame_pairs)]
        out = (
            (np.concatenate([p[0] for p in parts]), np.concatenate([p[1] for p in parts]))
            if parts
            else (np.zeros(0, dtype=np.intp), np.zeros(0, dtype=np.intp))
        )
        object.__setattr__(self, "_pairs_cache", out)
        return out

    @property
    def pair_i(self) -> IntArray:
        """[P] first sphere of every sphere pair (materialised: O(P) memory)."""
        return self._all_pairs()[0]

    @property
    def pair_j(self) -> IntArray:
        """[P] second sphere of every sphere pair (materialised: O(P) memory)."""
        return self._all_pairs()[1]

    @property
    def pair_frame_pair(self) -> IntArray:
        """[P] frame pair of every sphere pair (materialised: O(P) memory)."""
        return np.repeat(np.arange(self.n_frame_pairs, dtype=np.intp), np.diff(self.pair_start))

    @property
    def pair_radius_sum(self) -> FloatArray:
        """[P] the two buffered radii of every sphere pair added (materialised)."""
        i, j = self._all_pairs()
        out: FloatArray = self.self_radii[i] + self.self_radii[j]
        return out

    @property
    def n_frame_pairs(self) -> int:
        return len(self.frame_pair_a)

    @property
    def frame_start(self) -> IntArray:
        """[Fs + 1] the first sphere of each frame (and, last, the number of spheres)."""
        out: IntArray = self._frame_start
        return out

    @property
    def frame_sizes(self) -> IntArray:
        """[Fs] the number of spheres on each frame."""
        out: IntArray = np.diff(self._frame_start)
        return out

    def spheres_of(self, frame: int) -> slice:
        """Slice of sphere indices on frame ``frame`` (index into ``frame_names``)."""
        return slice(int(self._frame_start[frame]), int(self._frame_start[frame + 1]))

    def sphere_counts(self) -> dict[str, int]:
        """Active spheres per frame."""
        return {f: int(n) for f, n in zip(self.frame_names, self.frame_sizes, strict=True)}

    def sphere_label(self, s: int) -> str:
        """``frame[k]``: the sphere's frame and position in that frame's list."""
        return f"{self.frame_names[self.frame_of_sphere[s]]}[{self.sphere_index[s]}]"

    def select_frame_pairs(self, keep: npt.ArrayLike) -> SphereSet:
        """A copy that keeps only the frame pairs where ``keep`` [K] is True (same spheres)."""
        k = np.asarray(keep, dtype=np.bool_)
        if k.shape != (self.n_frame_pairs,):
            raise ValueError(f"keep must be [{self.n_frame_pairs}], got {list(k.shape)}")
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
            n_placeholders=self.n_placeholders,
        )

    def frame_pair_names(self) -> Iterator[tuple[str, str]]:
        for a, b in zip(self.frame_pair_a.tolist(), self.frame_pair_b.tolist(), strict=True):
            yield self.frame_names[a], self.frame_names[b]


#: cuRobo clamps a buffered radius in (−1, 0] to this (1 mm): the sphere stays a real one.
MIN_BUFFERED_RADIUS = 0.001


def is_slot(radius: float) -> bool:
    """Whether a raw sphere ``radius`` marks an attached-object slot (≤ −1: cuRobo's
    ``extra_collision_spheres``), which is no geometry until an object is attached."""
    return radius <= -1.0


def self_radius(radius: float, buffer: float) -> float | None:
    """The self-collision radius of a sphere with raw ``radius`` and its frame's ``buffer``,
    or None for an attached-object slot (:func:`is_slot`) or a sphere buffered out of
    existence (buffered radius ≤ −1)."""
    if is_slot(radius):
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
    per_frame, n_placeholders = _active_spheres(kin, xrdf, diags)
    _check_ceilings(xrdf, per_frame)
    kin_frames = sorted(per_frame)
    names = tuple(kin.frame_names[k] for k in kin_frames)
    rows = [(f, k, *entry) for f, k in enumerate(kin_frames) for entry in per_frame[k]]
    fa, fb, masked = _frame_pairs(xrdf, names, include_masked)
    sset = SphereSet(
        frame_names=names,
        frame_kin_index=np.array(kin_frames, dtype=np.intp),
        frame_of_sphere=np.array([row[0] for row in rows], dtype=np.intp),
        kin_frame=np.array([row[1] for row in rows], dtype=np.intp),
        sphere_index=np.array([row[2] for row in rows], dtype=np.intp),
        local_centers=np.array([row[3] for row in rows], dtype=np.float64).reshape(-1, 3),
        radii=np.array([row[4] for row in rows], dtype=np.float64),
        self_radii=np.array([row[5] for row in rows], dtype=np.float64),
        frame_pair_a=np.array(fa, dtype=np.intp),
        frame_pair_b=np.array(fb, dtype=np.intp),
        frame_pair_masked=np.array(masked, dtype=np.bool_),
        n_placeholders=n_placeholders,
    )
    return sset, diags


#: One active sphere: its index in its frame's list, centre, raw radius and self radius.
_Entry = tuple[int, tuple[float, float, float], float, float]


def _active_spheres(
    kin: KinematicModel, xrdf: Xrdf, diags: list[Diagnostic]
) -> tuple[dict[int, list[_Entry]], int]:
    """The self-collision group's spheres per kinematic frame index, and how many
    attached-object slots were dropped; a frame the model lacks is a warning in ``diags``."""
    sc = xrdf.self_collision
    per_frame: dict[int, list[_Entry]] = {}
    n_placeholders = 0
    for frame, sph in xrdf.self_collision_spheres().items():
        if not kin.has_frame(frame):
            diags.append(_unknown_frame(kin, xrdf, frame))
            continue
        k = kin.frame_index(frame)
        buf = float(sc.buffer_distance.get(frame, 0.0)) if sc is not None else 0.0
        for i, s in enumerate(sph):
            r_self = self_radius(s.radius, buf)
            if r_self is None:
                n_placeholders += 1
                continue
            per_frame.setdefault(k, []).append((i, s.center, s.radius, r_self))
    return per_frame, n_placeholders


def _unknown_frame(kin: KinematicModel, xrdf: Xrdf, frame: str) -> Diagnostic:
    """``sphere-frame-unknown``: the spheres on ``frame`` are not checked, because
    set_base_frame removed it or the robot has no such frame; at the frame's key."""
    kp = f"geometry.{_group_holding(xrdf, frame)}.spheres.{frame}"
    line, col = xrdf.source.position(kp + "#key")
    why = (
        f"was removed by set_base_frame '{kin.base_frame}'"
        if frame in kin.pruned_frames
        else "is not a frame of the robot" + did_you_mean(frame, kin.frame_names)
    )
    return Diagnostic(
        xrdf.source.path,
        line,
        col,
        "sphere-frame-unknown",
        Severity.WARNING,
        f"spheres on frame '{frame}' are not checked: the frame {why}",
        kp,
    )


def _frame_pairs(
    xrdf: Xrdf, names: Sequence[str], include_masked: bool
) -> tuple[list[int], list[int], list[bool]]:
    """Every pair ``a < b`` of the frames ``names`` in lexicographic order, the masked ones
    only with ``include_masked``: the two indices and whether the mask ignores it."""
    sc = xrdf.self_collision
    fa: list[int] = []
    fb: list[int] = []
    masked: list[bool] = []
    for a in range(len(names)):
        for b in range(a + 1, len(names)):
            m = sc is not None and sc.is_ignored(names[a], names[b])
            if m and not include_masked:
                continue
            fa.append(a)
            fb.append(b)
            masked.append(m)
    return fa, fb, masked


class SphereLimitError(XrdfToolsError):
    """The self-collision spheres exceed :data:`MAX_SPHERES` or :data:`MAX_SPHERE_FRAMES`."""


def _check_ceilings(xrdf: Xrdf, per_frame: dict[int, list[Any]]) -> None:
    """Refuse sets beyond the documented ceilings, located at the self-collision group."""
    n = sum(len(v) for v in per_frame.values())
    if n <= MAX_SPHERES and len(per_frame) <= MAX_SPHERE_FRAMES:
        return
    sc = xrdf.self_collision
    key = f"geometry.{sc.geometry}" if sc is not None else "geometry"
    line, col = xrdf.source.position(key + "#key")
    what = (
        f"{n:,} self-collision spheres (at most {MAX_SPHERES:,})"
        if n > MAX_SPHERES
        else f"self-collision spheres on {len(per_frame):,} frames (at most {MAX_SPHERE_FRAMES:,})"
    )
    raise SphereLimitError(
        f"{what}: too many to check; merge spheres (xrdf spheres) or links",
        path=xrdf.source.path,
        line=line,
        col=col,
    )


def _group_holding(xrdf: Xrdf, frame: str) -> str:
    sc = xrdf.self_collision
    geometry = xrdf.geometry
    if sc is None or geometry is None:
        return ""
    for g in clone_order(geometry, sc.geometry):
        if frame in geometry[g].spheres:
            return g
    return sc.geometry
