"""Helpers shared by the CLI commands: error exits, diagnostic output, safe writes."""

from __future__ import annotations

import os
import sys
from collections.abc import Mapping, Sequence
from enum import Enum
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, NoReturn

import typer

from ..diagnostics import (
    Diagnostic,
    Severity,
    render_github,
    render_json,
    render_text,
)
from ..errors import XrdfToolsError

if TYPE_CHECKING:
    import yourdfpy


class OutputFormat(str, Enum):
    text = "text"
    json = "json"
    github = "github"
    sarif = "sarif"


EXIT_OK = 0
EXIT_FINDINGS = 1
EXIT_USAGE = 2


def fail(message: str | XrdfToolsError, code: int = EXIT_USAGE) -> NoReturn:
    """Print a one-line error to stderr and exit (2 by default: usage/input error)."""
    typer.echo(f"error: {message}", err=True)
    raise typer.Exit(code)


def not_implemented(name: str) -> NoReturn:
    typer.echo(f"error: 'xrdf {name}' is not implemented yet", err=True)
    raise typer.Exit(EXIT_USAGE)


def render_diagnostics(
    diagnostics: Sequence[Diagnostic],
    fmt: OutputFormat,
    *,
    files: Sequence[str] | None = None,
    rules: Sequence[tuple[str, str, Severity]] = (),
) -> str:
    """The one renderer dispatch of every command. ``files`` (JSON) lists the inputs checked;
    ``rules`` (SARIF) are listed even without results."""
    if fmt is OutputFormat.json:
        return render_json(diagnostics, **({"files": list(files)} if files is not None else {}))
    if fmt is OutputFormat.github:
        return render_github(diagnostics)
    if fmt is OutputFormat.sarif:
        from .. import __version__
        from ..diagnostics import render_sarif
        from ..rule_registry import rule_info

        listed = {r[0] for r in rules}
        described = list(rules)
        for rid in dict.fromkeys(d.rule for d in diagnostics):
            info = rule_info(rid)
            if rid not in listed and info is not None:
                described.append((rid, info.summary, info.severity))
        return render_sarif(diagnostics, described, version=__version__)
    return render_text(diagnostics)


def has_failures(diagnostics: Sequence[Diagnostic], *, strict: bool) -> bool:
    worst = {Severity.ERROR} | ({Severity.WARNING} if strict else set())
    return any(d.severity in worst for d in diagnostics)


def same_file(a: str | os.PathLike[str], b: str | os.PathLike[str]) -> bool:
    try:
        return Path(a).resolve() == Path(b).resolve() or (
            Path(a).exists() and Path(b).exists() and os.path.samefile(a, b)
        )
    except OSError:
        return False


def refuse_input_overwrite(output: Path, inputs: Sequence[Path | str | None]) -> None:
    """Exit with an error when ``output`` names one of the inputs (nothing is ever lost), or
    cannot be an output at all (a directory, device, FIFO or socket; symlinks are fine)."""
    from ..fileio import check_output_path

    for src in inputs:
        if src is not None and same_file(output, src):
            fail(f"{output}: refusing to overwrite an input file; choose another -o path")
    try:
        check_output_path(output)
    except XrdfToolsError as e:
        fail(e)


def refuse_output_clash(outputs: Mapping[str, Path | None]) -> None:
    """Exit with an error when two output options (``{"--plot": path, ...}``) name the same
    file: one would silently replace the other."""
    seen: list[tuple[str, Path]] = []
    for option, path in outputs.items():
        if path is None:
            continue
        for other, earlier in seen:
            if same_file(path, earlier):
                fail(f"{path}: given for both {other} and {option}; choose different paths")
        seen.append((option, path))


def stdout_is_terminal() -> bool:
    return sys.stdout.isatty()


#: ``--xacro-arg`` / ``--package-path`` of every command reading a robot (same as ``convert``).
XacroArgOption = Annotated[
    list[str] | None,
    typer.Option(
        "--xacro-arg", help="xacro argument NAME:=VALUE when the robot is a xacro (repeatable)."
    ),
]
PackagePathOption = Annotated[
    list[str] | None,
    typer.Option("--package-path", help="ROS package location NAME=DIR (repeatable)."),
]


def pairs(values: list[str] | None, parse: Any) -> dict[str, str]:
    """``--package-path``/``--xacro-arg`` values as a mapping (the last one wins)."""
    return dict(parse(v) for v in values or [])


def load_robot_option(
    path: Path, xacro_arg: list[str] | None, package_path: list[str] | None
) -> yourdfpy.URDF:
    """The robot of ``--urdf``: a URDF, or a xacro expanded with ``--xacro-arg`` and
    ``--package-path`` like ``xrdf convert`` does (one loader for every command).

    Raises :class:`XrdfToolsError` (the caller exits 2).
    """
    from ..packages import parse_package_path
    from ..sources.xacro_source import load_robot, parse_xacro_arg

    urdf, _ = load_robot(
        path,
        xacro_args=pairs(xacro_arg, parse_xacro_arg),
        package_paths=pairs(package_path, parse_package_path),
    )
    return urdf
