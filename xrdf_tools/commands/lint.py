"""`xrdf lint`: check XRDF files against the spec, a URDF, and cuRobo's loader."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

import typer

from .common import (
    EXIT_FINDINGS,
    OutputFormat,
    PackagePathOption,
    QuietOption,
    VerboseOption,
    XacroArgOption,
    detail,
    fail,
    has_failures,
    is_stdio,
    load_robot_option,
    refuse_two_stdin,
    render_diagnostics,
    timed,
)


def _robot_or_why_not(
    urdf: Path, xacro_arg: list[str] | None, package_path: list[str] | None
) -> Any:
    """The ``--urdf`` robot, or the :class:`UrdfError` that says why it is not a valid robot
    (lint reports that as ``urdf-invalid``, exit 1); a file that cannot be read raises."""
    from ..errors import UrdfError, UrdfReadError

    try:
        return load_robot_option(urdf, xacro_arg, package_path)
    except UrdfReadError:
        raise
    except UrdfError as exc:
        return exc


def _split(values: list[str] | None) -> list[str]:
    return [v.strip() for item in values or [] for v in item.split(",") if v.strip()]


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
    quiet: QuietOption = False,
    verbose: VerboseOption = False,
) -> None:
    """Check XRDF files; report problems as path:line:col: severity rule-id message.

    Exit codes: 0 clean, 1 errors (or warnings with --strict), 2 usage or input error.
    """
    from ..errors import XrdfToolsError
    from ..lint import RULES, lint
    from ..lint.config import discover_config, load_config

    refuse_two_stdin({"FILES": files})
    try:
        cfg = load_config(config) if config is not None else discover_config()
        detail(f"configuration: {cfg.source or 'none (defaults)'}")
        model = None
        if urdf is not None:
            model = _robot_or_why_not(urdf, xacro_arg, package_path)
        elif xacro_arg or package_path:
            fail("--xacro-arg and --package-path apply to --urdf; give --urdf")
        with timed("lint"):
            diagnostics = lint(
                files,
                urdf=urdf,
                config=cfg,
                select=_split(select),
                ignore=_split(ignore),
                target=target,
                urdf_model=model,
            )
    except XrdfToolsError as exc:
        fail(exc)
    text = render_diagnostics(
        diagnostics,
        output_format,
        files=["<stdin>" if is_stdio(f) else str(f) for f in files],
        rules=[(r.id, r.summary, r.severity) for r in RULES],
    )
    if text:
        typer.echo(text, nl=False)
    if has_failures(diagnostics, strict=strict):
        raise typer.Exit(EXIT_FINDINGS)
