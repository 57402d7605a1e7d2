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

from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from ...util.errors import one_line
from .options import (
    FINDINGS_FORMAT,
    LINT_ALLOW_MISSING_MESHES,
    PACKAGE_PATH,
    QUIET,
    VERBOSE,
    XACRO_ARG,
    Option,
    OptionTable,
    parse_command_line,
    path,
    split_values,
    target,
    text,
)
from .plain import (
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
    run_verbosity,
    timed,
    two_stdin,
)

if TYPE_CHECKING:
    from ...diagnostics import Diagnostic
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
            select=split_values(args.select),
            ignore=split_values(args.ignore),
            target=args.target,
            urdf_model=model,
            allow_missing_meshes=args.allow_missing_meshes,
        )
    detail(_tally(len(args.files), diagnostics))
    text = render_diagnostics(
        diagnostics,
        args.output_format,
        files=["<stdin>" if is_stdio(f) else str(f) for f in args.files],
        rules=[r.info for r in RULES],
    )
    return text, EXIT_FINDINGS if has_failures(diagnostics, strict=args.strict) else EXIT_OK


def _tally(files: int, diagnostics: Sequence[Diagnostic]) -> str:
    """What ``-v`` says after linting, also when nothing was found: ``2 file(s) checked: 0
    error(s), 1 warning(s), 0 info(s)``."""
    counts = Counter(d.severity.value for d in diagnostics)
    kinds = ", ".join(f"{counts[k]} {k}(s)" for k in ("error", "warning", "info"))
    return f"{files} file(s) checked: {kinds}"


# --------------------------------------------------------------------------------------------
# The options (of the Typer command too) and the fast path: `xrdf lint ...` without typer
# --------------------------------------------------------------------------------------------
LINT_OPTIONS = OptionTable(
    (
        Option(
            "urdf",
            ("--urdf",),
            "URDF (or xacro) the files describe: enables frame, joint, limit and collision checks.",
            path,
        ),
        XACRO_ARG,
        PACKAGE_PATH,
        FINDINGS_FORMAT,
        Option(
            "select",
            ("--select",),
            "Only these rules: ids or prefixes ending in '-' like 'curobo-' (repeatable or "
            "comma-separated).",
            text,
            multiple=True,
        ),
        Option(
            "ignore",
            ("--ignore",),
            "Skip these rules: ids or prefixes ending in '-' like 'curobo-' (repeatable or "
            "comma-separated).",
            text,
            multiple=True,
        ),
        target(
            "Its silent failures become errors; the other readers' checks are off. Default: "
            "the configuration's 'target' (else none: every reader's checks, as warnings)."
        ),
        Option("strict", ("--strict",), "Exit 1 on warnings too, not only errors."),
        Option(
            "config",
            ("--config",),
            "Configuration file (.xrdf-lint.yaml or pyproject.toml). Default: the first "
            ".xrdf-lint.yaml or [tool.xrdf.lint] from the current directory upwards.",
            path,
        ),
        LINT_ALLOW_MISSING_MESHES,
        QUIET,
        VERBOSE,
    )
)
_FAST = [o for o in LINT_OPTIONS if o.fast]
#: Views of the fast path's spellings: options taking a value (long name -> (field,
#: repeatable)), flags (long name -> field) and short names (-> long name).
_VALUED = {o.flags[0]: (o.name, o.multiple) for o in _FAST if not o.is_flag}
_FLAGS = {next(f for f in o.flags if f.startswith("--")): o.name for o in _FAST if o.is_flag}
_SHORT = {
    f: next(g for g in o.flags if g.startswith("--"))
    for o in _FAST
    for f in o.flags
    if not f.startswith("--")
}


def parse_fast(argv: Sequence[str]) -> LintArgs | None:
    """The :class:`LintArgs` of ``argv`` (the words after ``xrdf``) when it is a ``lint``
    command line read here exactly as typer would read it, else None (typer runs it)."""
    parsed = _parse(argv)
    return None if parsed is None else parsed[0]


def _parse(argv: Sequence[str]) -> tuple[LintArgs, bool] | None:
    """:func:`parse_fast`'s arguments and whether ``-q`` was given."""
    line = parse_command_line(LINT_OPTIONS, argv, "lint")
    if line is None or not line.arguments:
        return None
    quiet = bool(line.values.pop("quiet", False))
    return LintArgs(files=[Path(a) for a in line.arguments], **line.values), quiet


def fast_main(argv: Sequence[str]) -> int | None:
    """Run ``xrdf lint`` without typer when :func:`parse_fast` reads ``argv``: the exit code
    (findings on stdout, an error on stderr as ``error: ...``, like the Typer command), or
    None when typer must run it."""
    parsed = _parse(argv)
    if parsed is None:
        return None
    args, quiet = parsed
    from ...util.errors import XrdfToolsError

    try:
        with run_verbosity(quiet):
            text, code = run(args)
    except XrdfToolsError as exc:
        echo(f"error: {one_line(str(exc))}", err=True)
        return EXIT_USAGE
    if text:
        echo(text, nl=False)
    return code
