"""Option tables: one definition of a command's options for its Typer command and its fast path.

``xrdf lint`` and ``xrdf report`` start without typer when the command line is one they read
exactly as typer would (:func:`parse_command_line`); anything else (``--help``, a usage error,
``-v``, shell completion) is left to the Typer app, so that help, usage errors and every message
stay typer's. Both readers take the names, values and limits of the options from one
:class:`OptionTable`: the Typer command builds each ``typer.Option`` from it
(:func:`xrdf_tools.cli.commands.typer_common.typer_option`), and a test checks that the two
accept the same options. This module imports no typer.
"""

from __future__ import annotations

import os
import re
import sys
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from enum import Enum
from pathlib import Path
from typing import Any

from ...util.errors import SourceError
from .plain import OutputFormat

#: Converts an option's text to its value; raises ValueError when typer would refuse it (the
#: fast path then leaves the command line to typer, which says why).
Convert = Callable[[str], Any]


@dataclass(frozen=True)
class Option:
    """One option of a command.

    ``name`` is the command's parameter (and the field of its arguments); ``flags`` its
    spellings (in the order help shows them); ``convert`` reads its value (None: a flag);
    ``multiple``: it may be repeated and collects a list; ``fast``: a command line giving it
    is read without typer; ``bounds``: ``(min, max)`` of a number (None: open);
    ``typer_extra``: further ``typer.Option`` arguments (``show_default``).
    """

    name: str
    flags: tuple[str, ...]
    help: str
    convert: Convert | None = None
    multiple: bool = False
    fast: bool = True
    bounds: tuple[float | None, float | None] = (None, None)
    typer_extra: Mapping[str, Any] = field(default_factory=dict)

    @property
    def is_flag(self) -> bool:
        return self.convert is None


@dataclass(frozen=True)
class OptionTable:
    """The options of one command, by parameter name."""

    options: tuple[Option, ...]

    def __getitem__(self, name: str) -> Option:
        for opt in self.options:
            if opt.name == name:
                return opt
        raise KeyError(name)

    def __iter__(self) -> Iterator[Option]:
        return iter(self.options)

    def by_flag(self) -> dict[str, Option]:
        """Every spelling (``--format``, ``-f``) to its option."""
        return {flag: opt for opt in self.options for flag in opt.flags}


# --------------------------------------------------------------------------------------------
# Value converters: exactly what typer accepts, or ValueError (typer then says why)
# --------------------------------------------------------------------------------------------
def text(value: str) -> str:
    return value


def path(value: str) -> Path:
    return Path(value)


def choice(enum: type[Enum]) -> Convert:
    """A member of ``enum`` by its exact value (typer's choices are case-sensitive)."""

    def convert(value: str) -> Any:
        return enum(value)

    return convert


_DIGITS = re.compile(r"[0-9]+")
_DECIMAL = re.compile(r"[0-9]+(\.[0-9]*)?([eE][-+]?[0-9]+)?|\.[0-9]+([eE][-+]?[0-9]+)?")


def integer(value: str) -> int:
    """A plain decimal integer (signs, spaces and underscores are left to typer)."""
    if not _DIGITS.fullmatch(value):
        raise ValueError(value)
    return int(value)


def number(value: str) -> float:
    """A plain decimal number (``0.5``, ``1e-3``; anything fancier is left to typer)."""
    if not _DECIMAL.fullmatch(value):
        raise ValueError(value)
    return float(value)


