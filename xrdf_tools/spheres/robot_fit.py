"""Spheres for every link of a robot: how many per link, shared meshes, clip planes, timing.

:func:`fit_robot` is the one place the per-link fits of :class:`~.fit.SphereFitter` are
planned; :func:`xrdf_tools.spheres.fit_link_spheres` is its two-value form.

* Counts, at most one of ``per_link`` (``n`` or ``{link: n}``), ``count`` (a total, also the
  ``--sphere-budget`` of ``xrdf convert``: every sphere of the result, split by :mod:`.budget`:
  one per link, then each further sphere to the link whose covered volume grows most),
  ``density`` (per litre); by default the fewest spheres
  (up to ``AUTO_MAX_PER_LINK``) that cover ``target_coverage`` of the link's volume at the
  protrusion bound.
* With a count given and no protrusion bound of the link's own, the greedy spheres are
  refined (:mod:`.refine`: coverage against the 95th percentile of the union's protrusion)
  unless ``CountPolicy(refine=False)``; a bound given is kept as a hard bound.
* A tiny placeholder (bounding-box diagonal under ``PLACEHOLDER_SIZE``) gets one sphere.
* Without a count, a sheet with no protrusion bound or clip plane of its own (:mod:`.sheet`:
  far thinner than wide, and thinner than the bound) gets a few spheres covering all of it.
* Links whose solids are identical (same vertices and faces in the link frame, same options)
  are fitted once: the generator of a fit is seeded from ``seed`` and the solid's content, so
  the spheres do not depend on the link's name or on which other links are fitted.
"""

from __future__ import annotations

import hashlib
import math
import os
import time
from collections import Counter
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from ..diagnostics import Diagnostic, Severity
from ..robot.core import Robot
from ..util.errors import XrdfToolsError
from ..util.fixed_order import norm
from ..util.numbers import PLACEHOLDER_SIZE
from ..util.text import name_list
from ..xrdf.model import Sphere
from .budget import allocate
from .fewest import default_fit, fewest_reaching

if TYPE_CHECKING:
    import trimesh

    from ..robot.link_geometry import GeometryChoice
    from .fit import LinkPlan, Plane, SphereFitter
    from .geometry import LinkGeometry
    from .sheet import SheetPlan

MAX_PER_LINK = 64
AUTO_COVERAGE_TARGET = 0.9

RULE_SHARED_MESH = "spheres-shared-mesh"
RULE_TARGET_MISSED = "spheres-target-missed"
RULE_PLACEHOLDER = "spheres-placeholder"
RULE_SHEET = "spheres-sheet"
RULE_PAST_BOUND = "spheres-past-bound"
RULE_URDF_SPHERES = "spheres-from-urdf"

#: ``progress(link, i, n)``: called before step ``i`` of ``n``, two per link (each link is
#: prepared in steps ``0 … n/2 - 1``, then fitted in the same order).
Progress = Callable[[str, int, int], None]


@dataclass(frozen=True)
class FitResult:
    """What :func:`fit_robot` made: spheres per link (URDF link order), the seconds each link
    took (0 for a link that reused another's fit), how each link's solid was made
    (``LinkGeometry.kind``), the solids themselves and the diagnostics."""

    spheres: dict[str, tuple[Sphere, ...]]
    seconds: dict[str, float] = field(default_factory=dict)
    kinds: dict[str, str] = field(default_factory=dict)
    geometry: dict[str, LinkGeometry] = field(default_factory=dict)
    diagnostics: list[Diagnostic] = field(default_factory=list)


def link_seed(seed: int, link: str) -> list[int]:
    """Seed of one link's metric samples: independent of which other links are measured."""
    import zlib

    return [int(seed) & 0xFFFFFFFF, zlib.crc32(link.encode("utf-8"))]


