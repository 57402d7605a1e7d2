"""xacro arguments: those a command line gives that the expansion never reads, and those the
files need that nobody set.

xacro ignores a ``name:=value`` mapping that no ``<xacro:arg>`` declares and no ``$(arg)``
reads, so a misspelt ``--xacro-arg ee_typ:=dd`` silently expands the default robot.
:class:`ReadArgs` is the mapping xacro is given: it records every name xacro looks up (a
declaration asks whether the name is given, ``$(arg)`` and ``xacro.arg()`` read it), and
:func:`unread_arg_warnings` names each given argument xacro never asked for.

xacro stops at the first ``$(arg x)`` that has no value; a robot whose launch file passes six
arguments (PAL's Talos: ``enable_crane``, ``foot_collision``, ``head_type``, ...) would take six
runs to find them one by one. :func:`unset_args` reads the top file and the files its
``<xacro:include>`` tags name (a ``$(find pkg)`` resolved as the expansion does, other
substitutions skipped) and lists every argument used without a ``<xacro:arg>`` default;
:func:`unknown_packages` lists, from the same files, every ``$(find pkg)`` package that cannot
be found (Reachy 2's description needs four packages besides its own).
"""

from __future__ import annotations

import re
from collections.abc import Collection, Iterator, Mapping
from pathlib import Path
from typing import Any

from ..diagnostics import Diagnostic, Severity
from ..util.errors import XrdfToolsError, did_you_mean, shown_text
from ..util.fileio import read_input_bytes
from ..util.text import name_list
from .packages import PackageResolver

__all__ = [
    "RULE_UNREAD_ARG",
    "ReadArgs",
    "args_named",
    "unknown_packages",
    "unread_arg_warnings",
    "unset_args",
]

RULE_UNREAD_ARG = "xacro-arg-unread"


class ReadArgs(dict[str, str]):
    """A ``dict`` of xacro arguments that remembers the names looked up in it."""

    def __init__(self, given: Mapping[str, str]) -> None:
        super().__init__(given)
        self.asked: set[str] = set()

    def __contains__(self, key: object) -> bool:
        if isinstance(key, str):
            self.asked.add(key)
        return super().__contains__(key)

    def __getitem__(self, key: str) -> str:
        self.asked.add(key)
        return super().__getitem__(key)

    def get(self, key: str, default: Any = None) -> Any:
        self.asked.add(key)
        return super().get(key, default)


def unread_arg_warnings(path: str, given: Mapping[str, str], read: ReadArgs) -> list[Diagnostic]:
    """A warning per argument of ``given`` that the expansion never looked up in ``read``."""
    known = sorted(read.asked)
    shown = name_list(known)
    return [
        Diagnostic(
            path,
            None,
            None,
            RULE_UNREAD_ARG,
            Severity.WARNING,
            f"--xacro-arg {name}:={shown_text(value)}: no <xacro:arg> or $(arg) of the expansion "
            f"reads '{name}', so it changes nothing"
            + (f" (arguments read: {shown})" if known else "")
            + did_you_mean(name, known),
            "",
        )
        for name, value in given.items()
        if name not in read.asked
    ]


_ARG_USE = re.compile(r"\$\(arg\s+([^\s)]+)\s*\)")
_DECLARED = re.compile(r"<xacro:arg\b[^>]*?\bname\s*=\s*[\"']([^\"']+)[\"']")
_DEFAULT = re.compile(r"<xacro:arg\b[^>]*?\bname\s*=\s*[\"']([^\"']+)[\"'][^>]*?\bdefault\s*=")
_INCLUDE = re.compile(r"<xacro:include\b[^>]*?\bfilename\s*=\s*([\"'])(.*?)\1", re.DOTALL)
_FIND = re.compile(r"\$\(find\s+([^\s)]+)\s*\)")
#: Files read at most (a robot's description is tens of files).
_MAX_FILES = 200


def unset_args(top: Path, resolver: PackageResolver, given: Collection[str]) -> list[str]:
    """Arguments the files use in ``$(arg x)`` with no ``<xacro:arg>`` default and not in
    ``given``: the top file's first, then each include's (breadth first)."""
    used: dict[str, None] = {}
    defaults: set[str] = set()
    for text in _texts(top, resolver):
        used.update(dict.fromkeys(_ARG_USE.findall(text)))
        defaults.update(_DEFAULT.findall(text))
    return [a for a in used if a not in defaults and a not in given]


def args_named(top: Path, resolver: PackageResolver) -> frozenset[str]:
    """The arguments the files declare (``<xacro:arg>``) or use (``$(arg x)``): those a
    ``--xacro-arg`` given for them may change, read from the text without expanding it."""
    named: set[str] = set()
    for text in _texts(top, resolver):
        named.update(_ARG_USE.findall(text), _DECLARED.findall(text))
    return frozenset(named)


def unknown_packages(top: Path, resolver: PackageResolver) -> list[str]:
    """The packages the files name in ``$(find pkg)`` that ``resolver`` cannot find, in the
    order they are first named (the top file's first, then each include's that can be read:
    an unknown package's own files cannot)."""
    named: dict[str, None] = {}
    for text in _texts(top, resolver):
        named.update(dict.fromkeys(_FIND.findall(text)))
    out = []
    for name in named:
        try:
            resolver.find(name)
        except XrdfToolsError:
            out.append(name)
    return out


def _texts(top: Path, resolver: PackageResolver) -> Iterator[str]:
    """The text of the top file, then of each file its includes name (breadth first), without
    comments; a file that cannot be read or found is passed over."""
    queue, seen = [top], {top}
    while queue and len(seen) <= _MAX_FILES:
        path = queue.pop(0)
        try:  # the guarded reader: a regular file within the size limit (never /dev/zero)
            text = read_input_bytes(path, what="xacro file").decode("utf-8")
        except (XrdfToolsError, UnicodeDecodeError):
            continue
        text = re.sub(r"<!--.*?-->", "", text, flags=re.DOTALL)
        yield text
        for m in _INCLUDE.finditer(text):
            if (child := _included(m.group(2), path, resolver)) is not None and child not in seen:
                seen.add(child)
                queue.append(child)


def _included(name: str, at: Path, resolver: PackageResolver) -> Path | None:
    """The file an include names: ``$(find pkg)`` resolved, relative to the including file;
    None when it holds another substitution or an expression, or the package is unknown."""
    try:
        name = _FIND.sub(lambda m: str(resolver.find(m.group(1))), name)
    except XrdfToolsError:
        return None
    if "$(" in name or "${" in name:
        return None
    path = Path(name)
    return path if path.is_absolute() else at.parent / path
