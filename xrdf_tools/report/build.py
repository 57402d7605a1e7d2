"""Building the self-collision report: count, classify, certify, recommend.

:func:`self_collision_report` samples configurations (or takes given ones, e.g. a recorded
trajectory), counts for every pair of frames with spheres how often it collides
(:class:`xrdf_tools.selfcollision.engine.CountEngine`, exact, chunked so memory stays bounded),
classifies each pair (:mod:`.verdicts`), optionally certifies the "never" pairs
(:mod:`xrdf_tools.selfcollision.certify`) and recommends the ``ignore`` mask (:mod:`.mask`). Masked
adjacent pairs are not sampled (their verdict does not depend on it).
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Literal

import numpy as np
import numpy.typing as npt

from ..diagnostics import Diagnostic, sort_key
from ..robot.binding import cspace_indices
from ..robot.kinematics import (
    KinematicModel,
    build_kinematic_model,
    default_configuration,
    moveit_default_configuration,
)
from ..selfcollision.collision import (
    Contact,
    SphereSet,
    build_sphere_set,
    contacts,
    frame_pair_clearances,
    sphere_world_centers,
)
from ..selfcollision.engine import CountEngine, EngineTotals, ProgressFn, count_sampled
from ..util.arrays import FloatArray
from ..util.errors import XrdfToolsError
from ..util.frozen import FrozenMap
from ..util.numbers import REPORT_SAMPLES
from ..xrdf.model import Xrdf
from .mask import recommend_ignore
from .results import (
    CertifyOptions,
    ConfigsError,
    PairStat,
    Report,
    Sampler,
    TrajectoryHit,
    finite_or_none,
)
from .verdicts import (
    adjacent_frame_pairs,
    certified_stat,
    classify_pair,
    never_upper_bound,
    pair_findings,
    unchecked_finding,
)

if TYPE_CHECKING:
    import yourdfpy

    from ..robot.core import Robot
    from ..spheres import CoverageSummary


__all__ = ["DEFAULT_CHUNK", "ProgressFn", "self_collision_report"]

#: Configurations per chunk: the engine's working set stays in a few MB.
DEFAULT_CHUNK = 65536
#: Smallest chunk a sample is cut into for progress (a chunk of a robot with few body pairs
#: reports no progress from within: such a sample is cut into at least ten chunks).
_MIN_CHUNK = 4096


def self_collision_report(
    urdf: Robot | yourdfpy.URDF,
    xrdf: Xrdf,
    *,
    samples: int = REPORT_SAMPLES,
    seed: int | None = 0,
    sampler: Sampler = "uniform",
    configs: npt.ArrayLike | None = None,
    chunk: int = DEFAULT_CHUNK,
    progress: ProgressFn | None = None,
    urdf_path: str | None = None,
    coverage: bool = False,
    clearance_margin: float = 0.01,
    jobs: int = 1,
    certify: CertifyOptions | None = None,
    moveit: bool = False,
    certify_progress: ProgressFn | None = None,
) -> Report:
    """Sample (or take) configurations and build the self-collision :class:`Report`.

    ``configs`` [N, n_c] (c-space order) replaces sampling: the report then also lists which
    configurations collide and by which pairs (unmasked pairs only). Otherwise ``samples``
    configurations are drawn from the c-space limits with ``sampler`` (``uniform``: independent
    samples, for which the "never" bound holds; ``halton``: scrambled low-discrepancy points,
    better coverage, the bound is indicative only). Joints outside the c-space stay at their
    defaults. ``progress(done, total)`` is called after each chunk. ``coverage`` asks
    :mod:`xrdf_tools.spheres` for coverage metrics when it provides them. Minimum clearances
    below ``clearance_margin`` metres are exact; larger ones are reported as lower bounds.
    ``moveit`` takes the default configuration as MoveIt's Setup Assistant does (each joint at 0
    when within its limits, else mid-range) instead of the XRDF's, to compare like with like.
    ``jobs`` worker processes share a large sample (same result for any ``jobs``; given
    ``configs`` are always checked in this process). ``certify`` decides the "never" pairs
    over their whole joint box: proven, or "sometimes" with a witness configuration;
    ``certify_progress(done, total)`` is called as each of those pairs is decided.
    """
    from ..robot.urdf_source import urdf_path as _urdf_path

    t0 = time.perf_counter()
    upath = urdf_path or _urdf_path(urdf)
    kin, kin_diags = build_kinematic_model(urdf, xrdf, path=upath)
    spheres_all, sdiags = build_sphere_set(kin, xrdf, include_masked=True)
    diags: list[Diagnostic] = [*kin_diags, *sdiags]
    cspace, idx = cspace_indices(kin, xrdf)
    q_default = _default_pose(kin, xrdf, moveit)
    pairs = _counted_pairs(kin, spheres_all)
    qc = _given_configurations(configs, cspace)
    # given configurations may leave the joint limits, over which the engine proves things
    engine = CountEngine(
        _covering(kin, idx, qc), pairs.work, idx, q_default, margin=clearance_margin
    )
    if qc is not None:
        counted = _count_configs(engine, qc, chunk, progress)
    else:
        sampling = _Sampling(samples, sampler, seed, chunk, jobs)
        counted = _count_samples(engine, kin.lower[idx], kin.upper[idx], sampling, progress)
    def_clear, def_contacts = _default_clearances(kin, spheres_all, q_default)
    stats = _pair_stats(
        kin,
        pairs,
        (counted.totals.hits, *engine.reported_clearance(counted.totals)),
        def_clear,
        counted.n_total,
        counted.source,
        frozenset(cspace),
        clearance_margin,
    )
    if certify is not None:
        if engine.kin is not kin:  # over the joint limits, not the configurations' range
            engine = CountEngine(kin, pairs.work, idx, q_default, margin=clearance_margin)
        stats = _certify(engine, stats, pairs.work_index, cspace, certify, certify_progress)
    diags.extend(_pair_diagnostics(xrdf, kin, spheres_all, stats, def_contacts, counted))
    rec_ignore, change = recommend_ignore(xrdf, kin, spheres_all, stats)
    cov = _coverage(urdf, xrdf) if coverage else None
    if cov is not None:
        diags.extend(cov.diagnostics)  # meshes that could not be measured, and why
    return Report(
        xrdf_path=xrdf.source.path,
        urdf_path=upath,
        source=counted.source,
        samples=counted.n_total,
        sampler=sampler if counted.source == "sampled" else None,
        seed=seed if counted.source == "sampled" else None,
        cspace_joints=tuple(cspace),
        frames=spheres_all.frame_names,
        sphere_counts=FrozenMap(spheres_all.sphere_counts()),
        placeholders=spheres_all.n_placeholders,
        pairs=tuple(stats),
        default_configuration=FrozenMap(
            (j, float(v)) for j, v in zip(kin.actuated_joints, q_default, strict=True)
        ),
        default_contacts=tuple(def_contacts),
        trajectory=tuple(counted.trajectory) if counted.trajectory is not None else None,
        recommended_ignore=rec_ignore,
        mask_change=change,
        diagnostics=tuple(sorted(diags, key=sort_key)),
        elapsed_s=time.perf_counter() - t0,
        coverage=cov,
    )


def _default_pose(kin: KinematicModel, xrdf: Xrdf, moveit: bool) -> FloatArray:
    """The default configuration: the XRDF's, or with ``moveit`` the one MoveIt's Setup
    Assistant takes (0 when within the limits, else mid-range)."""
    if moveit:
        return moveit_default_configuration(kin)
    return default_configuration(kin, xrdf.default_joint_positions)


@dataclass(frozen=True)
class _Pairs:
    """The frame pairs of the report: ``every`` one (masked ones too), whether a joint joins
    each (``adjacent`` [K]), and those the engine counts (``work``, their indices
    ``work_index`` [W] in ``every``): all but the masked adjacent ones, which need no
    samples."""

    every: SphereSet
    adjacent: npt.NDArray[np.bool_]
    work: SphereSet
    work_index: npt.NDArray[np.intp]


def _counted_pairs(kin: KinematicModel, every: SphereSet) -> _Pairs:
    """The frame pairs of ``every`` and those of them the engine counts."""
    joined = adjacent_frame_pairs(kin, every.frame_names)
    adj = np.array([frozenset(p) in joined for p in every.frame_pair_names()], dtype=np.bool_)
    sampled = ~(every.frame_pair_masked & adj)  # masked adjacent pairs need no samples
    return _Pairs(every, adj, every.select_frame_pairs(sampled), np.flatnonzero(sampled))


@dataclass(frozen=True)
class _Sampling:
    """How the configurations are sampled: how many, how, from which seed (None: a fresh
    one), in chunks of at most ``chunk``, over ``jobs`` processes."""

    samples: int
    sampler: Sampler
    seed: int | None
    chunk: int
    jobs: int


@dataclass(frozen=True)
class _Counts:
    """What counting gave: the engine's totals, the configurations counted and where they
    came from; for given configurations, those where an unmasked pair collides."""

    totals: EngineTotals
    n_total: int
    source: Literal["sampled", "configs"]
    trajectory: list[TrajectoryHit] | None = None


def _count_samples(
    engine: CountEngine,
    lower: FloatArray,
    upper: FloatArray,
    sampling: _Sampling,
    progress: ProgressFn | None,
) -> _Counts:
    """Count ``sampling.samples`` configurations drawn within [``lower``, ``upper``]."""
    from ..selfcollision.sampling import fresh_seed

    samples = sampling.samples
    if samples < 1:
        raise XrdfToolsError(f"--samples must be at least 1, got {samples}")
    chunk = min(sampling.chunk, engine.chunk_limit())  # bounded memory
    if engine.steps_per_chunk < 10:  # progress per 10 %: from at least ten chunks
        chunk = min(chunk, max(_MIN_CHUNK, -(-samples // 10)))
    totals = count_sampled(
        engine,
        lower,
        upper,
        samples,
        method=sampling.sampler,
        seed=fresh_seed() if sampling.seed is None else sampling.seed,
        chunk=chunk,
        jobs=sampling.jobs,
        progress=progress,
    )
    return _Counts(totals, samples, "sampled")


def _pair_diagnostics(
    xrdf: Xrdf,
    kin: KinematicModel,
    spheres: SphereSet,
    stats: Sequence[PairStat],
    def_contacts: Sequence[Contact],
    counted: _Counts,
) -> list[Diagnostic]:
    """The findings on the pairs, then the one on a model with nothing to check."""
    found = pair_findings(xrdf, kin, stats, def_contacts, counted.trajectory, counted.n_total)
    if (unchecked := unchecked_finding(xrdf, spheres.n_spheres, len(stats))) is not None:
        found.append(unchecked)
    return found


def _coverage(urdf: Robot | yourdfpy.URDF, xrdf: Xrdf) -> CoverageSummary:
    """The sphere coverage metrics of ``xrdf`` on the loaded robot (no second parse)."""
    from ..robot.core import as_robot
    from ..spheres import coverage_for_xrdf

    return coverage_for_xrdf(as_robot(urdf), xrdf)


def _given_configurations(
    configs: npt.ArrayLike | None, cspace: Sequence[str]
) -> FloatArray | None:
    """The given configurations as a float array [N, n_c] (None when sampling). Raises
    :class:`ConfigsError` when they do not fit the c-space or are not finite."""
    if configs is None:
        return None
    qc = np.asarray(configs, dtype=np.float64)
    if qc.ndim != 2 or qc.shape[1] != len(cspace):
        raise ConfigsError(
            f"configurations must be [N, {len(cspace)}] in c-space order "
            f"({', '.join(cspace)}), got {list(qc.shape)}"
        )
    if not np.isfinite(qc).all():
        row, col = (int(v) for v in np.argwhere(~np.isfinite(qc))[0])
        raise ConfigsError(
            f"configuration {row}: {cspace[col]} is {qc[row, col]}; values must be finite"
        )
    return qc


def _covering(kin: KinematicModel, idx: npt.ArrayLike, qc: FloatArray | None) -> KinematicModel:
    """``kin`` with the c-space limits widened to hold the given configurations ``qc``.

    The engine decides at build time, over the joint limits, which sphere pairs can never
    come near (a prismatic joint's travel), its float32 error bounds and its cell grids; a
    recorded trajectory can leave those limits, and its configurations must still be counted
    exactly."""
    if qc is None or not len(qc):
        return kin
    cols = np.asarray(idx, dtype=np.intp)
    lower, upper = kin.lower.copy(), kin.upper.copy()
    lower[cols] = np.minimum(lower[cols], qc.min(axis=0))
    upper[cols] = np.maximum(upper[cols], qc.max(axis=0))
    if np.array_equal(lower, kin.lower) and np.array_equal(upper, kin.upper):
        return kin
    return dataclasses.replace(kin, lower=lower, upper=upper)


def _default_clearances(
    kin: KinematicModel, spheres: SphereSet, q_default: FloatArray
) -> tuple[FloatArray, list[Contact]]:
    """At the default configuration: the clearance [K] of every frame pair (masked ones too)
    and the colliding unmasked pairs, worst first."""
    c_def = sphere_world_centers(kin, spheres, q_default)
    def_clear = frame_pair_clearances(spheres, c_def)
    return def_clear, [c for c in contacts(spheres, c_def) if not c.masked]


def _pair_stats(
    kin: KinematicModel,
    pairs: _Pairs,
    counted: tuple[npt.NDArray[np.int64], FloatArray, npt.NDArray[np.bool_]],
    def_clear: FloatArray,
    n_total: int,
    source: str,
    cspace: frozenset[str],
    margin: float,
) -> list[PairStat]:
    """One :class:`PairStat` per frame pair of ``pairs``; the counted ones' collision
    counts, minimum clearances and whether each is only a bound are ``counted`` ([W]
    each). ``joints_on_path`` counts the c-space joints between the two frames: 0 means the
    pair's relative pose is constant in this report (decided once, at the default
    configuration). A pair that never collided but came within ``margin`` stays checked,
    unless no c-space joint moves its frames against each other: then it is as far apart in
    every configuration as at the default one (:func:`~.verdicts.classify_pair`)."""
    hits, min_clear, is_bound_w = counted
    spheres, adj = pairs.every, pairs.adjacent
    masked = spheres.frame_pair_masked
    counts = spheres.sphere_counts()
    ub = never_upper_bound(n_total)
    stats: list[PairStat] = []
    w_of = _work_positions(pairs.work_index)
    on_path = _cspace_joints_on_paths(kin, spheres, cspace)
    for k, (a, b) in enumerate(spheres.frame_pair_names()):
        w = w_of.get(k)
        h = int(hits[w]) if w is not None else None
        rate = (h / n_total if n_total else 0.0) if h is not None else None
        mc: float | None = None
        is_bound = False
        if w is not None:
            mc = float(min_clear[w])
            is_bound = bool(is_bound_w[w])
        near = (mc, margin) if mc is not None and not is_bound and 0.0 <= mc < margin else None
        cls, rec, note = classify_pair(
            bool(adj[k]),
            float(def_clear[k]),
            h,
            rate,
            n_total,
            ub,
            bool(masked[k]),
            source,
            near,
            fixed=on_path[k] == 0,
        )
        stats.append(
            PairStat(
                frame_a=a,
                frame_b=b,
                spheres_a=counts[a],
                spheres_b=counts[b],
                masked=bool(masked[k]),
                adjacent=bool(adj[k]),
                sampled=w is not None,
                hits=h,
                rate=rate,
                rate_upper_95=ub if h == 0 else None,
                min_clearance=finite_or_none(mc),
                min_clearance_is_bound=is_bound,
                default_clearance=float(def_clear[k]),
                classification=cls,
                recommendation=rec,
                note=note,
                joints_on_path=on_path[k],
            )
        )
    return stats


def _work_positions(work_index: npt.NDArray[np.intp]) -> dict[int, int]:
    """Frame pair index → its position among the engine's (sampled) pairs."""
    return {int(k): i for i, k in enumerate(work_index)}