def solid_key(solid: trimesh.Trimesh) -> str:
    """Content hash of a solid (vertices and faces as little-endian bytes)."""
    h = hashlib.sha256()
    h.update(np.ascontiguousarray(solid.vertices, dtype="<f8").tobytes())
    h.update(np.ascontiguousarray(solid.faces, dtype="<i8").tobytes())
    return h.hexdigest()


def check_counts(
    per_link: int | Mapping[str, int] | None, count: int | None, density: float | None
) -> None:
    """Raise for more than one counting option or a value out of range."""
    given = [
        n
        for n, v in (("per_link", per_link), ("count", count), ("density", density))
        if v is not None
    ]
    if len(given) > 1:
        raise XrdfToolsError(f"give at most one of count, per-link and density (got {given})")
    for n in per_link.values() if isinstance(per_link, Mapping) else [per_link]:
        if n is not None and not 0 <= n <= MAX_PER_LINK:
            raise XrdfToolsError(f"per-link must be between 1 and {MAX_PER_LINK}, got {n}")
    if isinstance(per_link, int) and per_link < 1:
        raise XrdfToolsError(f"per-link must be between 1 and {MAX_PER_LINK}, got {per_link}")
    if count is not None and count < 1:
        raise XrdfToolsError(f"count must be at least 1, got {count}")
    if density is not None and not (density > 0 and math.isfinite(density)):
        raise XrdfToolsError(f"density must be a positive number, got {density}")


@dataclass(frozen=True)
class CountPolicy:
    """How many spheres each link gets (see :func:`fit_robot`)."""

    per_link: int | Mapping[str, int] | None = None
    count: int | None = None
    density: float | None = None
    target_coverage: float = AUTO_COVERAGE_TARGET
    #: With a count given and no protrusion bound of the link's own: its bound is the
    #: smallest at which its spheres cover this share of its volume (None: the default
    #: bound, :func:`~.fit.default_max_protrusion`).
    count_coverage: float | None = None
    #: With a count given and no protrusion bound of the link's own (and no
    #: ``count_coverage``): the greedy spheres are refined on coverage and on the protrusion
    #: of their union (:mod:`.refine`). False keeps every sphere within the default bound.
    refine: bool = True

    @property
    def given(self) -> bool:
        """Whether a count is given (per link, in total or by density)."""
        return self.per_link is not None or self.count is not None or self.density is not None


def _info(path: str, line: int | None, rule: str, message: str, warn: bool = False) -> Diagnostic:
    return Diagnostic(path, line, None, rule, Severity.WARNING if warn else Severity.INFO, message)


