"""What the CLI commands share that needs no typer: exit codes, output formats and their one
renderer dispatch, the ``-q``/``-v`` level, ``-`` for standard input, the ``--urdf`` loader,
and :func:`echo`.

The Typer commands import it beside :mod:`xrdf_tools.cli.commands.typer_common` (what needs
typer); the typer-free command bodies (:mod:`~xrdf_tools.cli.commands.lint_core`,
:mod:`~xrdf_tools.cli.commands.report_core`) import only this module, so that they run without
importing typer.
"""

from __future__ import annotations

import os
import re
import sys
import time
from collections.abc import Callable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from enum import Enum, IntEnum
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ...diagnostics import (
    Diagnostic,
    RuleInfo,
    Severity,
    render_github,
    render_json,
    render_text,
)

if TYPE_CHECKING:
    from ...robot.core import Robot
    from ...xrdf.model import Xrdf


class OutputFormat(str, Enum):
    text = "text"
    json = "json"
    github = "github"
    sarif = "sarif"


EXIT_OK = 0
EXIT_FINDINGS = 1
EXIT_USAGE = 2

#: ANSI escape sequences, removed from output that is not a terminal (as ``typer.echo`` does).
_ANSI = re.compile(r"\033\[[;?0-9]*[a-zA-Z]")


def is_terminal(stream: Any) -> bool:
    try:
        return bool(stream.isatty())
    except Exception:  # a stream without a working isatty is no terminal (as click says)
        return False


def echo(message: str, *, err: bool = False, nl: bool = True) -> None:
    """``message`` on standard output (``err``: standard error), written like ``typer.echo``
    writes text: a newline added unless ``nl`` is false, ANSI escapes removed when the stream
    is not a terminal, flushed. Standard output goes through :func:`write_stdout`."""
    stream = sys.stderr if err else sys.stdout
    out = message + "\n" if nl else message
    if out and not is_terminal(stream):
        out = _ANSI.sub("", out)
    if not err:
        write_stdout(out)
        return
    if stream is None:  # no stream attached (pythonw): nothing to write to
        return
    if out:
        stream.write(out)
    stream.flush()


def write_stdout(data: str | bytes) -> None:
    """The one writer of a command's output to standard output: text or bytes, to the real
    stream or any text stream put in its place (an in-process runner's), flushed.

    Output that cannot be delivered is an error, never silently lost: a closed standard output
    (``>&-``), a full disk (``> /dev/full``) or a reader that went away (a closed pipe) raise
    :class:`~xrdf_tools.util.errors.OutputError` (the caller exits 2); standard output is then
    pointed at the null device, so that Python's own flush at exit says nothing more.
    """
    from ...util.errors import OutputError

    stream = sys.stdout
    if stream is None or getattr(stream, "closed", False):
        raise OutputError("standard output is closed; nothing was written (use -o FILE)")
    try:
        if isinstance(data, bytes):
            binary = getattr(stream, "buffer", None)
            if binary is None:  # a text stream (an in-process runner's StringIO)
                stream.write(data.decode("utf-8"))
            else:
                stream.flush()
                binary.write(data)
                binary.flush()
        elif data:
            stream.write(data)
        stream.flush()
    except (OSError, ValueError) as e:
        _silence_stdout()
        reason = e.strerror if isinstance(e, OSError) and e.strerror else str(e)
        raise OutputError(f"standard output: cannot write: {reason}") from None


def _silence_stdout() -> None:
    """Point file descriptor 1 at the null device (after a failed write to it)."""
    try:
        fd = sys.stdout.fileno()
    except (AttributeError, OSError, ValueError):
        return  # not a real file: nothing is flushed to it at exit
    null = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(null, fd)
    finally:
        os.close(null)


def _as_text(
    ds: Sequence[Diagnostic], files: Sequence[str] | None, rules: Sequence[RuleInfo]
) -> str:
    return render_text(ds)


