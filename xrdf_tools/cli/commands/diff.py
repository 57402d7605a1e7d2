"""`xrdf diff`: semantic difference between two XRDF files."""

from __future__ import annotations

import math
from enum import Enum
from pathlib import Path
from typing import Annotated

import typer

from ...util.errors import XrdfToolsError
from .plain import EXIT_FINDINGS, EXIT_OK, load_robot_option
from .typer_common import (
    PackagePathOption,
    QuietOption,
    VerboseOption,
    XacroArgOption,
    fail,
    load_xrdf_input,
    refuse_two_stdin,
    write_output,
)

#: ``xrdf_tools.diff.DEFAULT_TOLERANCE``, repeated so that importing the CLI (every ``xrdf lint``
#: start) does not import the diff engine; a test keeps the two equal.
DEFAULT_TOLERANCE = 1e-9


class DiffFormat(str, Enum):
    text = "text"
    json = "json"


def command(
    a: Annotated[
        Path, typer.Argument(metavar="A.xrdf", help="The 'before' XRDF file ('-': stdin).")
    ],
    b: Annotated[
        Path, typer.Argument(metavar="B.xrdf", help="The 'after' XRDF file ('-': stdin).")
    ],
    fmt: Annotated[
        DiffFormat,
        typer.Option(
            "--format",
            "-f",
            help="text: changes grouped by section; json: stable schema (docs/diff.md).",
        ),
    ] = DiffFormat.text,
    tolerance: Annotated[
        float,
        typer.Option(
            "--tolerance",
            help="Numbers within this absolute distance are equal (metres, radians, limits).",
        ),
    ] = DEFAULT_TOLERANCE,
    urdf: Annotated[
        Path | None,
        typer.Option(
            "--urdf",
            help="The robot's URDF (or xacro): set_base_frame on its root link then counts as "
            "no change.",
        ),
    ] = None,
    xacro_arg: XacroArgOption = None,
    package_path: PackagePathOption = None,
    quiet: QuietOption = False,
    verbose: VerboseOption = False,
) -> None:
    """Semantic difference between two XRDF files (1.0 or 2.0, in any combination).

    Mapping order is ignored; spheres are compared per frame as multisets within the tolerance
    (clones resolved, radius ≤ 0 placeholders left out); ignore pairs as a symmetric set;
    'collision' (1.0) and 'world_collision' (2.0) as one section; c-space and tool-frame order
    matter. Changes are grouped by section with counts.

    \b
    Examples:
      xrdf diff old.xrdf new.xrdf
      xrdf diff robot_1_0.xrdf robot_2_0.xrdf --format json
      xrdf diff a.xrdf b.xrdf --tolerance 1e-6
      xrdf diff a.xrdf b.xrdf --urdf robot.urdf
      xrdf convert robot.urdf --srdf robot.srdf | xrdf diff robot.xrdf -

    Exit codes: 0 identical, 1 different, 2 usage or input error.
    """
    if not (math.isfinite(tolerance) and tolerance >= 0):
        fail(f"--tolerance must be a finite number >= 0, not {tolerance}")
    refuse_two_stdin({"A.xrdf": [a], "B.xrdf": [b]})
    try:
        root, unset = None, None
        if urdf is not None:
            from ...robot.kinematics import build_kinematic_model, unset_defaults
            from ...robot.urdf_source import root_link

            robot = load_robot_option(urdf, xacro_arg, package_path)
            root = root_link(robot)
            unset = unset_defaults(build_kinematic_model(robot, None)[0])
        from ...diff import diff_xrdf

        result = diff_xrdf(
            load_xrdf_input(a),
            load_xrdf_input(b),
            tolerance,
            root_frame=root,
            unset_defaults=unset,
        )
    except XrdfToolsError as exc:
        fail(exc)
    from ...diff.render import RENDERERS

    out = RENDERERS[fmt.value](result)
    write_output(out, None)
    raise typer.Exit(EXIT_OK if result.is_equal else EXIT_FINDINGS)
