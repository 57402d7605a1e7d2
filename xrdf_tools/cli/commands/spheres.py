"""`xrdf spheres`: fit collision spheres to a URDF's link geometry and report their quality.

The options are read here; the fit, the merge and the metrics are
:mod:`xrdf_tools.convert.spheres_job`'s.
"""

from __future__ import annotations

from enum import Enum
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

import typer

from ...util.errors import XrdfToolsError
from .options import output as output_option
from .options import seed as seed_option
from .plain import (
    EXIT_FINDINGS,
    OutputFormat,
    check_robot_overwrite,
    detail,
    is_stdio,
    load_robot_option,
    timed,
)
from .typer_common import (
    AllowMissingMeshesOption,
    PackagePathOption,
    QuietOption,
    VerboseOption,
    XacroArgOption,
    echo_diagnostics,
    fail,
    finite,
    load_xrdf_input,
    note,
    progress_bar,
    refuse_input_overwrite,
    stderr_is_terminal,
    typer_option,
    write_output,
)

if TYPE_CHECKING:
    from collections.abc import Callable

    from .typer_common import ProgressUpdate


class FitMethod(str, Enum):
    ours = "ours"
    morphit = "morphit"


class VisualCheck(str, Enum):
    """``--visual-check`` (:data:`xrdf_tools.spheres.visual_agreement.VisualCheck`)."""

    fast = "fast"
    all = "all"
    off = "off"


class GeometryFrom(str, Enum):
    """``--from``: which of a link's geometry spheres are fitted to."""

    collision = "collision"
    visual = "visual"
    auto = "auto"


def geometry_from_option(when: str = "") -> Any:
    """``--from`` of ``xrdf spheres`` and ``xrdf convert --fit-spheres``."""
    return typer.Option(
        "--from",
        case_sensitive=False,
        help=(f"{when}: fit" if when else "Fit")
        + " to collision geometry (links with visual geometry only get no spheres), visual "
        "geometry, or auto (collision, else visual).",
    )


def visual_check_option(when: str = "") -> Any:
    """``--visual-check`` of ``xrdf spheres`` and ``xrdf convert --fit-spheres``."""
    return typer.Option(
        "--visual-check",
        case_sensitive=False,
        help=(f"{when}: is" if when else "Is")
        + " each link's collision geometry where its visual geometry is (a warning when the "
        "boxes clearly disagree, naming the quarter turn that would match them)? fast "
        "(default): visual STL/OBJ/COLLADA/GLB meshes and primitives are read without trimesh, "
        "other formats (and a COLLADA or GLB file its reader gives up on) are counted in one "
        "note; "
        "all: those too, through trimesh (about 25 ms a file); off: no check.",
    )


def fit_method_help(counts: str, coverage: str, enforced: str, when: str = "") -> str:
    """The help of ``--method`` (``xrdf spheres`` and ``xrdf convert --fit-spheres``):
    ``counts``, the options that set the per-link counts; ``coverage``, what the default count
    covers; ``enforced``, the bounds MorphIt's spheres are shrunk to; ``when``, the option it
    applies with."""
    return (f"{when}: who" if when else "Who") + (
        " fits each link's solid. ours (default): greedy cover, then refined "
        "(docs/spheres.md). morphit: MorphIt (cuRobo v2's fitter, preset MorphIt-B) at the same "
        f"per-link counts ({counts}, else the count ours needs to cover {coverage}), seeded "
        f"alike (same inputs, same bytes); {enforced} by shrinking its spheres. Needs "
        'pip install "xrdf-tools[morphit]".'
    )


