"""``xrdf expand``: a xacro file → the URDF (or SRDF) every other command would read.

Exit codes: 0 written; 2 usage or input error (xacro failure, unresolved package, invalid URDF).
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from ...diagnostics import Diagnostic
from ...util.errors import XrdfToolsError
from .options import output as output_option
from .plain import timed
from .typer_common import (
    PackagePathOption,
    QuietOption,
    VerboseOption,
    XacroArgOption,
    fail,
    refuse_input_overwrite,
    typer_option,
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
        Path | None, typer_option(output_option("the URDF (or the SRDF of an SRDF xacro)"))
    ] = None,
    quiet: QuietOption = False,
    verbose: VerboseOption = False,
) -> None:
    """Expand a xacro file without ROS and write the URDF (checked: it must load).

    `$(find pkg)` and `package://pkg/` resolve through --package-path, then package.xml
    files near the input, exactly as in `xrdf convert`. An SRDF xacro (a MoveIt
    configuration's robot.srdf.xacro: groups and disabled pairs, no links) is written as the
    SRDF `xrdf convert --srdf` reads from it (checked: it must parse).

    \b
    Examples:
      xrdf expand robot.urdf.xacro -o robot.urdf
      xrdf expand px150.urdf.xacro --xacro-arg robot_name:=px150 \\
          --package-path trossen_descriptions=../trossen_descriptions
      xrdf expand wx250s.srdf.xacro --xacro-arg robot_name:=wx250s -o wx250s.srdf
    """
    from ...robot.urdf_source import urdf_text
    from ...robot.xacro_child import XacroBoundError
    from ...robot.xacro_source import is_xacro
    from ...util.fileio import is_file
    from .plain import check_robot_overwrite, load_robot_option

    if output is not None:
        refuse_input_overwrite(output, [robot])
    if is_file(robot) and not is_xacro(robot):
        fail(f"{robot}: not a xacro file (nothing to expand)")
    try:
        with timed("expand"):
            loaded = None
            try:
                loaded = load_robot_option(robot, xacro_arg, package_path)
                text = urdf_text(loaded) or ""
            except XrdfToolsError as not_urdf:
                if isinstance(not_urdf, XacroBoundError):  # an SRDF would not do better
                    raise
                srdf = _expanded_srdf(robot, xacro_arg, package_path)
                if srdf is None:
                    raise not_urdf from None
                text = srdf
        if loaded is not None:  # an included file is an input too
            check_robot_overwrite(output, loaded)
    except XrdfToolsError as e:
        fail(e)
    write_output(text, output)


def _expanded_srdf(
    path: Path, xacro_arg: list[str] | None, package_path: list[str] | None
) -> str | None:
    """The expansion of an SRDF xacro (no ``<link>``; groups, disabled pairs or a virtual
    joint), checked as an SRDF; None when ``path`` does not expand to one."""
    from ...convert.sources.srdf_parse import parse_srdf
    from ...robot.packages import parse_package_paths
    from ...robot.xacro_source import expand_xacro, parse_xacro_arg
    from ...util.safe_xml import XmlSyntaxError, parse_xml, utf8_xml_bytes
    from .plain import echo_warnings, pairs

    said: list[Diagnostic] = []
    text = expand_xacro(
        path,
        pairs(xacro_arg, parse_xacro_arg),
        parse_package_paths(package_path),
        warnings=said,
    )
    try:
        tags = {el.tag for el in parse_xml(utf8_xml_bytes(text), keep_comments=False)}
    except XmlSyntaxError:
        return None
    if "link" in tags or not tags & {"group", "disable_collisions", "virtual_joint"}:
        return None
    parse_srdf(text, str(path), located=False)
    echo_warnings(said)
    return text