def _as_json(
    ds: Sequence[Diagnostic], files: Sequence[str] | None, rules: Sequence[RuleInfo]
) -> str:
    return render_json(ds, **({"files": list(files)} if files is not None else {}))


def _as_github(
    ds: Sequence[Diagnostic], files: Sequence[str] | None, rules: Sequence[RuleInfo]
) -> str:
    return render_github(ds)


def _as_sarif(
    ds: Sequence[Diagnostic], files: Sequence[str] | None, rules: Sequence[RuleInfo]
) -> str:
    from ... import __version__
    from ...diagnostics import render_sarif
    from ...rules.registry import rule_info

    listed = {r.id for r in rules}
    described = list(rules)
    for rid in dict.fromkeys(d.rule for d in ds):
        info = rule_info(rid)
        if rid not in listed and info is not None:
            described.append(info)
    return render_sarif(ds, described, version=__version__)


#: The diagnostics' one table of renderers: format -> (diagnostics, files, rules) -> text.
DIAGNOSTIC_RENDERERS: dict[
    OutputFormat,
    Callable[[Sequence[Diagnostic], Sequence[str] | None, Sequence[RuleInfo]], str],
] = {
    OutputFormat.text: _as_text,
    OutputFormat.json: _as_json,
    OutputFormat.github: _as_github,
    OutputFormat.sarif: _as_sarif,
}


def render_diagnostics(
    diagnostics: Sequence[Diagnostic],
    fmt: OutputFormat,
    *,
    files: Sequence[str] | None = None,
    rules: Sequence[RuleInfo] = (),
) -> str:
    """The one renderer dispatch of every command. ``files`` (JSON) lists the inputs checked;
    ``rules`` (SARIF) are listed even without results."""
    return DIAGNOSTIC_RENDERERS[fmt](diagnostics, files, rules)


def has_failures(diagnostics: Sequence[Diagnostic], *, strict: bool) -> bool:
    worst = {Severity.ERROR} | ({Severity.WARNING} if strict else set())
    return any(d.severity in worst for d in diagnostics)


# --------------------------------------------------------------------------------------------
# Verbosity: the level -q/--quiet and -v/--verbose set (their options: typer_common.py)
# --------------------------------------------------------------------------------------------
class Verbosity(IntEnum):
    QUIET = -1
    NORMAL = 0
    VERBOSE = 1


#: Key of the verbosity in the context's ``meta`` (one dict per ``xrdf`` run, shared by the
#: group and command contexts).
VERBOSITY_KEY = "xrdf_tools.verbosity"
#: The ``meta`` of the running command (bound by the option callbacks, which run on every
#: invocation, and unbound when its context closes): nothing survives from one run to the next
#: in one process (tests, ``CliRunner``).
RUN: list[dict[str, Any]] = [{}]


def verbosity() -> Verbosity:
    """The ``-q``/``-v`` level of the running command (normal outside a command)."""
    level: Verbosity = RUN[0].get(VERBOSITY_KEY, Verbosity.NORMAL)
    return level


@contextmanager
def run_verbosity(quiet: bool) -> Iterator[None]:
    """A command run without typer: ``-q`` (``quiet``) or the normal level, for the block."""
    previous = RUN[0]
    RUN[0] = {VERBOSITY_KEY: Verbosity.QUIET if quiet else Verbosity.NORMAL}
    try:
        yield
    finally:
        RUN[0] = previous


def detail(message: str) -> None:
    """A note on stderr shown only with ``-v``."""
    if verbosity() >= Verbosity.VERBOSE:
        echo(message, err=True)


@contextmanager
def timed(label: str) -> Iterator[None]:
    """With ``-v``: print how long the block took (``label: 1.23 s``)."""
    start = time.perf_counter()
    try:
        yield
    finally:
        detail(f"{label}: {time.perf_counter() - start:.2f} s")


