"""Helpers shared by the CLI commands: error exits, verbosity (``-q``/``-v``), diagnostics
on stderr, progress bars, ``-`` for standard input and output, safe writes.

What needs no typer lives in :mod:`xrdf_tools.cli.commands.core`.
"""

from __future__ import annotations

import os
import sys
import time
from collections.abc import Callable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, NoReturn

import typer

from ...diagnostics import Diagnostic, Severity
from ...util.errors import XrdfToolsError, one_line
from .core import (
    EXIT_USAGE,
    STDIO,
    OutputFormat,
    Verbosity,
    detail,
    is_stdio,
    render_diagnostics,
    two_stdin,
    verbosity,
    write_stdout,
)
from .core import RUN as _RUN
from .core import VERBOSITY_KEY as _VERBOSITY

if TYPE_CHECKING:
    from ...xrdf.model import Xrdf


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
QuietOption = Annotated[
    bool,
    typer.Option(
        "-q",
        "--quiet",
        callback=_quiet_callback,
        help="Only errors and the output: no notes, warnings or progress bars on stderr.",
    ),
]
#: ``-v/--verbose`` of every command: extra notes and timings on stderr.
VerboseOption = Annotated[
    bool,
    typer.Option(
        "-v",
        "--verbose",
        callback=_verbose_callback,
        help="Also print notes on what is read and done, and timings, on stderr.",
    ),
]


def note(message: str) -> None:
    """A note on stderr (what was written, a summary); dropped with ``-q``."""
    if verbosity() > Verbosity.QUIET:
        typer.echo(message, err=True)


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
#: ``update(label, done, total)``: one bar per label, created on first use.
ProgressUpdate = Callable[[str, int, int], None]


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


def one_bar(bar: ProgressUpdate | None, label: str) -> Callable[[int, int], None] | None:
    """A ``progress(done, total)`` callback drawing the bar ``label`` (None without a bar)."""
    if bar is None:
        return None
    update = bar
    return lambda done, total: update(label, done, total)


# --------------------------------------------------------------------------------------------
# '-': standard input and output
# --------------------------------------------------------------------------------------------
def refuse_two_stdin(inputs: Mapping[str, Sequence[Path | str | None]]) -> None:
    """Exit with an error when ``-`` (standard input) is given for more than one input
    (``{"A.xrdf": [a], "B.xrdf": [b]}``): it can be read once."""
    why = two_stdin(inputs)
    if why is not None:
        fail(why)


def load_xrdf_input(path: str | os.PathLike[str]) -> Xrdf:
    """An XRDF input of a command: a file, or standard input for ``-`` (read through the
    guarded reader, named ``<stdin>`` in messages). Raises :class:`XrdfToolsError`."""
    from ...xrdf.io import load_xrdf, parse_xrdf

    if not is_stdio(path):
        return load_xrdf(path)
    from ...util.errors import YamlError
    from ...util.fileio import read_input_text

    detail("reading the XRDF from standard input")
    text = read_input_text(STDIO, what="XRDF", error=YamlError, allow_stdin=True)
    return parse_xrdf(text, "<stdin>")


def write_output(data: str | bytes, output: Path | None) -> None:
    """The one output writer: ``data`` to stdout (no ``-o``, or ``-o -``), else atomically to
    ``output``; a failed write exits 2 naming the user's path."""
    if output is None or is_stdio(output):
        try:
            write_stdout(data)
        except XrdfToolsError as e:
            fail(e)
        return
    from ...util.fileio import write_atomic

    try:
        write_atomic(output, data)
    except XrdfToolsError as e:  # OutputError: names the user's path, never the temporary
        fail(e)
    except OSError as e:
        fail(f"{output}: cannot write: {e.strerror or e}")


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
    from ...util.fileio import check_output_path

    if is_stdio(output):
        return  # standard output: nothing on disk to lose or refuse
    for src in inputs:
        if is_stdio(src):
            continue
        if src is not None and same_file(output, src):
            fail(f"{output}: refusing to overwrite an input file; choose another -o path")
    try:
        check_output_path(_as_given(output))
    except XrdfToolsError as e:
        fail(e)


def _as_given(output: Path) -> Path | str:
    """``output`` as the command line spelled it: a ``Path`` option loses a trailing ``/``
    (``-o newdir/`` would write a file named ``newdir``), so the arguments are asked."""
    text = os.fspath(output)
    for arg in sys.argv[1:]:
        value = arg.split("=", 1)[1] if arg.startswith("-") and "=" in arg else arg
        if value.endswith(("/", os.sep)) and value.rstrip("/" + os.sep) == text.rstrip(os.sep):
            return value
    return output


def refuse_output_clash(outputs: Mapping[str, Path | None]) -> None:
    """Exit with an error when two output options (``{"--plot": path, ...}``) name the same
    file: one would silently replace the other."""
    seen: list[tuple[str, Path]] = []
    for option, path in outputs.items():
        if path is None:
            continue
        for other, earlier in seen:
            both_stdout = is_stdio(path) and is_stdio(earlier)
            if both_stdout or (
                not is_stdio(path) and not is_stdio(earlier) and same_file(path, earlier)
            ):
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
#: ``--allow-missing-meshes`` of every command that reads link meshes (one definition).
AllowMissingMeshesOption = Annotated[
    bool,
    typer.Option(
        "--allow-missing-meshes",
        help="Mesh files that cannot be found (unknown package, no such file) are expected: "
        "leave their parts out, a warning each. Without it such a mesh stops the command "
        "(exit 2) naming the URI and the directories searched (lint: a warning); "
        "--package-path NAME=DIR points at them.",
    ),
]
