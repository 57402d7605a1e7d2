"""``xrdf expand``: a xacro file → the URDF every other command would read.

Exit codes: 0 written; 2 usage or input error (xacro failure, unresolved package, invalid URDF).
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from ...util.errors import XrdfToolsError
from .plain import timed
from .typer_common import (
    PackagePathOption,
    QuietOption,
    VerboseOption,
    XacroArgOption,
    fail,
    refuse_input_overwrite,
    write_output,
)


def command(
    robot: Annotated[
        Path,
        typer.Argument(
            metavar="ROBOT.urdf.xacro",
            help="The xacro file (it evaluates Python: only expand files you trust).",
            show_default=False,
        ),
    ],
    xacro_arg: XacroArgOption = None,
    package_path: PackagePathOption = None,
    output: Annotated[
        Path | None,
        typer.Option(
            "-o", "--output", help="Write the URDF here (atomically); default or '-': stdout."
        ),
    ] = None,
    quiet: QuietOption = False,
    verbose: VerboseOption = False,
) -> None:
    """Expand a xacro file without ROS and write the URDF (checked: it must load).

    `$(find pkg)` and `package://pkg/` resolve through --package-path, then package.xml
    files near the input, exactly as in `xrdf convert`.

    \b
    Examples:
      xrdf expand robot.urdf.xacro -o robot.urdf
      xrdf expand px150.urdf.xacro --xacro-arg robot_name:=px150 \\
          --package-path trossen_descriptions=../trossen_descriptions
    """
    from ...robot.urdf_source import urdf_text
    from ...robot.xacro_source import is_xacro
    from .plain import load_robot_option

    if output is not None:
        refuse_input_overwrite(output, [robot])
    if robot.is_file() and not is_xacro(robot):
        fail(f"{robot}: not a xacro file (nothing to expand)")
    try:
        with timed("expand"):
            text = urdf_text(load_robot_option(robot, xacro_arg, package_path)) or ""
    except XrdfToolsError as e:
        fail(e)
    write_output(text, output)
