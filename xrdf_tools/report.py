"""Self-collision report: sample the c-space, count collisions per frame pair, judge the mask.

:func:`self_collision_report` answers "is my sphere model and mask right?" pair by pair. It
samples configurations (or takes given ones, e.g. a recorded trajectory), counts for every
pair of frames with spheres how often it collides (:class:`xrdf_tools.engine.CountEngine`,
exact, chunked so memory stays bounded), classifies each pair the way the MoveIt Setup
Assistant does and recommends what the ``ignore`` mask should say. Findings come back as
:class:`~xrdf_tools.diagnostics.Diagnostic` objects; rendering lives in
:mod:`xrdf_tools.report_render`.

Classification, first match wins (MoveIt Setup Assistant order):

``adjacent``  the frames are joined by a joint once frames without spheres are collapsed;
``default``   the pair collides at the default configuration;
``always``    it collides in more than 95 % of the configurations;
``never``     it never collides in the ``N`` configurations: with independent uniform samples
              the collision rate is below ``1 − 0.05^(1/N)`` (≈ 3/N) with 95 % confidence;
``sometimes`` anything else.

Masked adjacent pairs are not sampled (their verdict does not depend on it).
"""

from __future__ import annotations

import importlib
import math
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
import numpy.typing as npt

from .certify import Verdict, certify_pair
from .collision import (
    Contact,
    SphereSet,
    build_sphere_set,
    contacts,
    pair_clearance,
    sphere_world_centers,
)
from .diagnostics import Diagnostic, Severity, sort_key
from .engine import CountEngine, EngineTotals, count_sampled
from .errors import XrdfToolsError, did_you_mean
from .frozen import FrozenMap
from .kinematics import (
    KinematicModel,
    build_kinematic_model,
    default_configuration,
    moveit_default_configuration,
)
from .model import SelfCollisionSection, Xrdf

if TYPE_CHECKING:
    import yourdfpy

FloatArray = npt.NDArray[np.float64]
Sampler = Literal["uniform", "halton"]
Classification = Literal["adjacent", "default", "always", "never", "sometimes"]
Recommendation = Literal["ignore", "may-ignore", "check"]

__all__ = [
    "ALWAYS_RATE",
    "RULES",
    "CertifyOptions",
    "ConfigsError",
    "CoverageSummary",
    "MaskChange",
    "PairStat",
    "Report",
    "TrajectoryHit",
    "adjacent_frame_pairs",
    "never_upper_bound",
    "recommended_xrdf",
    "self_collision_report",
]

#: A pair colliding in more than this fraction of configurations is "always" colliding.
ALWAYS_RATE = 0.95
DEFAULT_CHUNK = 65536

#: Report rule ids: (id, short description, severity).
RULES: tuple[tuple[str, str, Severity], ...] = (
    (
        "report-always-colliding",
        "an unmasked frame pair collides in more than 95 % of configurations",
        Severity.ERROR,
    ),
    (
        "report-default-colliding",
        "an unmasked frame pair collides at the default configuration",
        Severity.ERROR,
    ),
    (
        "report-mask-hides-collision",
        "a masked frame pair that is not adjacent collides sometimes",
        Severity.WARNING,
    ),
    (
        "report-unknown-mask-frame",
        "self_collision.ignore names a frame the robot does not have",
        Severity.WARNING,
    ),
    (
        "report-trajectory-collision",
        "a given configuration (--configs) is in self-collision",
        Severity.ERROR,
    ),
)
_SEVERITY = {r[0]: r[2] for r in RULES}


@dataclass(frozen=True)
class CertifyOptions:
    """``--certify``: decide every "never" pair over its whole joint box (see
    :mod:`xrdf_tools.certify`) within ``budget_s`` seconds in all. ``mask_policy``
    ``"proven"`` recommends ignoring a never-colliding pair only when it is proven;
    ``"sampled"`` keeps the sampled recommendation."""

    budget_s: float = 60.0
    mask_policy: Literal["proven", "sampled"] = "sampled"


class ConfigsError(XrdfToolsError):
    """A ``--configs`` file cannot be read or does not fit the c-space."""


