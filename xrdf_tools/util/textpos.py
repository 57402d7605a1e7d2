"""Positions in a text: the 1-based line and column of a character offset, and the line of an
attribute a message quotes."""

from __future__ import annotations

import re
from collections.abc import Sequence

__all__ = ["attribute_line", "line_col"]


def line_col(text: str, offset: int) -> tuple[int, int]:
    """The 1-based line and column of ``text[offset]``."""
    return text.count("\n", 0, offset) + 1, offset - (text.rfind("\n", 0, offset) + 1) + 1


_QUOTED_ATTRIBUTE = re.compile(r"(?<![\w'])([A-Za-z_][\w:.-]*)='")


def attribute_line(lines: Sequence[str], line: int, message: str) -> int:
    """The line of the attribute ``message`` quotes (``xyz='0 0 abc'``) in the start tag that
    ends on ``line`` of the text's ``lines``: an XML parser places an element at the line its
    start tag ends on, and CAD exporters (SolidWorks') write one attribute a line. ``line``
    when the message quotes no attribute or the tag's lines do not write it."""
    found = _QUOTED_ATTRIBUTE.search(message)
    if found is None:
        return line
    written = re.compile(rf"(?<![\w:.-]){re.escape(found.group(1))}\s*=")
    for n in range(min(line, len(lines)), 0, -1):  # from the tag's end back to its '<'
        if written.search(lines[n - 1]):
            return n
        if "<" in lines[n - 1]:
            break
    return line