def _cspace_joints_on_paths(
    kin: KinematicModel, spheres: SphereSet, cspace: frozenset[str]
) -> list[int]:
    """Per frame pair of ``spheres``: how many joints of ``cspace`` lie between its frames."""
    mask = sum(1 << i for i, name in enumerate(kin.actuated_joints) if name in cspace)
    kf = spheres.frame_kin_index
    bits = kin.joint_paths.between(kf[spheres.frame_pair_a], kf[spheres.frame_pair_b])
    return [(b & mask).bit_count() for b in bits]


def _count_configs(
    engine: CountEngine, qc: FloatArray, chunk: int, progress: ProgressFn | None
) -> _Counts:
    """Count given c-space configurations and list those where an unmasked pair collides."""
    chunk = min(chunk, engine.chunk_limit(flags=True))
    work = engine.spheres
    unmasked = ~work.frame_pair_masked
    checked = work.select_frame_pairs(unmasked)
    totals = EngineTotals.empty(engine.K)
    trajectory: list[TrajectoryHit] = []
    n_total = qc.shape[0]
    for start in range(0, n_total, chunk):
        q_c = qc[start : start + chunk]
        hits = engine.count(q_c, totals)
        bad = np.flatnonzero(hits[unmasked].any(axis=0))
        if len(bad):
            q = np.repeat(engine.q_base[None, :], len(bad), axis=0)
            q[:, engine.cspace] = q_c[bad]
            centers = sphere_world_centers(engine.kin, checked, q)
            for b, c in zip(bad.tolist(), centers, strict=True):
                trajectory.append(TrajectoryHit(start + b, tuple(contacts(checked, c))))
        if progress is not None:
            progress(min(start + chunk, n_total), n_total)
    return _Counts(totals, n_total, "configs", trajectory)


