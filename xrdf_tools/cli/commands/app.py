"""The ``xrdf`` Typer app: a thin layer over the library.

Each subcommand lives in ``xrdf_tools.cli.commands.<name>``; this module wires them together and
handles ``--version``. The console entry point is :func:`xrdf_tools.cli.main` (which also
turns library exceptions into one-line errors with exit code 2); ``xrdf_tools.cli.app`` is
this app.
"""

from __future__ import annotations

from typing import Annotated

import typer

from ... import __version__
from . import convert, diff, edit, expand, export, inspect, lint, report, spheres, viz

app = typer.Typer(
    name="xrdf",
    help=(
        "Tools for XRDF robot descriptions (cuMotion / cuRobo / MoveIt).\n\n"
        "Typical flow: inspect a URDF (+ SRDF), convert it (with an SRDF or a cuRobo config) to "
        "XRDF, lint it, report on its self-collision mask, look at the spheres.\n\n"
        "Exit codes: 0 success, 1 findings (lint errors, differences), 2 usage or input error."
    ),
    no_args_is_help=True,
    add_completion=True,
    pretty_exceptions_enable=False,
    rich_markup_mode=None,
)


def _version(value: bool) -> None:
    if value:
        typer.echo(f"xrdf-tools {__version__}")
        raise typer.Exit()


@app.callback()
def _root(
    version: Annotated[
        bool,
        typer.Option("--version", callback=_version, is_eager=True, help="Show the version."),
    ] = False,
) -> None:
    """Tools for XRDF robot descriptions."""


# short_help is the one-line summary in `xrdf --help`; each command's docstring (with examples)
# is its full `xrdf COMMAND --help`.
app.command("convert", short_help="URDF/xacro + MoveIt SRDF or cuRobo config → XRDF.")(
    convert.command
)
app.command("inspect", short_help="Links, joints, chains, SRDF groups and the default c-space.")(
    inspect.command
)
app.command("lint", short_help="Check XRDF files against the spec (and a URDF).")(lint.command)
app.command("diff", short_help="Semantic difference between two XRDF files.")(diff.command)
app.command("report", short_help="Self-collision report over sampled configurations.")(
    report.command
)
app.command("viz", short_help="Sphere visualizations to rerun (.rrd), MCAP or PNG.")(viz.command)
app.command("spheres", short_help="Fit collision spheres to link meshes; coverage metrics.")(
    spheres.command
)
app.command("edit", short_help="Edit spheres, mask and defaults in the browser (viser).")(
    edit.command
)
app.command("expand", short_help="xacro → URDF, without ROS (as every command reads it).")(
    expand.command
)
app.add_typer(
    export.app,
    name="export",
    help="XRDF → cuRobo robot YAML, a MoveIt SRDF sync, or an XRDF for a reader (--target).",
)