def fit_robot(
    robot: str | os.PathLike[str] | Robot,
    *,
    links: Sequence[str] | None = None,
    counts: CountPolicy = CountPolicy(),
    seed: int = 0,
    package_paths: Mapping[str, str] | None = None,
    max_protrusion: float | Mapping[str, float] | None = None,
    clips: Mapping[str, Sequence[Plane]] | None = None,
    progress: Progress | None = None,
    source: GeometryChoice = "auto",
    geometry: Mapping[str, LinkGeometry] | None = None,
    method: str = "ours",
) -> FitResult:
    """Fit spheres to the links of ``robot`` (see the module docstring and
    :func:`xrdf_tools.spheres.fit_link_spheres`). ``clips`` keeps a link's spheres on the
    positive side of planes in its frame; ``geometry`` skips loading the solids; ``method``
    ``morphit`` fits each solid with MorphIt instead (:mod:`.morphit`)."""
    from .fit import SphereFitter
    from .geometry import load_link_geometry
    from .morphit import check_method

    check_method(method, searched_bound=counts.count_coverage is not None)
    check_counts(counts.per_link, counts.count, counts.density)
    for what, share in (("target", counts.target_coverage), ("count", counts.count_coverage)):
        if share is not None and not 0.0 < share <= 1.0:
            raise XrdfToolsError(f"{what} coverage must be in (0, 1], got {share}")
    diags: list[Diagnostic] = []
    if geometry is None:
        geoms, diags = load_link_geometry(
            robot, links=links, package_paths=package_paths, source=source
        )
    else:
        geoms = dict(geometry)
    if counts.count is not None and counts.count < len(geoms):
        raise XrdfToolsError(
            f"count {counts.count} is less than the number of links to fit ({len(geoms)})"
        )
    path = robot.path if isinstance(robot, Robot) else os.fspath(robot)
    stray = [k for k in clips or {} if k not in geoms]
    if stray:
        raise XrdfToolsError(
            f"clip plane(s) for link(s) without geometry to fit: {name_list(stray)}"
        )
    order = list(geoms)
    plans = _plan(geoms, max_protrusion, clips or {}, seed)
    exact = {n: geoms[n].exact for n, plan in plans.items() if geoms[n].exact and not plan[2]}
    plans = {n: plan for n, plan in plans.items() if n not in exact}
    fitters: dict[str, SphereFitter] = {}
    sheets: dict[str, SheetPlan] = {}
    seconds: dict[str, float] = {}
    first_of: dict[tuple[object, ...], str] = {}
    step: Progress = progress if progress is not None else (lambda _link, _i, _n: None)
    for i, (name, (key, tau, planes, fit_seed)) in enumerate(plans.items()):
        step(name, i, 2 * len(plans))
        if key in first_of:
            seconds[name] = 0.0
            continue
        first_of[key] = name
        t0 = time.perf_counter()
        sheet = _sheet(geoms[name], plans[name], counts)
        if sheet is not None:
            sheets[name] = sheet
            seconds[name] = time.perf_counter() - t0
            continue
        fitters[name] = SphereFitter(
            geoms[name].solid,
            seed=fit_seed,
            max_protrusion=tau,
            clips=planes,
            room=_refine_room(geoms[name].solid, tau, counts),
        )
        seconds[name] = time.perf_counter() - t0
    copies = Counter(first_of[key] for key, *_rest in plans.values())
    ks = _counts(fitters, counts, copies, taken=sum(len(w) for w in exact.values()))
    spheres: dict[str, tuple[Sphere, ...]] = {}
    for i, (name, (key, *_rest)) in enumerate(plans.items(), start=len(plans)):
        step(name, i, 2 * len(plans))
        owner = first_of[key]
        if owner != name:
            spheres[name] = spheres[owner]
            continue
        t0 = time.perf_counter()
        if owner in sheets:
            spheres[name] = _fit_sheet(sheets[owner], geoms[name], plans[name][1], path, diags)
        elif method == "morphit":
            spheres[name] = _morphit_one(
                fitters[owner], ks.get(owner), counts, geoms[name], plans[name], path, diags
            )
        else:
            own = plans[name][1] is not None
            mode = _fit_mode(plans[name][1], counts)
            spheres[name] = _fit_one(
                fitters[owner], ks.get(owner), counts, geoms[name], path, diags, mode, own
            )
        seconds[name] += time.perf_counter() - t0
    _report_shared(plans, first_of, path, geoms, diags)
    for name, written in exact.items():  # the URDF's own spheres: nothing to fit
        spheres[name], seconds[name] = written, 0.0
        diags.append(
            _info(
                path,
                geoms[name].line,
                RULE_URDF_SPHERES,
                f"link '{name}': its {geoms[name].source} geometry is {len(written)} <sphere> "
                "element(s), taken as they are",
            )
        )
    fitted = {n: spheres[n] for n in order if spheres.get(n)}
    return FitResult(
        fitted,
        {n: seconds[n] for n in fitted},
        {n: geoms[n].kind for n in fitted},
        {n: geoms[n] for n in fitted},
        diags,
    )


def _sheet(geom: LinkGeometry, plan: LinkPlan, counts: CountPolicy) -> SheetPlan | None:
    """How the sheet rule fits a link (:func:`.sheet.sheet_plan`), when it applies: no count
    given, no clip plane, not a placeholder."""
    if counts.given or plan[2] or _across(geom) < PLACEHOLDER_SIZE:
        return None
    from .sheet import sheet_plan

    return sheet_plan(geom.solid, plan[1])


