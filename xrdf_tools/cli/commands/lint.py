"""`xrdf lint`: check XRDF files against the spec, a URDF, and cuRobo's loader.

The options come from :data:`xrdf_tools.cli.commands.lint_core.LINT_OPTIONS`, and what the
command does is :func:`xrdf_tools.cli.commands.lint_core.run`: the fast start-up path of
``xrdf lint`` reads the same table and runs the same function (without typer).
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

import typer

from .lint_core import LINT_OPTIONS
from .plain import OutputFormat
from .typer_common import (
    PackagePathOption,
    QuietOption,
    VerboseOption,
    XacroArgOption,
    fail,
    typer_option,
    write_output,
)


def _option(name: str) -> Any:
    return typer_option(LINT_OPTIONS[name])


def command(
    files: Annotated[
        list[Path],
        typer.Argument(
            metavar="FILE.xrdf...", help="XRDF files to check ('-': stdin).", show_default=False
        ),
    ],
    urdf: Annotated[Path | None, _option("urdf")] = None,
    xacro_arg: XacroArgOption = None,
    package_path: PackagePathOption = None,
    output_format: Annotated[OutputFormat, _option("output_format")] = OutputFormat.text,
    select: Annotated[list[str] | None, _option("select")] = None,
    ignore: Annotated[list[str] | None, _option("ignore")] = None,
    target: Annotated[str | None, _option("target")] = None,
    strict: Annotated[bool, _option("strict")] = False,
    config: Annotated[Path | None, _option("config")] = None,
    allow_missing_meshes: Annotated[bool, _option("allow_missing_meshes")] = False,
    quiet: QuietOption = False,
    verbose: VerboseOption = False,
) -> None:
    """Check XRDF files; report problems as path:line:col: severity rule-id message.

    Exit codes: 0 clean, 1 errors (or warnings with --strict), 2 usage or input error.
    With --urdf, collision meshes that cannot be found or read are warnings (the check that
    needs them is skipped); --allow-missing-meshes makes the ones not found an info.

    \b
    Examples:
      xrdf lint robot.xrdf --urdf robot.urdf --target curobo
      xrdf lint robots/*.xrdf --format github
      xrdf convert robot.urdf --srdf robot.srdf -q | xrdf lint - --urdf robot.urdf
    """
    from ...util.errors import XrdfToolsError
    from .lint_core import LintArgs, run

    args = LintArgs(
        files,
        urdf,
        xacro_arg,
        package_path,
        output_format,
        select,
        ignore,
        target,
        strict,
        config,
        allow_missing_meshes,
    )
    try:
        text, code = run(args)
    except XrdfToolsError as exc:
        fail(exc)
    if text:
        write_output(text, None)
    if code:
        raise typer.Exit(code)
