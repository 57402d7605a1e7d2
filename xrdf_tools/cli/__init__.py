"""The ``xrdf`` command line: the console entry point :func:`main`.

The commands are a Typer app (:mod:`xrdf_tools.cli.commands.app`, also importable as
``xrdf_tools.cli.app``), imported only when it is needed: ``xrdf lint`` with the arguments
a user or the pre-commit hook normally gives runs without typer
(:mod:`xrdf_tools.cli.commands.lint_core`), because typer's start-up alone takes longer than
yamllint takes to lint a file; so does a ``xrdf report`` that draws no progress bar
(:mod:`xrdf_tools.cli.commands.report_core`). Everything else, their ``--help`` and usage
errors included, is typer's.
"""

from __future__ import annotations

import contextlib
import errno
import os
import signal
import sys
import threading  # before the handlers: an interrupted import of its modules would break it
from collections.abc import MutableMapping
from typing import Any


def __getattr__(name: str) -> Any:
    """``app``: the Typer app, imported on first use."""
    if name == "app":
        from .commands.app import app

        return app
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


#: After a signal: when the process is still running this long, the interrupt is raised again
#: (a library may have swallowed it: trimesh's import catches ``BaseException``) ...
_REPEAT_AFTER_S = 0.3
#: ... and after this long it exits at once, its temporary files removed.
_EXIT_AFTER_S = 0.8


def _on_signal(signum: int, _frame: object) -> None:
    """SIGINT/SIGTERM/SIGHUP: unwind (``finally`` blocks remove temporary files, workers are
    stopped), as ``KeyboardInterrupt`` for SIGINT, else ``SystemExit(128 + signum)``; a
    watchdog makes sure the process ends within :data:`_EXIT_AFTER_S` seconds."""
    if not _WATCHDOG:
        _WATCHDOG.append(signum)
        with contextlib.suppress(Exception):
            sys.stderr.write("interrupted\n" if signum == signal.SIGINT else "terminated\n")
            sys.stderr.flush()
        threading.Thread(target=_watchdog, args=(signum,), daemon=True).start()
    if signum == signal.SIGINT:
        raise KeyboardInterrupt
    raise SystemExit(128 + signum)


_WATCHDOG: list[int] = []


def _watchdog(signum: int) -> None:
    import _thread
    import time

    time.sleep(_REPEAT_AFTER_S)
    _thread.interrupt_main(signal.Signals(signum))
    time.sleep(_EXIT_AFTER_S - _REPEAT_AFTER_S)
    from ..util.fileio import remove_temporaries

    remove_temporaries()
    jobs = sys.modules.get("xrdf_tools.selfcollision.engine.jobs")
    if jobs is not None:
        jobs.stop_workers()
    xacro_child = sys.modules.get("xrdf_tools.robot.xacro_child")
    if xacro_child is not None:
        xacro_child.stop_children()
    os._exit(128 + signum)


def main() -> None:
    """Console entry point: library errors become one line on stderr and exit code 2;
    SIGINT, SIGTERM and SIGHUP end the command (see :func:`_on_signal`)."""
    try:
        for name in ("SIGINT", "SIGTERM", "SIGHUP"):  # first: imports take a while
            sig = getattr(signal, name, None)
            if sig is not None and signal.getsignal(sig) is not signal.SIG_IGN:
                signal.signal(sig, _on_signal)
        _run()
    except KeyboardInterrupt:  # said by _on_signal
        sys.exit(130)
    except Exception:
        # A signal that lands while a library imports can leave that library half imported:
        # the import swallows the interrupt and fails on a name it never bound (scipy.ndimage:
        # NameError). The command was ended on purpose: exit as the signal says, no traceback.
        if _WATCHDOG:
            sys.exit(128 + _WATCHDOG[0])
        raise


#: The thread-count variables of the BLAS libraries numpy may use.
BLAS_THREAD_VARS = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")


def one_blas_thread_for(argv: list[str], environ: MutableMapping[str, str]) -> None:
    """``xrdf report`` counts with numpy one small array at a time (and its ``--jobs``
    workers with one BLAS thread each): a BLAS thread pool only spins beside it. Unless the
    user chose a count, ``report`` runs with one BLAS thread (set before numpy is imported)."""
    if argv[:1] == ["report"]:
        for name in BLAS_THREAD_VARS:
            environ.setdefault(name, "1")


def _run() -> None:
    from ..util.errors import XrdfToolsError
    from .commands.plain import echo

    one_blas_thread_for(sys.argv[1:], os.environ)
    try:
        check_working_directory()
        code = _fast(sys.argv[1:])
        if code is not None:
            sys.exit(code)
        from .commands.app import app_for

        completing = any(k.startswith("_") and k.endswith("_COMPLETE") for k in os.environ)
        app_for([] if completing else sys.argv[1:])()
    except XrdfToolsError as exc:
        echo(f"error: {exc}", err=True)
        sys.exit(2)


def check_working_directory() -> None:
    """Raise :class:`XrdfToolsError` when the current directory was removed: relative paths,
    the lint configuration search and the paths written relative to it cannot be resolved
    (``os.getcwd`` fails in every command that asks)."""
    from ..util.errors import XrdfToolsError

    try:
        os.getcwd()
    except OSError as e:
        raise XrdfToolsError(
            f"the current directory cannot be read ({e.strerror or e}); it may have been "
            "removed: change to an existing directory"
        ) from None


def _fast(argv: list[str]) -> int | None:
    """``xrdf lint`` and ``xrdf report`` without typer (``fast_main`` of
    :mod:`~xrdf_tools.cli.commands.lint_core` and :mod:`~xrdf_tools.cli.commands.report_core`),
    or None when typer runs the command line. An interrupt ends the run with exit code 130 and
    a closed standard output quietly with 1, as typer ends a command."""
    try:
        if argv[:1] == ["lint"]:
            from .commands.lint_core import fast_main

            return fast_main(argv)
        if argv[:1] == ["report"]:
            from .commands import report_core

            return report_core.fast_main(argv)
        return None
    except KeyboardInterrupt:
        return 130
    except OSError as exc:
        if exc.errno != errno.EPIPE:
            raise
        # nothing more reaches the reader; Python's own flush at exit must not complain
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 1