# --------------------------------------------------------------------------------------------
# Options every command reading a robot shares, and -q/-v
# --------------------------------------------------------------------------------------------
XACRO_ARG = Option(
    "xacro_arg",
    ("--xacro-arg",),
    "xacro argument NAME:=VALUE when the robot is a xacro (repeatable).",
    text,
    multiple=True,
)
PACKAGE_PATH = Option(
    "package_path",
    ("--package-path",),
    "ROS package location NAME=DIR (repeatable; a relative DIR is taken from the current "
    "directory). Give one NAME several times for a package split over several folders: "
    "package://NAME/rel is the first DIR/rel that exists, in the order given; $(find NAME) "
    "is the first DIR.",
    text,
    multiple=True,
)
ALLOW_MISSING_MESHES = Option(
    "allow_missing_meshes",
    ("--allow-missing-meshes",),
    "Mesh files that cannot be found (unknown package, no such file) are expected: "
    "leave their parts out, a warning each. Without it such a mesh stops the command "
    "(exit 2) naming the URI and the directories searched; --package-path NAME=DIR points "
    "at them.",
)
#: ``xrdf lint``'s spelling of it: lint never stops for a mesh, it skips a check.
LINT_ALLOW_MISSING_MESHES = Option(
    "allow_missing_meshes",
    ("--allow-missing-meshes",),
    "Mesh files that cannot be found (unknown package, no such file) are expected, as in a CI "
    "job without the mesh packages: the check that needs them skips their links with an info "
    "instead of a warning. --package-path NAME=DIR points at them.",
)
#: ``--urdf`` of the commands that need the robot (``report``, ``viz``, ``export curobo``,
#: ``edit``); ``lint``, ``diff`` and ``export srdf`` say what their optional one enables.
ROBOT_URDF = Option(
    "urdf",
    ("--urdf",),
    "The robot's URDF, or a xacro (expanded with --xacro-arg and --package-path).",
    path,
    typer_extra={"show_default": False},
)
#: The choice of c-space, defaults and tool frames, in ``convert`` (what it writes) and
#: ``inspect`` (what convert would pick with them).
GROUP = Option(
    "group",
    ("--group",),
    "SRDF planning group (repeatable: the c-space is the union, in the given order). Default: "
    "the group without subgroups that has the most actuated joints (a warning names it).",
    text,
    multiple=True,
)
STATE = Option(
    "state",
    ("--state",),
    "SRDF group_state for default positions (a state of any group: it sets the joints it "
    "names). Default: the group's state named home, ready, default or neutral, else its first "
    "one; without one, 0 (mid-limits when 0 is outside them).",
    text,
)
TOOL_FRAME = Option(
    "tool_frame",
    ("--tool-frame",),
    "Tool frame (repeatable; the first is the end effector). Default: the SRDF end effector's "
    "link, else a frame below the last c-space joint named like a tool (tool0, a TCP), else "
    "the chain's tip (a warning names it).",
    text,
    multiple=True,
)
JOINTS = Option(
    "joints",
    ("--joints",),
    "C-space without an SRDF group: these actuated joints in this order (comma-separated or "
    "repeated).",
    text,
    multiple=True,
)
CHAIN = Option(
    "chain",
    ("--chain",),
    "C-space without an SRDF group: the actuated joints from BASE_LINK to TIP_LINK "
    "(BASE:TIP, repeatable for several arms).",
    text,
    multiple=True,
)


def split_values(values: Sequence[str] | None) -> list[str]:
    """The values of a repeatable option that also takes comma-separated lists, in order."""
    return [v.strip() for item in values or [] for v in item.split(",") if v.strip()]


def split_names(values: Sequence[str] | None, flag: str, form: str) -> list[str]:
    """:func:`split_values` of an option whose every use must name something: ``--joints ,,``
    or ``--chain ''`` is refused (a SourceError) rather than read as the option not given."""
    for item in values or []:
        if not split_values([item]):
            raise SourceError(f"{flag} '{item}' names nothing; give {flag} {form}")
    return split_values(values)


#: What ``--target`` names, in every command that has it (``convert``, ``lint``,
#: ``export xrdf``); each adds what it does with it.
_TARGET_HELP = (
    "The program that will load the XRDF: curobo (cuRobo and Isaac ROS cuMotion; XRDF 1.0 "
    "only), cumotion (the cuMotion library) or isaac-sim (Isaac Sim's Robot Description "
    "Editor)."
)
_FORMATS_HELP = "text, json, github (GitHub Actions annotations) or sarif (a SARIF 2.1.0 log)"


def target(effect: str) -> Option:
    """``--target READER``: the one help text of the readers, then ``effect`` (what the command
    does with it, and its default)."""
    return Option(
        "target",
        ("--target",),
        f"{_TARGET_HELP} {effect}",
        text,
        typer_extra={"show_default": False, "metavar": "<curobo|cumotion|isaac-sim>"},
    )


def format_version(default: str) -> Option:
    """``--format-version 1.0|2.0`` of the commands that write an XRDF; ``default`` says what
    is written without it."""
    return Option(
        "format_version",
        ("--format-version",),
        f"XRDF version to write: 1.0 or 2.0. Default: {default}",
        text,
        typer_extra={"show_default": False, "metavar": "<1.0|2.0>"},
    )


def output(what: str) -> Option:
    """``-o/--output FILE`` of a command whose output goes to stdout without it."""
    return Option(
        "output",
        ("-o", "--output"),
        f"Write {what} to this file (atomically, never over an input); without -o, or "
        "with '-o -', to stdout.",
        path,
    )


def seed(what: str) -> Option:
    """``--seed S`` (an integer ≥ 0): the same seed and inputs give the same bytes."""
    return Option(
        "seed",
        ("--seed",),
        f"Seed of {what}: the same seed and inputs give the same output.",
        integer,
        bounds=(0, None),
    )


