"""`xrdf lint`: check XRDF files against the spec, a URDF, and cuRobo's loader.

The options are read here; what the command does is :func:`xrdf_tools.cli.commands.lint_core.run`,
which the fast start-up path of ``xrdf lint`` runs too (without typer).
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from .common import (
    AllowMissingMeshesOption,
    PackagePathOption,
    QuietOption,
    VerboseOption,
    XacroArgOption,
    fail,
    write_output,
)
from .core import OutputFormat


def command(
    files: Annotated[
        list[Path],
        typer.Argument(help="XRDF files to check ('-': stdin).", show_default=False),
    ],
    urdf: Annotated[
        Path | None,
        typer.Option(
            "--urdf",
            help="URDF (or xacro) the files describe: enables frame, joint, limit and "
            "collision checks.",
        ),
    ] = None,
    xacro_arg: XacroArgOption = None,
    package_path: PackagePathOption = None,
    output_format: Annotated[
        OutputFormat, typer.Option("--format", "-f", help="Output format.")
    ] = OutputFormat.text,
    select: Annotated[
        list[str] | None,
        typer.Option("--select", help="Only these rules (ids or prefixes like 'curobo-')."),
    ] = None,
    ignore: Annotated[
        list[str] | None,
        typer.Option("--ignore", help="Skip these rules (ids or prefixes like 'curobo-')."),
    ] = None,
    target: Annotated[
        str | None,
        typer.Option(
            "--target",
            help="The program that will load the files: curobo (cuRobo, Isaac ROS cuMotion), "
            "cumotion (cuMotion library) or isaac-sim. That reader's silent failures become "
            "errors; other readers' checks are off. Default: the configuration's 'target'.",
            show_default=False,
        ),
    ] = None,
    strict: Annotated[
        bool, typer.Option("--strict", help="Exit 1 on warnings too, not only errors.")
    ] = False,
    config: Annotated[
        Path | None,
        typer.Option(
            "--config",
            help="Configuration file (.xrdf-lint.yaml or pyproject.toml). Default: the first "
            ".xrdf-lint.yaml or [tool.xrdf.lint] from the current directory upwards.",
        ),
    ] = None,
    allow_missing_meshes: AllowMissingMeshesOption = False,
    quiet: QuietOption = False,
    verbose: VerboseOption = False,
) -> None:
    """Check XRDF files; report problems as path:line:col: severity rule-id message.

    Exit codes: 0 clean, 1 errors (or warnings with --strict), 2 usage or input error.
    With --urdf, collision meshes that cannot be found or read are warnings (the check that
    needs them is skipped); --allow-missing-meshes makes the ones not found an info.
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