def never_upper_bound(n: int, confidence: float = 0.95) -> float:
    """Upper bound of the collision rate after ``n`` samples without a hit (exact binomial).

    ``1 − (1 − confidence)^(1/n)``; about ``3/n`` for 95 %. ``1.0`` for ``n == 0``.
    """
    if n <= 0:
        return 1.0
    return -math.expm1(math.log(1.0 - confidence) / n)


# ------------------------------------------------------------------------------------------
# Result types
# ------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class PairStat:
    """Statistics and verdict for one pair of frames that carry spheres.

    ``hits``/``rate`` are None when the pair was not sampled (masked and adjacent).
    ``min_clearance`` is the smallest clearance seen (negative: deepest penetration); when
    ``min_clearance_is_bound`` it is only a lower bound (culling skipped the closest
    configurations, all of them farther apart than this). ``rate_upper_95`` is the 95 %
    upper bound of the collision rate when ``hits == 0``.
    """

    frame_a: str
    frame_b: str
    spheres_a: int
    spheres_b: int
    masked: bool
    adjacent: bool
    sampled: bool
    hits: int | None
    rate: float | None
    rate_upper_95: float | None
    min_clearance: float | None
    min_clearance_is_bound: bool
    default_clearance: float
    classification: Classification
    recommendation: Recommendation
    note: str
    certificate: Verdict | None = None
    witness: Mapping[str, float] | None = None
    certify_s: float | None = None
    #: Actuated joints whose values move the two frames relative to each other: 0 means the
    #: pair's verdict holds for every configuration, 1-2 are decided on a grid.
    joints_on_path: int = 0

    @property
    def colliding_at_default(self) -> bool:
        return self.default_clearance < 0

    def to_dict(self) -> dict[str, Any]:
        return {
            "frame_a": self.frame_a,
            "frame_b": self.frame_b,
            "spheres_a": self.spheres_a,
            "spheres_b": self.spheres_b,
            "masked": self.masked,
            "adjacent": self.adjacent,
            "sampled": self.sampled,
            "hits": self.hits,
            "rate": self.rate,
            "rate_upper_95": self.rate_upper_95,
            "min_clearance": _finite(self.min_clearance),
            "min_clearance_is_bound": self.min_clearance_is_bound,
            "default_clearance": self.default_clearance,
            "classification": self.classification,
            "recommendation": self.recommendation,
            "note": self.note,
            "certified": None if self.certificate is None else self.certificate == "proven",
            "certificate": self.certificate,
            "witness": dict(self.witness) if self.witness is not None else None,
            "certify_s": self.certify_s,
            "joints_on_path": self.joints_on_path,
        }


@dataclass(frozen=True)
class TrajectoryHit:
    """A given configuration (row ``index`` of ``--configs``) in self-collision."""

    index: int
    contacts: tuple[Contact, ...]


@dataclass(frozen=True)
class MaskChange:
    """How the recommended ``ignore`` differs from the current one (pairs as (a, b))."""

    added: tuple[tuple[str, str], ...] = ()
    removed: tuple[tuple[str, str], ...] = ()
    dropped_unknown: tuple[str, ...] = ()

    @property
    def empty(self) -> bool:
        return not (self.added or self.removed or self.dropped_unknown)


@dataclass(frozen=True)
class CoverageSummary:
    """Optional sphere-coverage metrics (from ``xrdf_tools.spheres``): per frame and overall,
    each ``{metric: value}`` (e.g. ``coverage``, ``surface_coverage``, ``protrusion_max``)."""

    per_frame: Mapping[str, Mapping[str, float]]
    overall: Mapping[str, float] = field(default_factory=dict)
    note: str = ""


