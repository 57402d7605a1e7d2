"""Helpers shared by the CLI commands: error exits, verbosity (``-q``/``-v``), diagnostics
on stderr, progress bars, ``-`` for standard input and output, safe writes.

What needs no typer lives in :mod:`xrdf_tools.cli.commands.plain`.
"""

from __future__ import annotations

import math
import sys
import time
from collections.abc import Iterator, Mapping, Sequence
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, NoReturn

import typer

from ...diagnostics import Diagnostic, Severity
from ...util.errors import XrdfToolsError, one_line
from .options import (
    ALLOW_MISSING_MESHES,
    CHAIN,
    DIAGNOSTICS_FORMAT,
    GROUP,
    JOINTS,
    PACKAGE_PATH,
    QUIET,
    ROBOT_URDF,
    STATE,
    TOOL_FRAME,
    VERBOSE,
    XACRO_ARG,
    Option,
    number,
)
from .plain import (
    EXIT_USAGE,
    OutputFormat,
    Verbosity,
    check_input_overwrite,
    check_output_clash,
    render_diagnostics,
    two_stdin,
    verbosity,
    write_result,
)
from .plain import RUN as _RUN
from .plain import VERBOSITY_KEY as _VERBOSITY
from .plain import ProgressUpdate as ProgressUpdate
from .plain import load_xrdf_input as load_xrdf_input  # the commands' helpers, shared here too
from .plain import note as note
from .plain import one_bar as one_bar
from .plain import read_xrdf_input as read_xrdf_input

if TYPE_CHECKING:
    pass


def finite(value: float | None) -> float | None:
    """Typer callback of a number option: ``nan`` and ``inf`` (which typer reads as floats,
    and a ``nan`` passes every range check) are refused."""
    if value is not None and not math.isfinite(value):
        raise typer.BadParameter(f"{value} is not a finite number")
    return value


def typer_option(option: Option, **typer_only: Any) -> Any:
    """The ``typer.Option`` of ``option`` (its table entry: spellings, help, bounds);
    ``typer_only``: what only typer uses (an option's callback). A number option refuses
    ``nan`` and ``inf`` (:func:`finite`)."""
    low, high = option.bounds
    settings: dict[str, Any] = {"help": option.help, "min": low, "max": high}
    if option.convert is number:
        settings["callback"] = finite
    settings.update(option.typer_extra)
    settings.update(typer_only)
    return typer.Option(*option.flags, **settings)


def fail(message: str | XrdfToolsError, code: int = EXIT_USAGE) -> NoReturn:
    """Print a one-line error to stderr and exit (2 by default: usage/input error)."""
    typer.echo(f"error: {one_line(str(message))}", err=True)
    raise typer.Exit(code)


def not_implemented(name: str) -> NoReturn:
    typer.echo(f"error: 'xrdf {name}' is not implemented yet", err=True)
    raise typer.Exit(EXIT_USAGE)


# --------------------------------------------------------------------------------------------
# Verbosity: -q/--quiet and -v/--verbose of every command
# --------------------------------------------------------------------------------------------
def _bind(ctx: typer.Context) -> dict[str, Any]:
    meta: dict[str, Any] = ctx.meta
    if _RUN[0] is not meta:
        _RUN[0] = meta

        def unbind() -> None:
            if _RUN[0] is meta:
                _RUN[0] = {}

        ctx.call_on_close(unbind)
    return meta


def _set_verbosity(ctx: typer.Context, level: Verbosity, flag: str) -> None:
    meta = _bind(ctx)
    current = meta.get(_VERBOSITY, Verbosity.NORMAL)
    if current not in (Verbosity.NORMAL, level):
        raise typer.BadParameter("-q/--quiet and -v/--verbose cannot be combined", param_hint=flag)
    meta[_VERBOSITY] = level


def _quiet_callback(ctx: typer.Context, value: bool) -> bool:
    _bind(ctx)
    if value:
        _set_verbosity(ctx, Verbosity.QUIET, "-q/--quiet")
    return value


def _verbose_callback(ctx: typer.Context, value: bool) -> bool:
    _bind(ctx)
    if value:
        _set_verbosity(ctx, Verbosity.VERBOSE, "-v/--verbose")
        start = time.perf_counter()
        name = ctx.command_path or "xrdf"
        ctx.call_on_close(
            lambda: typer.echo(f"{name}: {time.perf_counter() - start:.2f} s in all", err=True)
        )
    return value


#: ``-q/--quiet`` of every command: no info/warning diagnostics or notes on stderr, no
#: progress bars; errors and the command's output stay.
QuietOption = Annotated[bool, typer_option(QUIET, callback=_quiet_callback)]
#: ``-v/--verbose`` of every command: extra notes and timings on stderr.
VerboseOption = Annotated[bool, typer_option(VERBOSE, callback=_verbose_callback)]


