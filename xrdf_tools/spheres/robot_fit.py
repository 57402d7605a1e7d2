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

from ..diagnostics import Diagnostic
from ..robot.core import Robot
from ..util.errors import XrdfToolsError
from ..util.text import name_list
from ..xrdf.model import Sphere
from .budget import allocate
from .count_policy import BY_TARGET, MAX_PER_LINK, CountPolicy, check_policy
from .link_fit import (
    fit_mode,
    fit_note,
    fit_one,
    fit_sheet,
    link_fitter,
    morphit_one,
    sheet_of,
)

if TYPE_CHECKING:
    import trimesh

    from ..robot.link_geometry import GeometryChoice
    from ..robot.packages import PackagePaths
    from .fit import LinkPlan, Plane, SphereFitter
    from .geometry import LinkGeometry
    from .sheet import SheetPlan
    from .visual_agreement import VisualCheck

RULE_SHARED_MESH = "spheres-shared-mesh"
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


def fit_robot(
    robot: str | os.PathLike[str] | Robot,
    *,
    links: Sequence[str] | None = None,
    counts: CountPolicy = BY_TARGET,
    seed: int = 0,
    package_paths: PackagePaths | None = None,
    max_protrusion: float | Mapping[str, float] | None = None,
    clips: Mapping[str, Sequence[Plane]] | None = None,
    progress: Progress | None = None,
    source: GeometryChoice = "auto",
    geometry: Mapping[str, LinkGeometry] | None = None,
    method: str = "ours",
    visual_check: VisualCheck = "fast",
    reading: Progress | None = None,
) -> FitResult:
    """Fit spheres to the links of ``robot`` (see the module docstring and
    :func:`xrdf_tools.spheres.fit_link_spheres`). ``clips`` keeps a link's spheres on the
    positive side of planes in its frame; ``geometry`` skips loading the solids; ``method``
    ``morphit`` fits each solid with MorphIt instead (:mod:`.morphit`). ``visual_check``:
    how each link fitted from collision geometry is compared with its visual geometry
    (:mod:`.visual_agreement`; not for ``geometry`` given with a path). ``reading(link, i,
    n)`` is called before each link's geometry is read (``progress`` then for each link
    prepared and fitted)."""
    from .morphit import check_method

    check_method(method, searched_bound=counts.count_coverage is not None)
    check_policy(counts)
    if not isinstance(robot, Robot) and geometry is None:
        from ..robot.xacro_source import load_robot

        robot = load_robot(robot, package_paths=package_paths)
    geoms, diags = _solids(robot, links, package_paths, source, geometry, reading)
    if isinstance(robot, Robot):
        from .visual_agreement import visual_disagreements

        diags += visual_disagreements(robot, geoms, package_paths=package_paths, check=visual_check)
    _check_against_solids(counts, clips or {}, geoms)
    path = robot.path if isinstance(robot, Robot) else os.fspath(robot)
    plans = _plan(geoms, max_protrusion, clips or {}, seed)
    exact = {n: geoms[n].exact for n, plan in plans.items() if geoms[n].exact and not plan[2]}
    run = _Run(
        geoms,
        {n: plan for n, plan in plans.items() if n not in exact},
        counts,
        path,
        progress if progress is not None else (lambda _link, _i, _n: None),
        diags,
        _moving_joints(robot) if isinstance(robot, Robot) else {},
    )
    _prepare(run)
    copies = Counter(run.first_of[key] for key, *_rest in run.plans.values())
    ks = _counts(run.fitters, counts, copies, taken=sum(len(w) for w in exact.values()))
    spheres = _fit_solids(run, ks, method)
    _report_shared(run.plans, run.first_of, path, geoms, diags)
    _take_urdf_spheres(run, exact, spheres)
    fitted = {n: spheres[n] for n in geoms if spheres.get(n)}
    return FitResult(
        fitted,
        {n: run.seconds[n] for n in fitted},
        {n: geoms[n].kind for n in fitted},
        {n: geoms[n] for n in fitted},
        diags,
    )


def _solids(
    robot: str | os.PathLike[str] | Robot,
    links: Sequence[str] | None,
    package_paths: PackagePaths | None,
    source: GeometryChoice,
    geometry: Mapping[str, LinkGeometry] | None,
    reading: Progress | None,
) -> tuple[dict[str, LinkGeometry], list[Diagnostic]]:
    """The solids to fit per link (URDF link order): ``geometry`` when given, else loaded
    from ``robot`` (``reading`` told of each link) with the diagnostics of loading them."""
    if geometry is not None:
        return dict(geometry), []
    from .geometry import load_link_geometry

    return load_link_geometry(
        robot, links=links, package_paths=package_paths, source=source, progress=reading
    )