def _certify(
    engine: CountEngine,
    stats: list[PairStat],
    work_index: npt.NDArray[np.intp],
    cspace: Sequence[str],
    opts: CertifyOptions,
    progress: ProgressFn | None = None,
) -> list[PairStat]:
    """Certify the "never" pairs, sharing the box budget (and the optional wall-clock limit)
    evenly among those still to do; ``progress(done, total)`` after each pair. The engine
    counts the pairs of ``work_index`` [W] (indices into ``stats``), in that order."""
    from ..selfcollision.certify import certify_pair  # only with --certify

    w_of = _work_positions(work_index)
    # a pair no c-space joint moves is proven in one box (its pose is constant)
    todo = [i for i, p in enumerate(stats) if p.classification == "never" and i in w_of]
    start = time.perf_counter()
    boxes_left = opts.boxes
    out = list(stats)
    for n_left, i in zip(range(len(todo), 0, -1), todo, strict=True):
        deadline = None
        if opts.budget_s is not None:
            deadline = max(0.0, opts.budget_s - (time.perf_counter() - start)) / n_left
        cert = certify_pair(engine, w_of[i], boxes_left // n_left, deadline)
        boxes_left -= cert.boxes
        out[i] = certified_stat(stats[i], cert, cspace, opts)
        if progress is not None:
            progress(len(todo) - n_left + 1, len(todo))
    return out