@dataclass(frozen=True)
class Report:
    """Everything ``xrdf report`` shows. See :func:`self_collision_report`."""

    xrdf_path: str
    urdf_path: str
    source: Literal["sampled", "configs"]
    samples: int
    sampler: Sampler | None
    seed: int | None
    cspace_joints: tuple[str, ...]
    frames: tuple[str, ...]
    sphere_counts: Mapping[str, int]
    placeholders: int
    pairs: tuple[PairStat, ...]
    default_configuration: Mapping[str, float]
    default_contacts: tuple[Contact, ...]
    trajectory: tuple[TrajectoryHit, ...] | None
    recommended_ignore: Mapping[str, tuple[str, ...]]
    mask_change: MaskChange
    diagnostics: tuple[Diagnostic, ...]
    elapsed_s: float
    coverage: CoverageSummary | None = None
    _pair_index: dict[tuple[str, str], int] = field(default_factory=dict, compare=False, repr=False)

    @property
    def default_ok(self) -> bool:
        """No unmasked pair collides at the default configuration."""
        return not self.default_contacts

    @property
    def configs_per_s(self) -> float:
        return self.samples / self.elapsed_s if self.elapsed_s > 0 else float("inf")

    def pair(self, a: str, b: str) -> PairStat:
        """The statistics of frame pair ``a``/``b`` (either order); KeyError if absent."""
        if not self._pair_index:
            for i, p in enumerate(self.pairs):
                self._pair_index[(p.frame_a, p.frame_b)] = i
                self._pair_index[(p.frame_b, p.frame_a)] = i
        return self.pairs[self._pair_index[(a, b)]]


def _finite(x: float | None) -> float | None:
    return None if x is None or not math.isfinite(x) else x


# ------------------------------------------------------------------------------------------
# Adjacency (MoveIt Setup Assistant)
# ------------------------------------------------------------------------------------------
def adjacent_frame_pairs(
    kin: KinematicModel, geometry_frames: Sequence[str]
) -> frozenset[frozenset[str]]:
    """Pairs of ``geometry_frames`` joined by a joint once frames without geometry collapse.

    Two geometry frames are adjacent when the kinematic tree path between them passes only
    through frames without geometry (none at all: parent and child), the rule of the MoveIt
    Setup Assistant (siblings under a geometry-less frame are adjacent too).
    """
    geo = {kin.frame_index(f) for f in geometry_frames}
    nbrs: dict[int, list[int]] = {i: [] for i in range(kin.n_frames)}
    for i in range(1, kin.n_frames):
        p = int(kin.parent[i])
        nbrs[i].append(p)
        nbrs[p].append(i)
    out: set[frozenset[str]] = set()
    for g in geo:
        seen = {g}
        stack = list(nbrs[g])
        while stack:
            v = stack.pop()
            if v in seen:
                continue
            seen.add(v)
            if v in geo:
                out.add(frozenset((kin.frame_names[g], kin.frame_names[v])))
            else:
                stack.extend(nbrs[v])
    return frozenset(out)


# ------------------------------------------------------------------------------------------
# The report
# ------------------------------------------------------------------------------------------
ProgressFn = Callable[[int, int], None]