def _fit_sheet(
    sheet: SheetPlan, geom: LinkGeometry, bound: float | None, path: str, diags: list[Diagnostic]
) -> tuple[Sphere, ...]:
    """A sheet's spheres (:func:`.sheet.sheet_spheres`), said once for the link; ``bound``:
    the link's own protrusion bound."""
    from .fit import default_max_protrusion
    from .sheet import sheet_message, sheet_spheres

    spheres = sheet_spheres(*sheet)
    tau = default_max_protrusion(geom.solid) if bound is None else bound
    message, past = sheet_message(geom.link, sheet[0], spheres, tau, own=bound is not None)
    diags.append(_info(path, geom.line, RULE_SHEET, message, warn=past))
    return spheres


def _fit_mode(tau: float | None, counts: CountPolicy) -> str:
    """How :func:`_fit_one` fits a link whose own bound is ``tau`` (None: the default)."""
    if _refines(tau, counts):
        return "refine"
    return "search" if tau is None and counts.count_coverage is not None else "hard"


def _across(geom: LinkGeometry) -> float:
    """The bounding-box diagonal of a link's solid: under :data:`PLACEHOLDER_SIZE`, a
    placeholder."""
    return norm(np.asarray(geom.solid.extents, dtype=np.float64))  # not a BLAS dot product


def _refines(tau: float | None, counts: CountPolicy) -> bool:
    """Whether a link's count-given fit is refined (:mod:`.refine`): a count is given, the
    link has no bound of its own and no bound is searched for a coverage."""
    return counts.given and tau is None and counts.refine and counts.count_coverage is None


def _refine_room(solid: trimesh.Trimesh, tau: float | None, counts: CountPolicy) -> float | None:
    """How far the distance grid of a refined fit reaches: past the loosest start's bound,
    so that one grid serves every start (None: the fitter's own bound)."""
    if not _refines(tau, counts):
        return None
    from .fit import default_max_protrusion
    from .refine import START_BOUNDS

    return max(START_BOUNDS) * default_max_protrusion(solid)


def _plan(
    geoms: Mapping[str, LinkGeometry],
    max_protrusion: float | Mapping[str, float] | None,
    clips: Mapping[str, Sequence[Plane]],
    seed: int,
) -> dict[str, LinkPlan]:
    """Per link: the cache key of its fit, its protrusion budget, clip planes and seed."""
    out: dict[str, LinkPlan] = {}
    for name, g in geoms.items():
        tau = max_protrusion.get(name) if isinstance(max_protrusion, Mapping) else max_protrusion
        planes = tuple(clips.get(name, ()))
        content = solid_key(g.solid)
        key = (content, tau, planes)
        out[name] = (key, tau, planes, [int(seed) & 0xFFFFFFFF, int(content[:8], 16)])
    return out


def _counts(
    fitters: Mapping[str, SphereFitter], counts: CountPolicy, copies: Mapping[str, int], taken: int
) -> dict[str, int]:
    """Spheres per fitted solid for the explicit counting options (empty: by target); a total
    ``count`` holds the ``taken`` spheres of the URDF and each solid once per link sharing it
    (``copies``: :mod:`.budget`)."""
    if isinstance(counts.per_link, Mapping):
        return {n: int(counts.per_link.get(n, 0)) for n in fitters}
    if counts.per_link is not None:
        return dict.fromkeys(fitters, counts.per_link)
    if counts.density is not None:
        d = counts.density
        return {  # capped before ceil: a density of 1e308 times a volume is inf
            n: max(1, math.ceil(min(d * f.volume * 1000.0, MAX_PER_LINK) - 1e-9))
            for n, f in fitters.items()
        }
    if counts.count is not None:
        budget, least = counts.count - taken, sum(copies[n] for n in fitters)
        if budget < least:
            raise XrdfToolsError(
                f"count {counts.count} is less than one sphere per link to fit ({least}) and "
                f"the URDF's own {taken} sphere(s)"
            )
        curves = {n: f.greedy(min(MAX_PER_LINK, budget - least + 1))[1] for n, f in fitters.items()}
        return allocate(curves, {n: f.volume for n, f in fitters.items()}, budget, copies)
    return {}


