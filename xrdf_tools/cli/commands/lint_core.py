"""The body of ``xrdf lint``, without typer, and its fast start-up path.

:func:`run` is what ``xrdf lint`` does once its arguments are read. The Typer command
(:mod:`xrdf_tools.cli.commands.lint`) calls it, and so does :func:`fast_main`: ``xrdf lint`` is
run once per commit by the pre-commit hook and must start as fast as yamllint, and typer's
own start-up (click, pydantic, every command's options) costs several times that.
:func:`parse_fast` reads the arguments a user normally gives; whatever it does not fully
understand (``--help``, ``-v``, a usage error, shell completion) is left to the Typer app,
so help, usage errors and every message stay typer's.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from .core import (
    EXIT_FINDINGS,
    EXIT_OK,
    EXIT_USAGE,
    OutputFormat,
    detail,
    echo,
    has_failures,
    is_stdio,
    load_robot_option,
    render_diagnostics,
    timed,
    two_stdin,
)

if TYPE_CHECKING:
    from ...robot.core import Robot
    from ...util.errors import XrdfToolsError


@dataclass(frozen=True)
class LintArgs:
    """The arguments of ``xrdf lint`` (as the Typer command receives them)."""

    files: Sequence[Path]
    urdf: Path | None = None
    xacro_arg: list[str] | None = None
    package_path: list[str] | None = None
    output_format: OutputFormat = OutputFormat.text
    select: list[str] | None = None
    ignore: list[str] | None = None
    target: str | None = None
    strict: bool = False
    config: Path | None = None
    allow_missing_meshes: bool = False


def _robot_or_why_not(
    urdf: Path, xacro_arg: list[str] | None, package_path: list[str] | None
) -> Robot | XrdfToolsError:
    """The ``--urdf`` robot, or the :class:`UrdfError` that says why it is not a valid robot
    (lint reports that as ``urdf-invalid``, exit 1); a file that cannot be read raises."""
    from ...util.errors import UrdfError, UrdfReadError

    try:
        return load_robot_option(urdf, xacro_arg, package_path)
    except UrdfReadError:
        raise
    except UrdfError as exc:
        return exc


def _split(values: list[str] | None) -> list[str]:
    return [v.strip() for item in values or [] for v in item.split(",") if v.strip()]


def run(args: LintArgs) -> tuple[str, int]:
    """Lint as ``xrdf lint`` does: the findings rendered in the chosen format and the exit
    code (0 clean, 1 errors, or warnings with ``strict``). Raises :class:`XrdfToolsError` for
    a usage or input error (exit 2)."""
    from ...lint import RULES, lint
    from ...lint.config import discover_config, load_config
    from ...util.errors import XrdfToolsError

    why = two_stdin({"FILES": args.files})
    if why is not None:
        raise XrdfToolsError(why)
    cfg = load_config(args.config) if args.config is not None else discover_config()
    detail(f"configuration: {cfg.source or 'none (defaults)'}")
    model = None
    if args.urdf is not None:
        model = _robot_or_why_not(args.urdf, args.xacro_arg, args.package_path)
    elif args.xacro_arg or args.package_path:
        raise XrdfToolsError("--xacro-arg and --package-path apply to --urdf; give --urdf")
    with timed("lint"):
        diagnostics = lint(
            args.files,
            urdf=args.urdf,
            config=cfg,
            select=_split(args.select),
            ignore=_split(args.ignore),
            target=args.target,
            urdf_model=model,
            allow_missing_meshes=args.allow_missing_meshes,
        )
    text = render_diagnostics(
        diagnostics,
        args.output_format,
        files=["<stdin>" if is_stdio(f) else str(f) for f in args.files],
        rules=[r.info for r in RULES],
    )
    return text, EXIT_FINDINGS if has_failures(diagnostics, strict=args.strict) else EXIT_OK


# --------------------------------------------------------------------------------------------
# The fast path: `xrdf lint ...` without typer
# --------------------------------------------------------------------------------------------
#: Options taking a value: long name -> (LintArgs field, repeatable).
_VALUED = {
    "--urdf": ("urdf", False),
    "--xacro-arg": ("xacro_arg", True),
    "--package-path": ("package_path", True),
    "--format": ("output_format", False),
    "--select": ("select", True),
    "--ignore": ("ignore", True),
    "--target": ("target", False),
    "--config": ("config", False),
}
#: Flags: long name -> LintArgs field (``-q`` sets nothing lint prints without ``-v``).
_FLAGS = {"--strict": "strict", "--quiet": None, "--allow-missing-meshes": "allow_missing_meshes"}
_SHORT = {"-f": "--format", "-q": "--quiet"}
_PATHS = ("urdf", "config")


@dataclass
class _Parsed:
    values: dict[str, Any] = field(default_factory=dict)
    files: list[Path] = field(default_factory=list)

    def set(self, name: str, value: str) -> bool:
        """Take ``value`` for option ``name``; False when typer should say what is wrong."""
        key, repeatable = _VALUED[name]
        if not value or (not repeatable and key in self.values):
            return False  # an empty value or a repeated option: leave it to typer
        if key == "output_format":
            if value not in {f.value for f in OutputFormat}:
                return False
            self.values[key] = OutputFormat(value)
        elif repeatable:
            self.values.setdefault(key, []).append(value)
        else:
            self.values[key] = Path(value) if key in _PATHS else value
        return True


def _short(token: str, rest: list[str], parsed: _Parsed) -> bool:
    """A cluster of short options (``-q``, ``-f json``, ``-fjson``, ``-qf json``)."""
    for i, letter in enumerate(token[1:], start=1):
        name = _SHORT.get(f"-{letter}")
        if name is None:
            return False
        if name in _FLAGS:
            continue
        value = token[i + 1 :] or (rest.pop(0) if rest else "")
        return parsed.set(name, value)
    return True


def parse_fast(argv: Sequence[str]) -> LintArgs | None:
    """The :class:`LintArgs` of ``argv`` (the words after ``xrdf``) when it is a ``lint``
    command line read here exactly as typer would read it, else None (typer runs it)."""
    if not argv or argv[0] != "lint" or sys.platform.startswith("win"):
        return None  # click expands wildcards on Windows: leave that to it
    if any(k.startswith("_") and k.endswith("_COMPLETE") for k in os.environ):
        return None  # shell completion
    rest = list(argv[1:])
    parsed = _Parsed()
    while rest:
        token = rest.pop(0)
        if token == "--":  # the rest are files
            if not all(rest):
                return None
            parsed.files.extend(Path(t) for t in rest)
            break
        if token.startswith("--"):
            name, eq, value = token.partition("=")
            if name in _FLAGS and not eq:
                key = _FLAGS[name]
                if key is not None:
                    parsed.values[key] = True
                continue
            if name not in _VALUED or not parsed.set(name, value if eq else _pop(rest)):
                return None
        elif token.startswith("-") and token != "-":
            if not _short(token, rest, parsed):
                return None
        elif token:
            parsed.files.append(Path(token))
        else:
            return None
    if not parsed.files:
        return None
    return LintArgs(files=parsed.files, **parsed.values)


def _pop(rest: list[str]) -> str:
    return rest.pop(0) if rest else ""


def fast_main(argv: Sequence[str]) -> int | None:
    """Run ``xrdf lint`` without typer when :func:`parse_fast` reads ``argv``: the exit code
    (findings on stdout, an error on stderr as ``error: ...``, like the Typer command), or
    None when typer must run it."""
    args = parse_fast(argv)
    if args is None:
        return None
    from ...util.errors import XrdfToolsError

    try:
        text, code = run(args)
    except XrdfToolsError as exc:
        echo(f"error: {exc}", err=True)
        return EXIT_USAGE
    if text:
        echo(text, nl=False)
    return code