def self_collision_report(
    urdf: yourdfpy.URDF,
    xrdf: Xrdf,
    *,
    samples: int = 100_000,
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
    over their whole joint box: proven, or "sometimes" with a witness configuration.
    """
    from .sampling import fresh_seed
    from .urdf_source import urdf_path as _urdf_path

    t0 = time.perf_counter()
    upath = urdf_path or _urdf_path(urdf)
    kin, kin_diags = build_kinematic_model(urdf, xrdf, path=upath)
    spheres_all, sdiags = build_sphere_set(kin, xrdf, include_masked=True)
    diags: list[Diagnostic] = [*kin_diags, *sdiags]
    cspace = _cspace_joints(kin, xrdf)
    defaults = xrdf.default_joint_positions
    if moveit:  # like MoveIt's Setup Assistant: 0 when within the limits, else mid-range
        q_default = moveit_default_configuration(kin)
        defaults = FrozenMap(zip(kin.actuated_joints, map(float, q_default), strict=True))
    else:
        q_default = default_configuration(kin, defaults)

    adjacent = adjacent_frame_pairs(kin, spheres_all.frame_names)
    pair_names = list(spheres_all.frame_pair_names())
    adj = np.array([frozenset(p) in adjacent for p in pair_names], dtype=np.bool_)
    masked = spheres_all.frame_pair_masked
    sampled = ~(masked & adj)
    work = spheres_all.select_frame_pairs(sampled)
    K = spheres_all.n_frame_pairs
    work_index = np.flatnonzero(sampled)

    idx = np.array([kin.actuated_index(n) for n in cspace], dtype=np.intp)
    engine = CountEngine(kin, work, idx, q_default, margin=clearance_margin)
    trajectory: list[TrajectoryHit] | None = None
    if configs is not None:
        qc = np.asarray(configs, dtype=np.float64)
        if qc.ndim != 2 or qc.shape[1] != len(cspace):
            raise ConfigsError(
                f"configurations must be [N, {len(cspace)}] in c-space order "
                f"({', '.join(cspace)}), got {list(qc.shape)}"
            )
        n_total = qc.shape[0]
        totals, trajectory = _count_configs(engine, qc, chunk, progress)
        source: Literal["sampled", "configs"] = "configs"
    else:
        if samples < 1:
            raise XrdfToolsError(f"--samples must be at least 1, got {samples}")
        n_total = samples
        totals = count_sampled(
            engine,
            kin.lower[idx],
            kin.upper[idx],
            samples,
            method=sampler,
            seed=fresh_seed() if seed is None else seed,
            chunk=chunk,
            jobs=jobs,
            progress=progress,
        )
        source = "sampled"
    hits = totals.hits
    min_clear, is_bound_w = totals.clearance()

    # --- the default configuration: clearance of every frame pair ----------------------------
    c_def = sphere_world_centers(kin, spheres_all, q_default)
    def_clear = np.full(K, np.inf)
    if spheres_all.n_pairs:
        clr = pair_clearance(spheres_all, c_def)
        def_clear = np.minimum.reduceat(clr, spheres_all.pair_start[:-1])
    def_contacts = [c for c in contacts(spheres_all, c_def) if not c.masked]

    # --- per-pair verdicts -------------------------------------------------------------------
    counts = spheres_all.sphere_counts()
    ub = never_upper_bound(n_total)
    stats: list[PairStat] = []
    w_of = {int(k): i for i, k in enumerate(work_index)}
    for k, (a, b) in enumerate(pair_names):
        w = w_of.get(k)
        h = int(hits[w]) if w is not None else None
        rate = (h / n_total if n_total else 0.0) if h is not None else None
        mc: float | None = None
        is_bound = False
        if w is not None:
            mc = float(min_clear[w])
            is_bound = bool(is_bound_w[w])
        cls, rec, note = _verdict(
            bool(adj[k]), float(def_clear[k]), h, rate, n_total, ub, bool(masked[k]), source
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
                min_clearance=_finite(mc),
                min_clearance_is_bound=is_bound,
                default_clearance=float(def_clear[k]),
                classification=cls,
                recommendation=rec,
                note=note,
                joints_on_path=len(kin.joints_on_path(a, b)),
            )
        )

    if certify is not None:
        stats = _certify(engine, stats, w_of, cspace, certify)
    diags.extend(_findings(xrdf, kin, stats, def_contacts, trajectory, n_total))
    rec_ignore, change = _recommended_ignore(xrdf, kin, spheres_all, stats)
    cov = _coverage(upath, xrdf) if coverage else None
    return Report(
        xrdf_path=xrdf.source.path,
        urdf_path=upath,
        source=source,
        samples=n_total,
        sampler=sampler if source == "sampled" else None,
        seed=seed if source == "sampled" else None,
        cspace_joints=tuple(cspace),
        frames=spheres_all.frame_names,
        sphere_counts=FrozenMap(counts),
        placeholders=spheres_all.n_placeholders,
        pairs=tuple(stats),
        default_configuration=FrozenMap(
            (j, float(v)) for j, v in zip(kin.actuated_joints, q_default, strict=True)
        ),
        default_contacts=tuple(def_contacts),
        trajectory=tuple(trajectory) if trajectory is not None else None,
        recommended_ignore=rec_ignore,
        mask_change=change,
        diagnostics=tuple(sorted(diags, key=sort_key)),
        elapsed_s=time.perf_counter() - t0,
        coverage=cov,
    )


def _count_configs(
    engine: CountEngine, qc: FloatArray, chunk: int, progress: ProgressFn | None
) -> tuple[EngineTotals, list[TrajectoryHit]]:
    """Count given c-space configurations and list those where an unmasked pair collides."""
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
            q[:, engine.varying] = q_c[bad]
            centers = sphere_world_centers(engine.kin, checked, q)
            for b, c in zip(bad.tolist(), centers, strict=True):
                trajectory.append(TrajectoryHit(start + b, tuple(contacts(checked, c))))
        if progress is not None:
            progress(min(start + chunk, n_total), n_total)
    return totals, trajectory


def _certify(
    engine: CountEngine,
    stats: list[PairStat],
    w_of: Mapping[int, int],
    cspace: Sequence[str],
    opts: CertifyOptions,
) -> list[PairStat]:
    """Certify the "never" pairs, sharing the time budget evenly among those still to do."""
    todo = [i for i, p in enumerate(stats) if p.classification == "never" and i in w_of]
    deadline = time.perf_counter() + opts.budget_s
    out = list(stats)
    for n_left, i in zip(range(len(todo), 0, -1), todo, strict=True):
        budget = max(0.0, deadline - time.perf_counter()) / n_left
        cert = certify_pair(engine, w_of[i], budget)
        path = [cspace[j] for j in cert.joints]
        out[i] = _certified(stats[i], cert.verdict, cert.witness, cert.seconds, cspace, path, opts)
    return out


def _certified(
    p: PairStat,
    verdict: Verdict,
    witness: FloatArray | None,
    seconds: float,
    cspace: Sequence[str],
    path: Sequence[str],
    opts: CertifyOptions,
) -> PairStat:
    """The pair's statistics with the verdict of ``--certify`` (``path``: its joints)."""
    took = f"{seconds:.2f} s"
    if verdict == "witness" and witness is not None:
        values = {j: float(v) for j, v in zip(cspace, witness, strict=True)}
        what = "remove from ignore" if p.masked else "keep checking"
        at = ", ".join(f"{j}={values[j]:.4f}" for j in path)
        note = f"collides at {at} (others at default; found by --certify in {took}): {what}"
        return replace(
            p,
            classification="sometimes",
            recommendation="check",
            note=note,
            certificate="witness",
            witness=values,
            certify_s=seconds,
        )
    if verdict == "proven":
        note = f"proven never to collide over the whole joint box ({took}): ignore"
        return replace(
            p, recommendation="ignore", note=note, certificate="proven", certify_s=seconds
        )
    rec: Recommendation = "check" if opts.mask_policy == "proven" else p.recommendation
    note = f"{p.note}; not proven within the --certify budget ({took})"
    return replace(p, recommendation=rec, note=note, certificate="undecided", certify_s=seconds)


def _cspace_joints(kin: KinematicModel, xrdf: Xrdf) -> list[str]:
    if xrdf.cspace is None or not xrdf.cspace.joint_names:
        return list(kin.actuated_joints)
    return list(xrdf.cspace.joint_names)


def _verdict(
    adjacent: bool,
    default_clearance: float,
    hits: int | None,
    rate: float | None,
    n: int,
    ub: float,
    masked: bool,
    source: str,
) -> tuple[Classification, Recommendation, str]:
    what = "samples" if source == "sampled" else "given configurations"
    if adjacent:
        return "adjacent", "ignore", "adjacent frames: ignore"
    if default_clearance < 0:
        return "default", "ignore", "collides at the default configuration: ignore"
    assert hits is not None and rate is not None
    if rate > ALWAYS_RATE:
        return "always", "ignore", f"collides in {rate:.1%} of {what}: ignore"
    if hits == 0:
        return (
            "never",
            "may-ignore",
            f"may ignore: never seen in {n} {what} (rate < {ub:.2g} at 95 % confidence)",
        )
    if masked:
        return "sometimes", "check", f"collides in {rate:.3%} of {what}: remove from ignore"
    return "sometimes", "check", f"collides in {rate:.3%} of {what}: keep checking"


def _diag(xrdf: Xrdf, rule: str, message: str, key_path: str) -> Diagnostic:
    line, col = xrdf.source.position(key_path)
    return Diagnostic(xrdf.source.path, line, col, rule, _SEVERITY[rule], message, key_path)


def _ignore_key_path(sc: SelfCollisionSection | None, a: str, b: str) -> str:
    if sc is None:
        return "self_collision"
    for x, y in ((a, b), (b, a)):
        others = sc.ignore.get(x, ())
        if y in others:
            return f"self_collision.ignore.{x}[{others.index(y)}]"
    return "self_collision.ignore"


def _findings(
    xrdf: Xrdf,
    kin: KinematicModel,
    stats: Sequence[PairStat],
    def_contacts: Sequence[Contact],
    trajectory: Sequence[TrajectoryHit] | None,
    n: int,
) -> list[Diagnostic]:
    out: list[Diagnostic] = []
    sc = xrdf.self_collision
    for p in stats:
        pair = f"'{p.frame_a}' and '{p.frame_b}'"
        if not p.masked and p.rate is not None and p.rate > ALWAYS_RATE:
            out.append(
                _diag(
                    xrdf,
                    "report-always-colliding",
                    f"{pair} collide in {p.rate:.1%} of {n} configurations but are not in "
                    "self_collision.ignore: a planner will find no valid configuration",
                    "self_collision.ignore" if sc is not None else "self_collision",
                )
            )
        if p.masked and p.classification == "sometimes":
            seen = (
                "collide at a configuration that --certify found (sampling missed it)"
                if p.certificate == "witness"
                else f"collide in {p.hits} of {n} configurations ({p.rate:.3%})"
            )
            out.append(
                _diag(
                    xrdf,
                    "report-mask-hides-collision",
                    f"{pair} are ignored but are not adjacent and {seen}: the mask hides real "
                    "collisions",
                    _ignore_key_path(sc, p.frame_a, p.frame_b),
                )
            )
    for c in def_contacts:
        out.append(
            _diag(
                xrdf,
                "report-default-colliding",
                f"'{c.frame_a}' and '{c.frame_b}' collide at the default configuration "
                f"(clearance {c.clearance * 1000:.1f} mm, spheres {c.sphere_a} and "
                f"{c.sphere_b}) but are not in self_collision.ignore",
                "default_joint_positions",
            )
        )
    if sc is not None:
        for a, others in sc.ignore.items():
            for i, name in enumerate((a, *others)):
                if kin.has_frame(name):
                    continue
                kp = f"self_collision.ignore.{a}" + ("#key" if i == 0 else f"[{i - 1}]")
                out.append(
                    _diag(
                        xrdf,
                        "report-unknown-mask-frame",
                        f"self_collision.ignore names unknown frame '{name}'"
                        + did_you_mean(name, kin.frame_names)
                        + "; the entry masks nothing",
                        kp,
                    )
                )
    for hit in trajectory or ():
        worst = hit.contacts[0] if hit.contacts else None
        detail = (
            f"'{worst.frame_a}' and '{worst.frame_b}' (clearance {worst.clearance * 1000:.1f} mm)"
            if worst
            else "?"
        )
        more = f" and {len(hit.contacts) - 1} more pair(s)" if len(hit.contacts) > 1 else ""
        out.append(
            Diagnostic(
                xrdf.source.path,
                None,
                None,
                "report-trajectory-collision",
                Severity.ERROR,
                f"configuration {hit.index} is in self-collision: {detail}{more}",
                f"configs[{hit.index}]",
            )
        )
    return out


# ------------------------------------------------------------------------------------------
# Recommended mask
# ------------------------------------------------------------------------------------------
def _recommended_ignore(
    xrdf: Xrdf, kin: KinematicModel, spheres: SphereSet, stats: Sequence[PairStat]
) -> tuple[FrozenMap[str, tuple[str, ...]], MaskChange]:
    """Ignore map: pairs classified adjacent/default/always/never, plus existing entries
    between known frames that involve a frame without spheres (the report cannot judge
    them); entries naming unknown frames are dropped."""
    sc = xrdf.self_collision
    current = sc.ignore_pairs() if sc is not None else frozenset()
    sphere_frames = set(spheres.frame_names)
    want: set[frozenset[str]] = {
        frozenset((p.frame_a, p.frame_b)) for p in stats if p.recommendation != "check"
    }
    unknown: set[str] = set()
    for pair in current:
        names = tuple(pair)
        if not all(kin.has_frame(n) for n in names):
            unknown.update(n for n in names if not kin.has_frame(n))
            continue
        if not all(n in sphere_frames for n in names):
            want.add(pair)
    if sc is not None:  # self-entries and names in lone keys
        unknown.update(n for a, o in sc.ignore.items() for n in (a, *o) if not kin.has_frame(n))
    order = {f: i for i, f in enumerate(kin.frame_names)}

    def ordered(pair: frozenset[str]) -> tuple[str, str]:
        a, b = sorted(pair, key=lambda f: order[f])
        return a, b

    mapping: dict[str, list[str]] = {}
    for a, b in sorted((ordered(p) for p in want), key=lambda ab: (order[ab[0]], order[ab[1]])):
        mapping.setdefault(a, []).append(b)
    known_current = {p for p in current if all(kin.has_frame(n) for n in p)}
    added = sorted((ordered(p) for p in want - known_current), key=lambda ab: ab)
    removed = sorted((ordered(p) for p in known_current - want), key=lambda ab: ab)
    change = MaskChange(tuple(added), tuple(removed), tuple(sorted(unknown)))
    return FrozenMap((a, tuple(bs)) for a, bs in mapping.items()), change


def recommended_xrdf(xrdf: Xrdf, report: Report) -> Xrdf:
    """``xrdf`` with ``self_collision.ignore`` replaced by the report's recommendation."""
    sc = xrdf.self_collision
    if sc is None:
        raise XrdfToolsError("the XRDF has no self_collision section to write a mask into")
    return xrdf.replace(
        self_collision=SelfCollisionSection(
            geometry=sc.geometry,
            buffer_distance=sc.buffer_distance,
            ignore=FrozenMap(report.recommended_ignore),
        )
    )


# ------------------------------------------------------------------------------------------
# Optional coverage hook (xrdf_tools.spheres)
# ------------------------------------------------------------------------------------------
def _coverage(urdf_path: str, xrdf: Xrdf) -> CoverageSummary | None:
    """Coverage metrics from ``xrdf_tools.spheres.coverage_for_xrdf`` when it exists.

    The function is looked up lazily so the report works without the sphere tools. It must
    return a mapping ``frame -> {metric: value}`` (or a :class:`CoverageSummary`).
    """
    try:
        mod = importlib.import_module("xrdf_tools.spheres")
    except ImportError:
        return CoverageSummary({}, note="xrdf_tools.spheres is not available")
    fn = getattr(mod, "coverage_for_xrdf", None)
    if fn is None:
        return CoverageSummary({}, note="xrdf_tools.spheres provides no coverage_for_xrdf yet")
    result = fn(urdf_path, xrdf)
    if isinstance(result, CoverageSummary):
        return result
    data = result.to_dict() if hasattr(result, "to_dict") else dict(result)
    links = data.get("links", data)
    per_frame = {str(f): _numbers(m) for f, m in dict(links).items() if isinstance(m, Mapping)}
    overall = _numbers(data.get("overall", {}))
    unmeasured = data.get("unmeasured") or ()
    note = f"not measured (no geometry): {', '.join(unmeasured)}" if unmeasured else ""
    return CoverageSummary(per_frame, overall, note)


def _numbers(m: Any) -> dict[str, float]:
    if not isinstance(m, Mapping):
        return {}
    return {
        str(k): float(v)
        for k, v in m.items()
        if isinstance(v, (int, float)) and not isinstance(v, bool)
    }
