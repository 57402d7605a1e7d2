"""The ``xrdf`` command line: the console entry point :func:`main`.

The commands are a Typer app (:mod:`xrdf_tools.cli.commands.app`, also importable as
``xrdf_tools.cli.app``), imported only when it is needed: ``xrdf lint`` with the arguments
a user or the pre-commit hook normally gives runs without typer
(:mod:`xrdf_tools.cli.commands.lint_core`), because typer's start-up alone takes longer than
yamllint takes to lint a file. Everything else, ``xrdf lint --help`` and lint's usage errors
included, is typer's.
"""

from __future__ import annotations

import errno
import os
import signal
import sys
from typing import Any


def __getattr__(name: str) -> Any:
    """``app``: the Typer app, imported on first use."""
    if name == "app":
        from .commands.app import app

        return app
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def _terminate(signum: int, _frame: object) -> None:
    """SIGTERM/SIGHUP: unwind like an interrupt, so ``finally`` blocks remove temporary files."""
    raise SystemExit(128 + signum)


def main() -> None:
    """Console entry point: library errors become one line on stderr and exit code 2."""
    from ..util.errors import XrdfToolsError
    from .commands.core import echo

    for name in ("SIGTERM", "SIGHUP"):
        if hasattr(signal, name):
            signal.signal(getattr(signal, name), _terminate)
    try:
        code = _fast(sys.argv[1:])
        if code is not None:
            sys.exit(code)
        from .commands.app import app

        app()
    except XrdfToolsError as exc:
        echo(f"error: {exc}", err=True)
        sys.exit(2)
    except KeyboardInterrupt:
        echo("interrupted", err=True)
        sys.exit(130)


def _fast(argv: list[str]) -> int | None:
    """``xrdf lint`` without typer (:func:`~xrdf_tools.cli.commands.lint_core.fast_main`), or
    None when typer runs the command line. An interrupt ends the run with exit code 130 and
    a closed standard output quietly with 1, as typer ends a command."""
    if argv[:1] != ["lint"]:
        return None
    from .commands.lint_core import fast_main

    try:
        return fast_main(argv)
    except KeyboardInterrupt:
        return 130
    except OSError as exc:
        if exc.errno != errno.EPIPE:
            raise
        # nothing more reaches the reader; Python's own flush at exit must not complain
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 1
