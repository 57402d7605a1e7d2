"""`xrdf spheres`: fit collision spheres to a URDF's link geometry and report their quality."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from ...diagnostics import Diagnostic
from ...util.errors import XrdfToolsError
from .common import (
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
    write_output,
)
from .core import EXIT_FINDINGS, OutputFormat, is_stdio, load_robot_option, timed

if TYPE_CHECKING:
    from collections.abc import Callable

    from ...spheres import SphereMetrics
    from .common import ProgressUpdate


def _split_links(values: list[str] | None) -> list[str] | None:
    if not values:
        return None
    out = [v.strip() for item in values for v in item.split(",") if v.strip()]
    return out or None


def metrics_table(per: dict[str, SphereMetrics], overall: SphereMetrics) -> str:
    """Plain-text table: one row per link and an overall row (lengths in millimetres)."""
    head = (
        f"{'link':<24} {'spheres':>7} {'coverage':>9} {'surface':>8} "
        f"{'protr. mean':>11} {'protr. p95':>10}"
    )
    rows = [head, "-" * len(head)]

    def row(name: str, m: SphereMetrics) -> str:
        return (
            f"{name:<24} {m.sphere_count:>7} {m.coverage:>9.3f} {m.surface_coverage:>8.3f} "
            f"{m.protrusion_mean * 1000:>8.1f} mm {m.protrusion_p95 * 1000:>7.1f} mm"
        )

    rows += [row(n, m) for n, m in per.items()]
    rows += ["-" * len(head), row("overall", overall)]
    return "\n".join(rows) + "\n"


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
    fmt: Annotated[
        OutputFormat, typer.Option("--format", help="Diagnostics format (on stderr).")
    ] = OutputFormat.text,
    quiet: QuietOption = False,
    verbose: VerboseOption = False,
) -> None:
    """Fit collision spheres to each link's collision geometry (visual as a fallback).

    Without --xrdf the rest of the XRDF (c-space, defaults) is drafted as `xrdf convert`
    would, and adjacent links are added to the self-collision ignore mask. The metrics table
    goes to stdout with -o FILE, else to stderr (not with -q). Exit 1 when a link's geometry
    could not be read.
    """
    from ...robot.packages import parse_package_path
    from ...spheres import fit_link_spheres, ignore_adjacent, measure_links, merge_spheres
    from ...spheres.geometry import RULE_MESH_UNREADABLE, load_link_geometry
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
        with progress_bar() as bar, timed("fitting"):
            fitted, fdiags = fit_link_spheres(
                model,
                links=link_list,
                per_link=per_link,
                count=count,
                density=density,
                seed=seed,
                package_paths=pkgs,
                max_protrusion=max_protrusion,
                progress=None if bar is None else _per_link(bar),
            )
        diags += fdiags
        merged, mdiags = merge_spheres(base, fitted)
        diags += mdiags
        if xrdf is None:
            merged, adiags = ignore_adjacent(merged, model)
            diags += adiags
        geoms, _ = load_link_geometry(model, links=list(fitted))
        with timed("measuring"):
            per, overall = measure_links(geoms, fitted, samples=10_000, seed=seed)
    except XrdfToolsError as e:
        fail(e)
    text = dump_xrdf(merged)
    echo_diagnostics(diags, fmt)
    table = metrics_table(per, overall)
    write_output(text, output)
    if output is None or is_stdio(output):
        note(table.rstrip("\n"))
    else:
        write_output(table, None)
    if not fitted:
        fail("no link with readable geometry: no spheres fitted", EXIT_FINDINGS)
    if any(d.rule == RULE_MESH_UNREADABLE for d in fdiags):
        raise typer.Exit(EXIT_FINDINGS)


def _per_link(bar: ProgressUpdate) -> Callable[[str, int, int], None]:
    """``progress(link, i, n)`` of :func:`fit_link_spheres` drawn on the common bar."""
    return lambda _link, i, n: bar("fitting spheres (links)", i, n)
