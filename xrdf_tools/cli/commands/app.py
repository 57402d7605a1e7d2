"""The ``xrdf`` Typer app: a thin layer over the library.

Each subcommand lives in ``xrdf_tools.cli.commands.<name>``; this module wires them together and
handles ``--version``. The console entry point is :func:`xrdf_tools.cli.main` (which also
turns library exceptions into one-line errors with exit code 2); ``xrdf_tools.cli.app`` is
this app, with every command. :func:`app_for` builds the app with only the command a command
line runs: its options are all typer reads, so the other commands' modules and options are
neither imported nor built (help and messages are the same).
"""

from __future__ import annotations

import importlib
from collections.abc import Iterable
from typing import Annotated, Any

import typer

from ... import __version__

_HELP = (
    "Tools for XRDF robot descriptions (cuMotion / cuRobo / MoveIt).\n\n"
    "Typical flow: inspect a URDF (+ SRDF), convert it (with an SRDF or a cuRobo config) to "
    "XRDF, lint it, report on its self-collision mask, look at the spheres.\n\n"
    "Exit codes: 0 success, 1 findings (lint errors, differences), 2 usage or input error."
)

#: The commands in the order ``xrdf --help`` lists them: name and its one-line summary (each
#: command's docstring, with examples, is its full ``xrdf COMMAND --help``). The module of a
#: command is ``xrdf_tools.cli.commands.<name>``.
COMMANDS: tuple[tuple[str, str], ...] = (
    ("convert", "URDF/xacro + MoveIt SRDF or cuRobo config → XRDF."),
    ("inspect", "Links, joints, chains, SRDF groups and the default c-space."),
    ("lint", "Check XRDF files against the spec (and a URDF)."),
    ("diff", "Semantic difference between two XRDF files."),
    ("report", "Self-collision report over sampled configurations."),
    ("viz", "Sphere visualizations to rerun (.rrd), MCAP or PNG."),
    ("spheres", "Fit collision spheres to link meshes; coverage metrics."),
    ("edit", "Edit spheres, mask and defaults in the browser (viser)."),
    ("expand", "xacro → URDF, without ROS (as every command reads it)."),
)
#: Command groups (a Typer app of their own): name and help.
GROUPS: tuple[tuple[str, str], ...] = (
    (
        "export",
        "XRDF → cuRobo YAML, MoveIt SRDF sync, or an XRDF for a reader.",
    ),
)


def _version(value: bool) -> None:
    if value:
        typer.echo(f"xrdf-tools {__version__}")
        raise typer.Exit()


def _root(
    version: Annotated[
        bool,
        typer.Option("--version", callback=_version, is_eager=True, help="Show the version."),
    ] = False,
) -> None:
    """Tools for XRDF robot descriptions."""


def build_app(names: Iterable[str] | None = None) -> typer.Typer:
    """The ``xrdf`` app with the commands ``names`` (None: every command)."""
    wanted = None if names is None else set(names)
    app = typer.Typer(
        name="xrdf",
        help=_HELP,
        no_args_is_help=True,
        add_completion=True,
        pretty_exceptions_enable=False,
        rich_markup_mode=None,
    )
    app.callback()(_root)
    for name, summary in COMMANDS:
        if wanted is None or name in wanted:
            app.command(name, short_help=summary)(_module(name).command)
    for name, help_ in GROUPS:
        if wanted is None or name in wanted:
            app.add_typer(_module(name).app, name=name, help=help_)
    return app


def _module(name: str) -> Any:
    return importlib.import_module(f"{__package__}.{name}")


def app_for(words: list[str]) -> typer.Typer:
    """The app for the command line ``words`` (after ``xrdf``): only its command when the
    first word names one, else every command (``xrdf --help``, a mistyped command)."""
    known = {name for name, _ in (*COMMANDS, *GROUPS)}
    if words and words[0] in known:
        return build_app([words[0]])
    return full_app()


_APP: list[typer.Typer] = []


def full_app() -> typer.Typer:
    """The app with every command (built once)."""
    if not _APP:
        _APP.append(build_app())
    return _APP[0]


def __getattr__(name: str) -> Any:
    """``app``: :func:`full_app`, built on first use."""
    if name == "app":
        return full_app()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
