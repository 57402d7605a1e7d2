"""`xrdf spheres`: fit collision spheres to a URDF's link geometry and report their quality."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from ...diagnostics import Diagnostic
from ...util.errors import XrdfToolsError
from .common import (
    AllowMissingMeshesOption,
    PackagePathOption,
    QuietOption,
    VerboseOption,
    XacroArgOption,
    echo_diagnostics,
    fail,
    load_xrdf_input,
    note,
    progress_bar,
    refuse_input_overwrite,
    stderr_is_terminal,
    write_output,
)
from .core import EXIT_FINDINGS, OutputFormat, detail, is_stdio, load_robot_option, timed

if TYPE_CHECKING:
    from collections.abc import Callable

    from ...spheres import SphereMetrics
    from ...spheres.fit import Plane
    from .common import ProgressUpdate


def _split_links(values: list[str] | None) -> list[str] | None:
    if not values:
        return None
    out = [v.strip() for item in values for v in item.split(",") if v.strip()]
    return out or None


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
    head = f"{'link':<{width}} " + " ".join(
        f"{h:>{len(f.format(0) if 'd' in f else f.format(0.0))}}" for h, _, _, f in _COLUMNS
    )
    rows = [head, "-" * len(head)]

    def cell(m: SphereMetrics, name: str, scale: float, fmt: str) -> str:
        value = getattr(m, name)
        if value is None:
            return " " * len(fmt.format(0.0))
        return fmt.format(value * scale if scale != 1.0 else value)

    def row(name: str, m: SphereMetrics) -> str:
        return f"{name:<{width}} " + " ".join(cell(m, *c[1:]) for c in _COLUMNS)

    rows += [row(n, m) for n, m in per.items()]
    rows += ["-" * len(head), row("overall", overall)]
    notes = "lengths in mm; " + ", ".join(
        f"{n}: {m.solid}" for n, m in per.items() if m.solid not in ("mesh", "union")
    )
    return "\n".join(rows) + "\n" + notes.rstrip("; ") + "\n"


def metrics_json(per: dict[str, SphereMetrics], overall: SphereMetrics) -> str:
    """The metrics as one JSON object: ``{"links": {link: metrics}, "overall": metrics}``
    (lengths in metres, as :class:`~xrdf_tools.spheres.SphereMetrics`)."""
    import json

    doc = {"links": {n: m.to_dict() for n, m in per.items()}, "overall": overall.to_dict()}
    return json.dumps(doc, indent=2, sort_keys=False) + "\n"


def command(
    robot: Annotated[
        Path,
        typer.Argument(metavar="ROBOT.urdf|xacro", help="URDF or xacro file.", show_default=False),
    ],
    xrdf: Annotated[
        Path | None,
        typer.Option(
            "--xrdf",
            help="Existing XRDF to merge into (only the fitted links' spheres are replaced; "
            "'-': stdin).",
        ),
    ] = None,
    links: Annotated[
        list[str] | None,
        typer.Option("--links", help="Links to fit (repeatable or comma-separated; default: all)."),
    ] = None,
    count: Annotated[
        int | None, typer.Option("--count", help="Total number of spheres over all links.")
    ] = None,
    per_link: Annotated[
        int | None, typer.Option("--per-link", help="Number of spheres for each link.")
    ] = None,
    density: Annotated[
        float | None,
        typer.Option("--density", help="Spheres per litre of link volume (at least 1 per link)."),
    ] = None,
    max_protrusion: Annotated[
        float | None,
        typer.Option(
            "--max-protrusion",
            help="How far (m) a sphere may reach outside its link "
            "(default: 6 % of the cube root of the link volume).",
        ),
    ] = None,
    target_coverage: Annotated[
        float,
        typer.Option(
            "--target-coverage",
            min=0.01,
            max=1.0,
            help="Without --count/--per-link/--density: per link, the fewest spheres (up to "
            "16) that cover this share of its volume within --max-protrusion.",
        ),
    ] = 0.9,
    clip: Annotated[
        list[str] | None,
        typer.Option(
            "--clip",
            help="LINK:nx,ny,nz,d keeps LINK's spheres on the side of the plane n.x = d that "
            "n points to (link frame, metres; e.g. base_link:0,0,1,0 keeps a base's spheres "
            "above its z = 0 floor). Repeatable.",
        ),
    ] = None,
    seed: Annotated[
        int, typer.Option("--seed", min=0, help="Random seed (same seed, same spheres).")
    ] = 0,
    output: Annotated[
        Path | None,
        typer.Option(
            "-o",
            "--output",
            help="Write the XRDF here (atomically) instead of stdout ('-': stdout).",
        ),
    ] = None,
    package_path: PackagePathOption = None,
    xacro_arg: XacroArgOption = None,
    allow_missing_meshes: AllowMissingMeshesOption = False,
    fmt: Annotated[
        OutputFormat,
        typer.Option(
            "--format",
            help="Format of the diagnostics and of the metrics (json: one object, lengths "
            "in metres).",
        ),
    ] = OutputFormat.text,
    quiet: QuietOption = False,
    verbose: VerboseOption = False,
) -> None:
    """Fit collision spheres to each link's collision geometry (visual as a fallback).

    Without --xrdf the rest of the XRDF (c-space, defaults) is drafted as `xrdf convert`
    would, and adjacent links are added to the self-collision ignore mask. The metrics table
    goes to stdout with -o FILE, else to stderr (not with -q). Every link with geometry
    gets spheres, or the command fails (exit 1, nothing written) naming each link and why; a
    mesh file that cannot be found is an input error (exit 2) unless --allow-missing-meshes.
    """
    from ...convert.fit_check import unfitted_links
    from ...convert.pipeline import geometry_links
    from ...robot.link_geometry import require_meshes
    from ...robot.packages import parse_package_path
    from ...spheres import ignore_adjacent, measure_links, merge_spheres
    from ...spheres.robot_fit import CountPolicy, fit_robot, parse_clip
    from ...xrdf.io import dump_xrdf

    chosen = [
        n
        for n, v in (("--count", count), ("--per-link", per_link), ("--density", density))
        if v is not None
    ]
    if len(chosen) > 1:
        fail(f"give only one of --count, --per-link and --density (got {', '.join(chosen)})")
    if output is not None:
        refuse_input_overwrite(output, [robot, xrdf])
    link_list = _split_links(links)
    diags: list[Diagnostic] = []
    try:
        pkgs = dict(parse_package_path(p) for p in (package_path or []))
        model = load_robot_option(robot, xacro_arg, package_path)
        if xrdf is not None:
            base = load_xrdf_input(xrdf)
        else:
            from ...convert.core import ConvertOptions, convert

            base, cdiags = convert(model, ConvertOptions())
            diags += [d for d in cdiags if d.rule != "convert-no-spheres"]
        wanted = [n for n in geometry_links(model, "auto")[0] if n in (link_list or [n])]
        missing = require_meshes(
            model, "auto", links=wanted, package_paths=pkgs, allow_missing=allow_missing_meshes
        )
        clips: dict[str, list[Plane]] = {}
        for text in clip or []:
            link, plane = parse_clip(text)
            clips.setdefault(link, []).append(plane)
        with progress_bar() as bar, timed("fitting"):
            result = fit_robot(
                model,
                links=link_list,
                counts=CountPolicy(per_link, count, density, target_coverage),
                seed=seed,
                package_paths=pkgs,
                max_protrusion=max_protrusion,
                clips=clips,
                progress=per_link_progress(bar, "fitting spheres"),
            )
        fitted, fdiags = result.spheres, result.diagnostics
        diags += fdiags
        merged, mdiags = merge_spheres(base, fitted)
        diags += mdiags
        if xrdf is None:
            merged, adiags = ignore_adjacent(merged, model)
            diags += adiags
        with timed("measuring"):
            per, overall = measure_links(result.geometry, fitted, samples=10_000, seed=seed)
        per = {n: replace(m, fit_seconds=round(result.seconds[n], 3)) for n, m in per.items()}
        overall = replace(overall, fit_seconds=round(sum(result.seconds.values()), 3))
    except XrdfToolsError as e:
        fail(e)
    text = dump_xrdf(merged)
    unfitted = unfitted_links(
        model.path, wanted, fitted, fdiags, allowed_missing=missing, lines=model.link_lines
    )
    echo_diagnostics([*diags, *unfitted], fmt)
    if unfitted:
        fail(
            f"{len(unfitted)} link(s) with geometry got no spheres or only some (listed "
            "above); nothing written. Fix or replace those meshes",
            EXIT_FINDINGS,
        )
    if not fitted:
        fail("no link with readable geometry: no spheres fitted", EXIT_FINDINGS)
    table = metrics_json(per, overall) if fmt is OutputFormat.json else metrics_table(per, overall)
    write_output(text, output)
    if output is None or is_stdio(output):
        note(table.rstrip("\n"))
    else:
        write_output(table, None)


def per_link_progress(bar: ProgressUpdate | None, label: str) -> Callable[[str, int, int], None]:
    """``progress(link, i, n)``: drawn on the common bar on a terminal; with ``-v`` elsewhere
    (CI logs), one line per link on stderr."""

    def update(link: str, i: int, n: int) -> None:
        if bar is not None:
            bar(f"{label} (links)", i, n)
        elif not stderr_is_terminal():
            detail(f"{label}: {i + 1}/{n} {link}")

    return update
