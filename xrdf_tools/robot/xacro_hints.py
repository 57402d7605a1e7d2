"""Hints added to a xacro error, found by searching the xacro files for what the message
names: a call of a macro with a parameter it lacks, a ``<property>`` or ``<macro>`` written
without the ``xacro:`` prefix (which xacro 2 no longer reads), an argument whose default is
declared below its first use."""

from __future__ import annotations

import re
from collections.abc import Sequence

from ..util.fileio import reread_text
from ..util.textpos import line_col
from .xacro_culprits import UNDEFINED_ARG

__all__ = ["bad_macro_call", "late_default_hint", "unprefixed_hint"]


def late_default_hint(message: str, path: str, line: int | None) -> str:
    """What to know when the undefined ``$(arg x)`` of ``message`` has a ``<xacro:arg>``
    default below its use at ``line`` (Flexiv's ``<robot name="$(arg name)">`` with the
    default inside ``<robot>``): xacro has not read it yet, the launch file passes it."""
    m = UNDEFINED_ARG.search(message)
    if m is None or line is None:
        return ""
    tag = re.compile(rf"<xacro:arg\s[^>]*name\s*=\s*[\"']{re.escape(m.group(1))}[\"'][^>]*default=")
    if (hit := _first_match(tag, [path])) is None:
        return ""
    _, text, found = hit
    declared, _ = line_col(text, found.start())
    if declared <= line:
        return ""
    return (
        f"; line {declared} declares a default for it, but xacro evaluates it here before "
        "reading that declaration"
    )


#: xacro's message for a macro call with an attribute the macro has no parameter for.
_INVALID_PARAMETER = re.compile(r'Invalid parameter "([^"]+)"')


def bad_macro_call(
    message: str, macro: str | None, files: Sequence[str]
) -> tuple[str, str, int, int] | None:
    """The message and position of a call of ``macro`` that passes a parameter the macro
    lacks: the first ``<xacro:MACRO …>`` tag in ``files`` that sets it (a call inside another
    macro's body, which the generic search would look for in the top file)."""
    m = _INVALID_PARAMETER.search(message)
    if m is None or macro is None:
        return None
    call = re.compile(rf"<xacro:{re.escape(macro)}\b[^>]*?\s{re.escape(m.group(1))}\s*=")
    if (hit := _first_match(call, files)) is None:
        return None
    path, text, found = hit
    line, col = line_col(text, found.start())
    why = f" in a call of macro '{macro}', which has no parameter '{m.group(1)}'"
    return message + why, path, line, col


def _first_match(
    pattern: re.Pattern[str], files: Sequence[str]
) -> tuple[str, str, re.Match[str]] | None:
    """The first of ``files`` (unreadable ones skipped) whose text ``pattern`` matches: its
    path, its text and the match."""
    for path in dict.fromkeys(files):
        text = reread_text(path)
        if text is None:
            continue
        if (found := pattern.search(text)) is not None:
            return path, text, found
    return None


#: ``name 'x' is not defined``: a property xacro never defined.
_UNDEFINED_NAME = re.compile(r"name '(\w+)' is not defined")
#: ``unknown macro name: xacro:m``: a macro xacro never defined.
_UNKNOWN_MACRO = re.compile(r"unknown macro name: (?:xacro:)?([\w.]+)")


def unprefixed_hint(message: str, files: Sequence[str]) -> str:
    """What to change when the undefined name of ``message`` is defined by a ``<property>``,
    or is a parameter of a ``<macro>``, written without the ``xacro:`` prefix, which ROS 1's
    xacro read (with a deprecation warning) and xacro 2 ignores (its body is then plain XML
    whose expressions name parameters nothing defines); likewise an unknown macro defined by
    an unprefixed ``<macro>``, or never read because its file is included by an unprefixed
    ``<include>`` (the Fuerte-era youBot description)."""
    if (m := _UNDEFINED_NAME.search(message)) is not None:
        name = re.escape(m.group(1))
        tags = [
            (
                rf"<property\s[^>]*name\s*=\s*[\"']{name}[\"']",
                "defines it by <property>",
                "property",
            ),
            (
                rf"<macro\s[^>]*params\s*=\s*[\"'][^\"']*\b{name}\b",
                "takes it as a <macro> parameter",
                "macro",
            ),
        ]
    elif (m := _UNKNOWN_MACRO.search(message)) is not None:
        name = re.escape(m.group(1))
        tags = [
            (rf"<macro\s[^>]*name\s*=\s*[\"']{name}[\"']", "defines it by <macro>", "macro"),
            (r"<include\s[^>]*filename\s*=", "includes a file by <include>", "include"),
        ]
    else:
        return ""
    for tag, what, kind in tags:
        if (hit := _first_match(re.compile(tag), files)) is not None:
            path, text, found = hit
            line, _ = line_col(text, found.start())
            return (
                f" ({path}:{line} {what} without the xacro: prefix, which xacro 2 no longer "
                f"reads: write <xacro:{kind}> there)"
            )
    return ""