def _split_links(values: list[str] | None) -> list[str] | None:
    if not values:
        return None
    out = [v.strip() for item in values for v in item.split(",") if v.strip()]
    return out or None


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
        int | None,
        typer.Option(
            "--count",
            help="Total number of spheres over all links (at least 1 per link). Default: per "
            "link, the fewest that reach --target-coverage.",
        ),
    ] = None,
    per_link: Annotated[
        int | None,
        typer.Option(
            "--per-link",
            help="Number of spheres for each link, 1 to 64. Default: per link, the fewest that "
            "reach --target-coverage.",
        ),
    ] = None,
    density: Annotated[
        float | None,
        typer.Option(
            "--density",
            callback=finite,
            help="Spheres per litre of link volume (1 to 64 per link). Default: per link, the "
            "fewest that reach --target-coverage.",
        ),
    ] = None,
    max_protrusion: Annotated[
        float | None,
        typer.Option(
            "--max-protrusion",
            callback=finite,
            min=0.0,
            help="How far (m) a sphere may reach outside its link: a hard bound on every "
            "sphere. Without it: 6 % of the cube root of the link volume when the count is "
            "chosen per link; with --count/--per-link/--density the spheres are refined "
            "instead, trading coverage against the 95th percentile of their protrusion.",
        ),
    ] = None,
    target_coverage: Annotated[
        float,
        typer.Option(
            "--target-coverage",
            callback=finite,
            min=0.01,
            max=1.0,
            help="Without --count/--per-link/--density: per link, the fewest spheres (up to "
            "16) that cover this share of its volume within --max-protrusion. A link the "
            "default bound cannot cover so (a thin disc) gets its 16 refined past that bound; "
            "a sheet (a marker plate) gets a few spheres holding all of it.",
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
    seed: Annotated[int, typer_option(seed_option("the fit"))] = 0,
    method: Annotated[
        FitMethod,
        typer.Option(
            "--method",
            case_sensitive=False,
            help=fit_method_help(
                "--count/--per-link/--density",
                "--target-coverage",
                "--clip and --max-protrusion are enforced",
            ),
        ),
    ] = FitMethod.ours,
    geometry_from: Annotated[GeometryFrom, geometry_from_option()] = GeometryFrom.auto,
    visual_check: Annotated[VisualCheck, visual_check_option()] = VisualCheck.fast,
    output: Annotated[Path | None, typer_option(output_option("the XRDF"))] = None,
    package_path: PackagePathOption = None,
    xacro_arg: XacroArgOption = None,
    allow_missing_meshes: AllowMissingMeshesOption = False,
    fmt: Annotated[
        OutputFormat,
        typer.Option(
            "--format",
            "-f",
            help="Format of the diagnostics (text, json, github or sarif) and of the metrics "
            "(json: one object, lengths in metres).",
        ),
    ] = OutputFormat.text,
    timings: Annotated[
        bool,
        typer.Option(
            "--timings",
            help="Add each link's fit time (wall seconds) to the metrics. Without it the "
            "metrics, like the XRDF, are the same bytes for the same inputs and options.",
        ),
    ] = False,
    quiet: QuietOption = False,
    verbose: VerboseOption = False,
) -> None:
    """Fit collision spheres to each link's collision geometry (visual as a fallback: --from).

    Without --xrdf the rest of the XRDF (c-space, defaults) is drafted as `xrdf convert`
    would, and adjacent links are added to the self-collision ignore mask. The metrics table
    goes to stdout with -o FILE, else to stderr (not with -q). Every link with geometry
    gets spheres, or the command fails (exit 1, nothing written) naming each link and why; a
    mesh file that cannot be found is an input error (exit 2) unless --allow-missing-meshes.

    \b
    Examples:
      xrdf spheres robot.urdf -o robot.xrdf
      xrdf spheres robot.urdf --xrdf robot.xrdf --links gripper_link --per-link 6 -o robot2.xrdf
      xrdf spheres robot.urdf --count 60 --clip base_link:0,0,1,0 -o robot.xrdf
    """
    from ...convert.spheres_job import (
        SpheresRequest,
        fit_metrics,
        fit_spheres,
        metrics_json,
        metrics_table,
    )
    from ...robot.packages import parse_package_paths
    from ...spheres.count_policy import CountPolicy
    from ...spheres.morphit import check_method
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
    try:
        check_method(method.value)
        request = SpheresRequest(
            CountPolicy(per_link, count, density, target_coverage),
            links=_split_links(links),
            seed=seed,
            package_paths=parse_package_paths(package_path),
            max_protrusion=max_protrusion,
            clips=clip or (),
            allow_missing_meshes=allow_missing_meshes,
            method=method.value,
            visual_check=visual_check.value,
            source=geometry_from.value,
        )
        model = load_robot_option(robot, xacro_arg, package_path)
        check_robot_overwrite(output, model)
        base = load_xrdf_input(xrdf) if xrdf is not None else None
        with progress_bar() as bar, timed("fitting"):
            fitted = fit_spheres(
                model,
                base,
                request,
                progress=per_link_progress(bar, "fitting spheres"),
                reading=per_link_progress(bar, "reading link geometry", steps=1),
            )
        with timed("measuring"):
            per, overall = fit_metrics(fitted.fit, seed, timings=timings)
    except XrdfToolsError as e:
        fail(e)
    echo_diagnostics([*fitted.diagnostics, *fitted.unfitted], fmt)
    if fitted.unfitted:
        fail(
            f"{len(fitted.unfitted)} link(s) with geometry got no spheres or only some (listed "
            "above); nothing written. Fix or replace those meshes",
            EXIT_FINDINGS,
        )
    if not fitted.fit.spheres:
        fail("no link with readable geometry: no spheres fitted", EXIT_FINDINGS)
    table = metrics_json(per, overall) if fmt is OutputFormat.json else metrics_table(per, overall)
    write_output(dump_xrdf(fitted.xrdf), output)
    if output is None or is_stdio(output):
        note(table.rstrip("\n"))
    else:
        write_output(table, None)


def per_link_progress(
    bar: ProgressUpdate | None, label: str, steps: int = 2
) -> Callable[[str, int, int], None]:
    """``progress(link, i, n)``: drawn on the common bar on a terminal; with ``-v`` elsewhere
    (CI logs), one line per step on stderr (``steps`` per link: read; prepared, then
    fitted)."""

    def update(link: str, i: int, n: int) -> None:
        if bar is not None:
            bar(f"{label} (2 steps a link)" if steps == 2 else label, i, n)
        elif not stderr_is_terminal():
            detail(f"{label}: {i + 1}/{n} {link}")

    return update