def _morphit_one(
    fitter: SphereFitter,
    k: int | None,
    counts: CountPolicy,
    geom: LinkGeometry,
    plan: LinkPlan,
    path: str,
    diags: list[Diagnostic],
) -> tuple[Sphere, ...]:
    """One link's spheres by MorphIt (:mod:`.morphit`): ``k`` of them, or the count our fit
    needs for the coverage target; an empty solid or a placeholder is handled as ours."""
    from .morphit import fit_link

    if fitter.empty or _across(geom) < PLACEHOLDER_SIZE:
        return _fit_one(fitter, k, counts, geom, path, diags)
    if k is None:
        k = len(fewest_reaching(fitter, counts.target_coverage)[0])
    return fit_link(fitter, k, geom, plan, path, diags)


def _fit_one(
    fitter: SphereFitter,
    k: int | None,
    counts: CountPolicy,
    geom: LinkGeometry,
    path: str,
    diags: list[Diagnostic],
    mode: str = "hard",
    own_bound: bool = False,
) -> tuple[Sphere, ...]:
    """One link's spheres: ``k`` of them (``mode``: ``hard`` within the fitter's bound,
    ``refine`` then refined on coverage and protrusion, ``search`` under the smallest bound
    at which they cover ``counts.count_coverage``), or the fewest reaching the coverage
    target (past the default bound when it cannot be reached within it, unless the link has
    a bound of its own: :mod:`.fewest`)."""
    if fitter.empty and k != 0:
        diags.append(
            _info(
                path,
                geom.line,
                RULE_TARGET_MISSED,
                f"link '{geom.link}': nothing of it lies on the kept side of its clip planes; "
                "no spheres",
                warn=True,
            )
        )
        return ()
    size = _across(geom)
    if size < PLACEHOLDER_SIZE and (k is None or k > 1):
        diags.append(
            _info(
                path,
                geom.line,
                RULE_PLACEHOLDER,
                f"link '{geom.link}' is a placeholder ({size * 1000:.0f} mm across): one sphere",
            )
        )
        return fitter.fit(1)
    if k is not None and mode == "search" and counts.count_coverage is not None:
        from .fit import bound_for_coverage

        return bound_for_coverage(fitter, k, counts.count_coverage)
    if k is not None and mode == "refine":
        from .refine import refined_fit

        return refined_fit(fitter, k)
    if k is not None:
        return fitter.fit(k)
    past = not own_bound and counts.refine
    spheres, note = default_fit(fitter, counts.target_coverage, past=past, most=MAX_PER_LINK)
    if note is not None:
        missed, text = note
        rule = RULE_TARGET_MISSED if missed else RULE_PAST_BOUND
        diags.append(_info(path, geom.line, rule, f"link '{geom.link}': {text}", warn=missed))
    return spheres


def _report_shared(
    plans: Mapping[str, LinkPlan],
    first_of: Mapping[tuple[object, ...], str],
    path: str,
    geoms: Mapping[str, LinkGeometry],
    diags: list[Diagnostic],
) -> None:
    """One line per fit reused by other links."""
    reused: dict[str, list[str]] = {}
    for name, (key, *_rest) in plans.items():
        owner = first_of[key]
        if owner != name:
            reused.setdefault(owner, []).append(name)
    for owner, others in reused.items():
        diags.append(
            _info(
                path,
                geoms[owner].line,
                RULE_SHARED_MESH,
                f"link '{owner}' has the same geometry as {name_list(others)}: fitted once, "
                "the same spheres",
            )
        )