def progress_lines(label: str) -> Callable[[int, int], None] | None:
    """With ``-v`` and no progress bar (stderr not a terminal, e.g. CI): ``update(done,
    total)`` printing one line per tenth of the work on stderr (``sampling: 30 %
    (30,000/100,000), 4.2 s``), whatever steps ``done`` comes in; None without ``-v``."""
    if verbosity() < Verbosity.VERBOSE:
        return None
    start = time.perf_counter()
    printed = [0]

    def line(done: int, total: int) -> None:
        tenth = 10 * done // max(total, 1)
        if tenth > printed[0]:
            printed[0] = tenth
            pct = 100 * done // max(total, 1)
            detail(f"{label}: {pct} % ({done:,}/{total:,}), {time.perf_counter() - start:.1f} s")

    return line


# --------------------------------------------------------------------------------------------
# '-': standard input and output
# --------------------------------------------------------------------------------------------
STDIO = "-"


def is_stdio(path: str | os.PathLike[str] | None) -> bool:
    return path is not None and os.fspath(path) == STDIO


def two_stdin(inputs: Mapping[str, Sequence[Path | str | None]]) -> str | None:
    """Why the inputs (``{"A.xrdf": [a], "B.xrdf": [b]}``) cannot be read when ``-``
    (standard input, which can be read once) is given for more than one, else None."""
    counts = {name: sum(1 for p in paths if is_stdio(p)) for name, paths in inputs.items()}
    if sum(counts.values()) <= 1:
        return None
    named = [f"{n} ({k} times)" if k > 1 else n for n, k in counts.items() if k]
    return f"'-' (standard input) can be read only once; it is given for {' and '.join(named)}"


# --------------------------------------------------------------------------------------------
# --urdf, --xacro-arg, --package-path
# --------------------------------------------------------------------------------------------
def pairs(values: list[str] | None, parse: Any) -> dict[str, str]:
    """``--xacro-arg`` values as a mapping (the last one wins)."""
    return dict(parse(v) for v in values or [])


def load_robot_option(
    path: Path,
    xacro_arg: list[str] | None,
    package_path: list[str] | None,
    srdf: Path | None = None,
) -> Robot:
    """The robot of ``--urdf``: a URDF, or a xacro expanded with ``--xacro-arg`` and
    ``--package-path`` like ``xrdf convert`` does (one loader for every command); ``srdf``:
    the command's ``--srdf``, expanded with the same arguments.

    Raises :class:`XrdfToolsError` (the caller exits 2).
    """
    from ...robot.packages import parse_package_paths
    from ...robot.xacro_source import load_robot, parse_xacro_arg

    robot = load_robot(
        path,
        xacro_args=pairs(xacro_arg, parse_xacro_arg),
        package_paths=parse_package_paths(package_path),
        srdf=srdf,
    )
    echo_warnings(robot.warnings)  # defects in unused parts, xacro's warnings
    return robot


def echo_warnings(warnings: Sequence[Diagnostic]) -> None:
    """Warnings found while loading an input, on stderr; dropped with ``-q``."""
    if warnings and verbosity() > Verbosity.QUIET:
        echo(render_text(warnings), err=True, nl=False)


# --------------------------------------------------------------------------------------------
# Notes, progress callbacks, inputs and outputs (errors raised: the caller exits 2)
# --------------------------------------------------------------------------------------------
def note(message: str) -> None:
    """A note on stderr (what was written, a summary); dropped with ``-q``."""
    if verbosity() > Verbosity.QUIET:
        echo(message, err=True)


#: ``update(label, done, total)``: one progress bar per label, created on first use.
ProgressUpdate = Callable[[str, int, int], None]


def one_bar(bar: ProgressUpdate | None, label: str) -> Callable[[int, int], None] | None:
    """A ``progress(done, total)`` callback drawing the bar ``label`` (None without a bar)."""
    if bar is None:
        return None
    update = bar
    return lambda done, total: update(label, done, total)


