"""``xrdf spheres`` as library calls: fit a robot's links, merge the spheres into an XRDF, say
which links were not covered, and measure the fit.

:func:`fit_spheres` takes the loaded robot, the XRDF to merge into (None: one is drafted as
``xrdf convert`` would, with adjacent links added to the ignore mask) and a
:class:`SpheresRequest`; it returns a :class:`SpheresFit` (the merged XRDF, the fit and its
diagnostics, and one error per link with geometry that got no spheres or only some).
:func:`fit_metrics` measures the fitted spheres against the link geometry; :func:`metrics_table`
and :func:`metrics_json` render those metrics.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING

from ..diagnostics import Diagnostic
from ..robot.xacro_places import located_at_elements

if TYPE_CHECKING:
    from collections.abc import Callable

    from ..robot.core import Robot
    from ..robot.link_geometry import GeometryChoice
    from ..robot.packages import PackagePaths
    from ..spheres import SphereMetrics
    from ..spheres.count_policy import CountPolicy
    from ..spheres.fit import Plane
    from ..spheres.robot_fit import FitResult
    from ..spheres.visual_agreement import VisualCheck
    from ..xrdf.model import Xrdf

#: Samples per link of the fit metrics.
METRIC_SAMPLES = 10_000


@dataclass(frozen=True)
class SpheresRequest:
    """What to fit: ``links`` (None: every link with geometry), how many spheres
    (``counts``), the random ``seed``, ROS ``package_paths`` for mesh URIs, the largest
    ``max_protrusion`` (None: per link, from its volume), ``clips`` (``LINK:nx,ny,nz,d``
    texts: keep LINK's spheres on the side of the plane its normal points to), whether
    mesh files that cannot be found are expected (``allow_missing_meshes``) and the fitting
    ``method`` (``ours`` or ``morphit``, :mod:`xrdf_tools.spheres.morphit`)."""

    counts: CountPolicy
    links: Sequence[str] | None = None
    seed: int = 0
    package_paths: PackagePaths = field(default_factory=dict)
    max_protrusion: float | None = None
    clips: Sequence[str] = ()
    allow_missing_meshes: bool = False
    method: str = "ours"
    #: How collision geometry is compared with visual geometry (``fast``, ``all``, ``off``).
    visual_check: VisualCheck = "fast"
    #: Which geometry is fitted: ``collision``, ``visual`` or ``auto`` (collision, else visual).
    source: GeometryChoice = "auto"


@dataclass(frozen=True)
class SpheresFit:
    """The outcome of :func:`fit_spheres`: the XRDF with the new spheres, the fit itself,
    the diagnostics of drafting, fitting, merging and masking (in that order) and one error
    per wanted link with geometry that got no spheres or only some (``unfitted``)."""

    xrdf: Xrdf
    fit: FitResult
    diagnostics: list[Diagnostic]
    unfitted: list[Diagnostic]


def fit_spheres(
    robot: Robot,
    base: Xrdf | None,
    request: SpheresRequest,
    *,
    progress: Callable[[str, int, int], None] | None = None,
    reading: Callable[[str, int, int], None] | None = None,
) -> SpheresFit:
    """Fit spheres to the links of ``robot`` and merge them into ``base`` (None: an XRDF
    drafted as ``xrdf convert`` drafts one, with adjacent links added to the ignore mask).
    ``progress(link, i, n)`` is called per step, two per link (prepared, then fitted), after
    ``reading(link, i, n)`` before each link's geometry is read. Raises
    :class:`~xrdf_tools.util.errors.XrdfToolsError` (a mesh file that cannot be found unless
    ``allow_missing_meshes``, a malformed clip plane)."""
    from ..robot.link_geometry import require_meshes
    from ..spheres import ignore_adjacent, merge_spheres
    from ..spheres.fit import parse_clip
    from ..spheres.robot_fit import fit_robot
    from .fit_check import unfitted_links
    from .pipeline import geometry_links

    diags: list[Diagnostic] = []
    if base is None:
        from .core import ConvertOptions, convert

        drafted, cdiags = convert(robot, ConvertOptions())
        diags += [d for d in cdiags if d.rule != "convert-no-spheres"]
    links = list(request.links) if request.links else None
    wanted = [n for n in geometry_links(robot, request.source)[0] if n in (links or [n])]
    missing = require_meshes(
        robot,
        request.source,
        links=wanted,
        package_paths=dict(request.package_paths),
        allow_missing=request.allow_missing_meshes,
    )
    clips: dict[str, list[Plane]] = {}
    for text in request.clips:
        link, plane = parse_clip(text)
        clips.setdefault(link, []).append(plane)
    result = fit_robot(
        robot,
        links=links,
        counts=request.counts,
        seed=request.seed,
        package_paths=dict(request.package_paths),
        max_protrusion=request.max_protrusion,
        clips=clips,
        progress=progress,
        reading=reading,
        method=request.method,
        visual_check=request.visual_check,
        source=request.source,
    )
    diags += result.diagnostics
    merged, mdiags = merge_spheres(drafted if base is None else base, result.spheres)
    diags += mdiags
    if base is None:
        merged, adiags = ignore_adjacent(merged, robot)
        diags += adiags
    unfitted = unfitted_links(
        robot.path,
        wanted,
        result.spheres,
        result.diagnostics,
        allowed_missing=missing,
        lines=robot.link_lines,
    )
    places = robot.include_places
    diags = located_at_elements(diags, robot.path, places)
    unfitted = located_at_elements(unfitted, robot.path, places)
    return SpheresFit(merged, result, diags, unfitted)


def fit_metrics(
    fit: FitResult, seed: int = 0, *, timings: bool = False
) -> tuple[dict[str, SphereMetrics], SphereMetrics]:
    """How well the spheres of ``fit`` cover their links: metrics per link and overall; with
    ``timings`` each also holds the seconds its fit took (wall time: it differs run to run,
    the rest is the same for the same inputs)."""
    from ..spheres import measure_links

    per, overall = measure_links(fit.geometry, fit.spheres, samples=METRIC_SAMPLES, seed=seed)
    if not timings:
        return per, overall
    per = {n: replace(m, fit_seconds=round(fit.seconds[n], 3)) for n, m in per.items()}
    overall = replace(overall, fit_seconds=round(sum(fit.seconds.values()), 3))
    return per, overall


#: Columns of the metrics table: header, SphereMetrics field, scale, format.
_COLUMNS = (
    ("spheres", "sphere_count", 1.0, "{:>7d}"),
    ("coverage", "coverage", 1.0, "{:>8.3f}"),
    ("surface", "surface_coverage", 1.0, "{:>7.3f}"),
    ("protr.share", "protrusion_share", 1.0, "{:>11.3f}"),
    ("protr.mean", "protrusion_mean", 1000.0, "{:>10.1f}"),
    ("protr.p95", "protrusion_p95", 1000.0, "{:>9.1f}"),
    ("gap mean", "surface_gap_mean", 1000.0, "{:>8.1f}"),
    ("gap p95", "surface_gap_p95", 1000.0, "{:>7.1f}"),
    ("max gap", "max_uncovered_gap", 1000.0, "{:>7.1f}"),
    ("vol.ratio", "volume_ratio", 1.0, "{:>9.3f}"),
    ("fit s", "fit_seconds", 1.0, "{:>6.2f}"),
)


def metrics_table(per: dict[str, SphereMetrics], overall: SphereMetrics) -> str:
    """Plain-text table: one row per link and an overall row (lengths in millimetres)."""
    width = max([24, *(len(n) for n in per)])
    timed = overall.fit_seconds is not None
    columns = [c for c in _COLUMNS if timed or c[1] != "fit_seconds"]
    head = f"{'link':<{width}} " + " ".join(
        f"{h:>{len(f.format(0) if 'd' in f else f.format(0.0))}}" for h, _, _, f in columns
    )
    rows = [head, "-" * len(head)]

    def cell(m: SphereMetrics, name: str, scale: float, fmt: str) -> str:
        value = getattr(m, name)
        if value is None:
            return " " * len(fmt.format(0.0))
        return fmt.format(value * scale if scale != 1.0 else value)

    def row(name: str, m: SphereMetrics) -> str:
        return f"{name:<{width}} " + " ".join(cell(m, *c[1:]) for c in columns)

    rows += [row(n, m) for n, m in per.items()]
    rows += ["-" * len(head), row("overall", overall)]
    solids = [f"{n}: {m.solid}" for n, m in per.items() if m.solid not in ("mesh", "union")]
    sheets = [f"{n} {m.sheet_thickness * 1000:.2g} mm" for n, m in per.items() if m.sheet_thickness]
    notes = ["lengths in mm", ", ".join(solids)]
    if sheets:
        notes.append(f"sheets (protr.share and vol.ratio only say how thin): {', '.join(sheets)}")
    return "\n".join(rows) + "\n" + "; ".join(n for n in notes if n) + "\n"


def metrics_json(per: dict[str, SphereMetrics], overall: SphereMetrics) -> str:
    """The metrics as one JSON object: ``{"links": {link: metrics}, "overall": metrics}``
    (lengths in metres, as :class:`~xrdf_tools.spheres.SphereMetrics`)."""
    doc = {"links": {n: m.to_dict() for n, m in per.items()}, "overall": overall.to_dict()}
    return json.dumps(doc, indent=2, sort_keys=False) + "\n"