def shown(diagnostics: Sequence[Diagnostic]) -> list[Diagnostic]:
    """The diagnostics printed on stderr at this verbosity: errors only with ``-q``."""
    if verbosity() <= Verbosity.QUIET:
        return [d for d in diagnostics if d.severity is Severity.ERROR]
    return list(diagnostics)


def echo_diagnostics(diagnostics: Sequence[Diagnostic], fmt: OutputFormat) -> None:
    """The diagnostics of a command whose output is something else, on stderr (the one place
    that applies ``-q``; ``lint``'s findings are its output and are not filtered)."""
    chosen = shown(diagnostics)
    if chosen:
        typer.echo(render_diagnostics(chosen, fmt), nl=False, err=True)


# --------------------------------------------------------------------------------------------
# Progress: one style (rich), on a terminal only, never with -q
# --------------------------------------------------------------------------------------------


def stderr_is_terminal() -> bool:
    return sys.stderr.isatty()


def progress_wanted() -> bool:
    """Progress bars are drawn on a terminal (stderr), never when piped or with ``-q``."""
    return verbosity() > Verbosity.QUIET and stderr_is_terminal()


@contextmanager
def progress_bar(enabled: bool = True) -> Iterator[ProgressUpdate | None]:
    """The progress bar of every long run: yields ``update(label, done, total)``, or None when
    no bar is drawn (not a terminal, ``-q``, or ``enabled`` false). The bar is transient: it
    is gone when the block ends."""
    if not (enabled and progress_wanted()):
        yield None
        return
    from rich.console import Console
    from rich.progress import BarColumn, Progress, TextColumn, TimeRemainingColumn

    bar = Progress(
        TextColumn("{task.description}"),
        BarColumn(),
        TextColumn("{task.completed:,}/{task.total:,}"),
        TimeRemainingColumn(),
        console=Console(stderr=True),
        transient=True,
    )
    tasks: dict[str, Any] = {}

    def update(label: str, done: int, total: int) -> None:
        if label not in tasks:
            tasks[label] = bar.add_task(label, total=total)
        bar.update(tasks[label], completed=done, total=total)

    with bar:
        yield update


# --------------------------------------------------------------------------------------------
# '-': standard input and output
# --------------------------------------------------------------------------------------------
def refuse_two_stdin(inputs: Mapping[str, Sequence[Path | str | None]]) -> None:
    """Exit with an error when ``-`` (standard input) is given for more than one input
    (``{"A.xrdf": [a], "B.xrdf": [b]}``): it can be read once."""
    why = two_stdin(inputs)
    if why is not None:
        fail(why)


def write_output(data: str | bytes, output: Path | None) -> None:
    """The one output writer (:func:`~xrdf_tools.cli.commands.plain.write_result`); a failed
    write exits 2 naming the user's path."""
    try:
        write_result(data, output)
    except XrdfToolsError as e:
        fail(e)


def refuse_input_overwrite(output: Path, inputs: Sequence[Path | str | None]) -> None:
    """Exit with an error when ``output`` names one of the inputs or cannot be an output
    (:func:`~xrdf_tools.cli.commands.plain.check_input_overwrite`)."""
    try:
        check_input_overwrite(output, inputs)
    except XrdfToolsError as e:
        fail(e)


def refuse_output_clash(outputs: Mapping[str, Path | None]) -> None:
    """Exit with an error when two output options name the same file
    (:func:`~xrdf_tools.cli.commands.plain.check_output_clash`)."""
    try:
        check_output_clash(outputs)
    except XrdfToolsError as e:
        fail(e)


def stdout_is_terminal() -> bool:
    return sys.stdout.isatty()


#: ``--xacro-arg`` / ``--package-path`` of every command reading a robot (same as ``convert``).
XacroArgOption = Annotated[list[str] | None, typer_option(XACRO_ARG)]
PackagePathOption = Annotated[list[str] | None, typer_option(PACKAGE_PATH)]
#: ``--allow-missing-meshes`` of every command that reads link meshes (one definition).
AllowMissingMeshesOption = Annotated[bool, typer_option(ALLOW_MISSING_MESHES)]
#: The c-space, defaults and tool frames chosen (``convert``, ``inspect``).
GroupOption = Annotated[list[str] | None, typer_option(GROUP)]
StateOption = Annotated[str | None, typer_option(STATE)]
ToolFrameOption = Annotated[list[str] | None, typer_option(TOOL_FRAME)]
JointsOption = Annotated[list[str] | None, typer_option(JOINTS)]
ChainOption = Annotated[list[str] | None, typer_option(CHAIN)]
#: ``--urdf`` of the commands that need the robot (one definition).
RobotUrdfOption = Annotated[Path, typer_option(ROBOT_URDF)]
#: ``-f/--format`` of the diagnostics on stderr, of every command whose output is a file.
DiagnosticsFormatOption = Annotated[OutputFormat, typer_option(DIAGNOSTICS_FORMAT)]