def read_xrdf_input(path: str | os.PathLike[str]) -> tuple[str, str]:
    """The text of an XRDF input and the name messages give it (``<stdin>`` for ``-``), for
    a command that lints it as well as reading it. Raises :class:`XrdfToolsError`."""
    from ...util.errors import YamlError
    from ...util.fileio import read_input_text

    if not is_stdio(path):
        return read_input_text(path, what="file", error=YamlError), os.fspath(path)
    detail("reading the XRDF from standard input")
    return read_input_text(STDIO, what="XRDF", error=YamlError, allow_stdin=True), "<stdin>"


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


def write_result(data: str | bytes, output: Path | None) -> None:
    """The one output writer: ``data`` to stdout (no ``-o``, or ``-o -``), else atomically to
    ``output``. A failed write raises :class:`XrdfToolsError` naming the user's path."""
    if output is None or is_stdio(output):
        write_stdout(data)
        return
    from ...util.fileio import write_output_file

    write_output_file(output, data)


def same_file(a: str | os.PathLike[str], b: str | os.PathLike[str]) -> bool:
    try:
        return Path(a).resolve() == Path(b).resolve() or (
            Path(a).exists() and Path(b).exists() and os.path.samefile(a, b)
        )
    except (OSError, RuntimeError, ValueError):  # a link loop (Python < 3.13), a NUL byte
        return False


def check_robot_overwrite(output: Path | None, robot: Any) -> None:
    """:func:`check_input_overwrite` against every file ``robot`` (a loaded
    :class:`~xrdf_tools.robot.core.Robot`) is read from: its URDF or xacro files and the mesh
    files of its links (:func:`~xrdf_tools.robot.input_files.robot_input_files`)."""
    if output is None or is_stdio(output):
        return
    from ...robot.input_files import robot_input_files

    check_input_overwrite(output, robot_input_files(robot))


def check_input_overwrite(output: Path, inputs: Sequence[Path | str | None]) -> None:
    """Raise :class:`XrdfToolsError` when ``output`` names one of the inputs (nothing is ever
    lost), or cannot be an output at all (a directory, device, FIFO or socket; symlinks are
    fine)."""
    from ...util.errors import XrdfToolsError
    from ...util.fileio import check_output_path

    if is_stdio(output):
        return  # standard output: nothing on disk to lose or refuse
    for src in inputs:
        if is_stdio(src):
            continue
        if src is not None and same_file(output, src):
            raise XrdfToolsError(
                f"{output}: refusing to overwrite an input file; choose another -o path"
            )
    check_output_path(_as_given(output))


def _as_given(output: Path) -> Path | str:
    """``output`` as the command line spelled it: a ``Path`` option loses a trailing ``/``
    (``-o newdir/`` would write a file named ``newdir``), so the arguments are asked."""
    text = os.fspath(output)
    for arg in sys.argv[1:]:
        value = arg.split("=", 1)[1] if arg.startswith("-") and "=" in arg else arg
        if value.endswith(("/", os.sep)) and value.rstrip("/" + os.sep) == text.rstrip(os.sep):
            return value
    return output


def check_output_clash(outputs: Mapping[str, Path | None]) -> None:
    """Raise :class:`XrdfToolsError` when two output options (``{"--plot": path, ...}``) name
    the same file: one would silently replace the other."""
    from ...util.errors import XrdfToolsError

    seen: list[tuple[str, Path]] = []
    for option, path in outputs.items():
        if path is None:
            continue
        for other, earlier in seen:
            both_stdout = is_stdio(path) and is_stdio(earlier)
            if both_stdout or (
                not is_stdio(path) and not is_stdio(earlier) and same_file(path, earlier)
            ):
                raise XrdfToolsError(
                    f"{path}: given for both {other} and {option}; choose different paths"
                )
        seen.append((option, path))