def configs(use: str) -> Option:
    """``--configs FILE``: configurations read by one loader
    (:func:`xrdf_tools.selfcollision.configurations.load_configurations`) in every command."""
    return Option(
        "configs",
        ("--configs",),
        f"{use} One per row: .npy, .csv/.txt (numbers, an optional header row of joint "
        "names), or .json/.yaml (lists of numbers or {joint: value} maps); rows without names "
        "in c-space order (or every actuated joint), radians and metres.",
        path,
    )


#: ``--format`` of a command whose output is a file: how its diagnostics look on stderr.
DIAGNOSTICS_FORMAT = Option(
    "output_format",
    ("--format", "-f"),
    f"Format of the diagnostics on stderr: {_FORMATS_HELP}.",
    choice(OutputFormat),
)
#: ``xrdf lint``'s: its findings are its output.
FINDINGS_FORMAT = Option(
    "output_format",
    ("--format", "-f"),
    "Format of the findings on stdout: text (path:line:col: severity rule message), json "
    "(docs/lint.md), github (GitHub Actions annotations) or sarif (a SARIF 2.1.0 log).",
    choice(OutputFormat),
)
QUIET = Option(
    "quiet",
    ("-q", "--quiet"),
    "Only errors and the output: no notes, warnings or progress bars on stderr.",
)
#: ``-v`` prints typer's timing of the whole command: left to typer.
VERBOSE = Option(
    "verbose",
    ("-v", "--verbose"),
    "Also print notes on what is read and done, and timings, on stderr.",
    fast=False,
)


# --------------------------------------------------------------------------------------------
# The fast reader
# --------------------------------------------------------------------------------------------
@dataclass
class CommandLine:
    """What :func:`parse_command_line` read: option values by name and the arguments."""

    values: dict[str, Any] = field(default_factory=dict)
    arguments: list[str] = field(default_factory=list)


class _LeaveToTyper(Exception):
    """The command line is not one read here exactly as typer reads it."""


def parse_command_line(
    table: OptionTable, words: Sequence[str], command: str
) -> CommandLine | None:
    """The options and arguments of ``words`` (after ``xrdf``) when they are ``command``'s,
    read exactly as typer would read them, else None (typer runs the command line)."""
    if not words or words[0] != command or sys.platform.startswith("win"):
        return None  # click expands wildcards on Windows: leave that to it
    if any(k.startswith("_") and k.endswith("_COMPLETE") for k in os.environ):
        return None  # shell completion
    try:
        return _read(table.by_flag(), list(words[1:]))
    except _LeaveToTyper:
        return None


def _read(flags: Mapping[str, Option], rest: list[str]) -> CommandLine:
    parsed = CommandLine()
    while rest:
        token = rest.pop(0)
        if token == "--":  # the rest are arguments
            parsed.arguments.extend(_argument(t) for t in rest)
            break
        if token.startswith("--"):
            name, eq, value = token.partition("=")
            opt = _known(flags, name)
            if opt.is_flag:
                if eq:
                    raise _LeaveToTyper
                _set(parsed, opt, True)
            else:
                _set(parsed, opt, value if eq else _pop(rest))
        elif token.startswith("-") and token != "-":
            _short(flags, token, rest, parsed)
        else:
            parsed.arguments.append(_argument(token))
    return parsed


def _known(flags: Mapping[str, Option], name: str) -> Option:
    opt = flags.get(name)
    if opt is None or not opt.fast:
        raise _LeaveToTyper
    return opt


def _argument(token: str) -> str:
    if not token:
        raise _LeaveToTyper  # an empty argument: typer says what is wrong
    return token


def _short(flags: Mapping[str, Option], token: str, rest: list[str], parsed: CommandLine) -> None:
    """A cluster of short options (``-q``, ``-f json``, ``-fjson``, ``-qf json``)."""
    for i, letter in enumerate(token[1:], start=1):
        opt = _known(flags, f"-{letter}")
        if opt.is_flag:
            _set(parsed, opt, True)
            continue
        _set(parsed, opt, token[i + 1 :] or _pop(rest))
        return


def _set(parsed: CommandLine, opt: Option, raw: str | bool) -> None:
    """Take ``raw`` for ``opt``; an empty, invalid or out-of-range value or a repeated
    single option is left to typer (it says what is wrong, or which value wins)."""
    if opt.is_flag:
        parsed.values[opt.name] = True
        return
    assert isinstance(raw, str) and opt.convert is not None
    if not raw or (not opt.multiple and opt.name in parsed.values):
        raise _LeaveToTyper
    try:
        value = opt.convert(raw)
    except ValueError:
        raise _LeaveToTyper from None
    low, high = opt.bounds
    if (low is not None and value < low) or (high is not None and value > high):
        raise _LeaveToTyper
    if opt.multiple:
        parsed.values.setdefault(opt.name, []).append(value)
    else:
        parsed.values[opt.name] = value


def _pop(rest: list[str]) -> str:
    return rest.pop(0) if rest else ""