def _check_against_solids(
    counts: CountPolicy, clips: Mapping[str, Sequence[Plane]], geoms: Mapping[str, LinkGeometry]
) -> None:
    """Raise for a total count under one sphere per link, or a clip plane on a link without
    a solid to fit."""
    if counts.count is not None and counts.count < len(geoms):
        raise XrdfToolsError(
            f"count {counts.count} is less than the number of links to fit ({len(geoms)})"
        )
    stray = [k for k in clips if k not in geoms]
    if stray:
        raise XrdfToolsError(
            f"clip plane(s) for link(s) without geometry to fit: {name_list(stray)}"
        )


@dataclass
class _Run:
    """One :func:`fit_robot` between its steps: the links to fit (``plans``, the URDF's own
    spheres left out), their solids, the count policy, the URDF path the notes name, the
    progress callback and the diagnostics; then what :func:`_prepare` fills in: the first
    link of each distinct solid (``first_of``: plan key → link), its fitter or sheet plan,
    and the seconds each link took."""

    geoms: Mapping[str, LinkGeometry]
    plans: dict[str, LinkPlan]
    counts: CountPolicy
    path: str
    step: Progress
    diags: list[Diagnostic]
    #: Per link, the joint nearest above it that moves it (links fixed to the root: absent).
    moved_by: Mapping[str, str]
    first_of: dict[tuple[object, ...], str] = field(default_factory=dict)
    fitters: dict[str, SphereFitter] = field(default_factory=dict)
    sheets: dict[str, SheetPlan] = field(default_factory=dict)
    seconds: dict[str, float] = field(default_factory=dict)


def _prepare(run: _Run) -> None:
    """Steps ``0 … n - 1``: the first link of each distinct solid gets a sheet plan when the
    sheet rule applies, else our fitter; a link sharing an earlier one's solid takes 0 s."""
    for i, (name, plan) in enumerate(run.plans.items()):
        run.step(name, i, 2 * len(run.plans))
        if plan[0] in run.first_of:
            run.seconds[name] = 0.0
            continue
        run.first_of[plan[0]] = name
        t0 = time.perf_counter()
        sheet = sheet_of(run.geoms[name], plan, run.counts)
        if sheet is not None:
            run.sheets[name] = sheet
        else:
            run.fitters[name] = link_fitter(run.geoms[name], plan, run.counts)
        run.seconds[name] = time.perf_counter() - t0


def _fit_solids(run: _Run, ks: Mapping[str, int], method: str) -> dict[str, tuple[Sphere, ...]]:
    """Steps ``n … 2n - 1``: each distinct solid fitted once (``ks``: its count, none by
    target), its spheres shared by the links with the same solid."""
    spheres: dict[str, tuple[Sphere, ...]] = {}
    for i, (name, (key, *_rest)) in enumerate(run.plans.items(), start=len(run.plans)):
        run.step(name, i, 2 * len(run.plans))
        owner = run.first_of[key]
        if owner != name:
            spheres[name] = spheres[owner]
            continue
        t0 = time.perf_counter()
        spheres[name] = _fit_solid(run, name, ks.get(name), method)
        run.seconds[name] += time.perf_counter() - t0
    return spheres


def _fit_solid(run: _Run, name: str, k: int | None, method: str) -> tuple[Sphere, ...]:
    """The spheres of link ``name``'s solid: by its sheet plan, by MorphIt, or by ours."""
    geom, plan = run.geoms[name], run.plans[name]
    if name in run.sheets:
        return fit_sheet(run.sheets[name], geom, plan[1], run.path, run.diags)
    fitter = run.fitters[name]
    if method == "morphit":
        return morphit_one(fitter, k, run.counts, geom, plan, run.path, run.diags)
    mode = fit_mode(plan[1], run.counts)
    own = plan[1] is not None
    moved_by = run.moved_by.get(name)
    return fit_one(fitter, k, run.counts, geom, run.path, run.diags, mode, own, moved_by)


def _moving_joints(robot: Robot) -> dict[str, str]:
    """Per link, the joint nearest above it that moves it: neither fixed nor held still by
    equal limits (a carriage on a rail: the rail's joint). Links fixed to the root are left
    out."""
    tree = robot.tree
    out: dict[str, str] = {}
    for name in tree.dfs_joints():  # a parent before its children
        joint = tree.joints[name]
        mover = out.get(joint.parent) if tree.is_held(name) else name
        if mover is not None:
            out[joint.child] = mover
    return out


def _take_urdf_spheres(
    run: _Run, exact: Mapping[str, tuple[Sphere, ...]], spheres: dict[str, tuple[Sphere, ...]]
) -> None:
    """The links whose geometry is the URDF's own spheres get them as they are (0 s), said
    once each."""
    for name, written in exact.items():
        spheres[name], run.seconds[name] = written, 0.0
        geom = run.geoms[name]
        run.diags.append(
            fit_note(
                run.path,
                geom.line,
                RULE_URDF_SPHERES,
                f"link '{name}': its {geom.source} geometry is {len(written)} <sphere> "
                "element(s), taken as they are",
            )
        )


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
            fit_note(
                path,
                geoms[owner].line,
                RULE_SHARED_MESH,
                f"link '{owner}' has the same geometry as {name_list(others)}: fitted once, "
                "the same spheres",
            )
        )
