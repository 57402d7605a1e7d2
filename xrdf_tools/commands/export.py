"""``xrdf export curobo|srdf``: XRDF → cuRobo robot YAML, XRDF ignore pairs → MoveIt SRDF."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from ..errors import XrdfToolsError
from .common import OutputFormat, fail, refuse_input_overwrite, render_diagnostics

app = typer.Typer(
    help="Export an XRDF to a cuRobo robot YAML or to MoveIt SRDF disable_collisions.",
    no_args_is_help=True,
    rich_markup_mode=None,
)


def _write(text: str, output: Path | None, inputs: list[Path | None]) -> None:
    if output is None:
        typer.echo(text, nl=False)
        return
    refuse_input_overwrite(output, inputs)
    from ..yaml_io import write_atomic

    try:
        write_atomic(output, text)
    except OSError as e:
        fail(f"{output}: cannot write: {e.strerror or e}")


@app.command("curobo")
def curobo(
    xrdf: Annotated[Path, typer.Argument(help="The XRDF file.", show_default=False)],
    urdf: Annotated[
        Path, typer.Option("--urdf", help="The robot's URDF (or xacro).", show_default=False)
    ],
    layout: Annotated[
        str,
        typer.Option("--layout", help="cuRobo config layout: 2.0 (tool_frames) or classic."),
    ] = "2.0",
    package_path: Annotated[
        list[str] | None,
        typer.Option("--package-path", help="ROS package location NAME=DIR (repeatable)."),
    ] = None,
    xacro_arg: Annotated[
        list[str] | None,
        typer.Option("--xacro-arg", help="xacro argument NAME:=VALUE (repeatable)."),
    ] = None,
    output: Annotated[
        Path | None, typer.Option("-o", "--output", help="Write here instead of stdout.")
    ] = None,
    fmt: Annotated[
        OutputFormat, typer.Option("--format", help="Diagnostics format (on stderr).")
    ] = OutputFormat.text,
) -> None:
    """Write a cuRobo robot YAML (floats, FIXED, lists in c-space order by joint name)."""
    from ..export import CUROBO_LAYOUTS, to_curobo
    from ..packages import parse_package_path
    from ..sources import RobotTree
    from ..sources.xacro_source import load_robot, parse_xacro_arg
    from ..xrdf_io import load_xrdf

    if layout not in CUROBO_LAYOUTS:
        fail(f"--layout must be one of {', '.join(CUROBO_LAYOUTS)}, not '{layout}'")
    try:
        pkgs = dict(parse_package_path(p) for p in package_path or [])
        xargs = dict(parse_xacro_arg(a) for a in xacro_arg or [])
        x = load_xrdf(xrdf)
        robot, _ = load_robot(urdf, xacro_args=xargs, package_paths=pkgs)
        text, diags = to_curobo(x, RobotTree.from_urdf(robot), layout=layout, urdf_path=urdf)
    except XrdfToolsError as e:
        fail(e)
    if diags:
        typer.echo(render_diagnostics(diags, fmt), nl=False, err=True)
    _write(text, output, [xrdf, urdf])


@app.command("srdf")
def srdf(
    xrdf: Annotated[Path, typer.Argument(help="The XRDF file.", show_default=False)],
    merge: Annotated[
        Path | None,
        typer.Option("--merge", help="Existing SRDF to add the pairs to (everything kept)."),
    ] = None,
    robot_name: Annotated[
        str | None, typer.Option("--robot-name", help="<robot name> of a new SRDF.")
    ] = None,
    output: Annotated[
        Path | None, typer.Option("-o", "--output", help="Write here instead of stdout.")
    ] = None,
) -> None:
    """Write self-collision ignore pairs as SRDF disable_collisions (reason "User")."""
    from ..export import to_srdf
    from ..fileio import read_input_bytes
    from ..xrdf_io import load_xrdf

    try:
        x = load_xrdf(xrdf)
        existing = None if merge is None else read_input_bytes(merge, what="SRDF file")
        text = to_srdf(x, robot_name or xrdf.stem.split(".")[0], existing)
    except OSError as e:
        fail(f"{merge}: cannot read: {e.strerror or e}")
    except XrdfToolsError as e:
        fail(e)
    _write(text, output, [xrdf])
