"""Where in the xacro files the name or expression a xacro error quotes is written: xacro keeps
no positions, so its messages are located by searching the files for what they quote."""

from __future__ import annotations

import re
from collections.abc import Sequence

from ..util.fileio import reread_text
from ..util.textpos import line_col

#: ``$(arg x)`` of an ``<xacro:arg>`` without a default, not given.
UNDEFINED_ARG = re.compile(r"Undefined substitution argument ([^\s;()]+)")
#: What xacro's messages name, and the text that names it in the file:
#: (pattern of the message, template of the source text).
_CULPRITS: tuple[tuple[re.Pattern[str], tuple[str, ...]], ...] = (
    (re.compile(r"when evaluating expression '([^']*)'"), ("${{{}}}", "${{{}")),
    (re.compile(r"unknown macro name: (xacro:\S+)"), ("<{}",)),
    (re.compile(r"Property names must be valid python identifiers:\s*(.*)$"), ('name="{}"',)),
    (UNDEFINED_ARG, ("$(arg {}",)),
    (re.compile(r"Unknown substitution command \[([^\]]*)\]"), ("$({})", "$({}")),
    (re.compile(r"may only specify one arg \[([^\]]*)\]"), ("$({})", "$({}")),
    (re.compile(r"cannot find ROS package '([^']+)'"), ("$(find {})", "$(find {}")),
    (re.compile(r'Invalid parameter "([^"]+)"'), ('{}="',)),
    (re.compile(r"invalid expression: (.+)$"), ("{}",)),
    (re.compile(r"Using (\w+)\(\) directly is deprecated"), ("${{{}(",)),
)
#: "xacro:macro: missing attribute 'name'": the first ``<xacro:macro>`` tag without it.
_MISSING_ATTRIBUTE = re.compile(r"^xacro failed: (xacro:\w+): missing attribute '(\w+)'")
#: xacro's warning on an include with a body (Sawyer's ``<xacro:arg>`` children): the first
#: ``<xacro:include>`` whose body holds an element.
_INCLUDE_BODY = "Child elements of a <xacro:include> tag are ignored"
_INCLUDE_TAG = re.compile(r"<xacro:include\b[^>]*>")
_INCLUDE_END = re.compile(r"</xacro:include\s*>")
_COMMENT = re.compile(r"<!--.*?-->", re.DOTALL)


def culprit_in(paths: Sequence[str], message: str) -> tuple[str, int | None, int | None]:
    """The first of ``paths`` that writes what ``message`` quotes, and where (the first path,
    without a position, when none does)."""
    for path in dict.fromkeys(paths):
        line, col = _find_culprit(path, message)
        if line is not None:
            return path, line, col
    return paths[0], None, None


def _find_culprit(path: str, message: str) -> tuple[int | None, int | None]:
    """Where in ``path`` the name or expression a xacro error quotes is first written (xacro
    itself keeps no positions); ``(None, None)`` when it is not found."""
    text = reread_text(path)
    if text is None:  # a file that cannot be read again: no position
        return None, None
    # xacro works in document order: the first use failed first; the file may write the
    # quoted text with XML escapes ('&' as '&amp;')
    at = next((i for n in _needles(message) if (i := text.find(n)) >= 0), -1)
    if (m := _MISSING_ATTRIBUTE.search(message)) is not None:
        tags = re.finditer(rf"<{m.group(1)}\b[^>]*>", text)
        at = next((t.start() for t in tags if f"{m.group(2)}=" not in t.group(0)), -1)
    if _INCLUDE_BODY in message:
        at = _include_with_body(text)
    if at < 0:
        return None, None
    return line_col(text, at)


def _include_with_body(text: str) -> int:
    """Where the first ``<xacro:include>`` with an element in its body starts (-1: none)."""
    for tag in _INCLUDE_TAG.finditer(text):
        if tag.group(0).endswith("/>"):
            continue
        end = _INCLUDE_END.search(text, tag.end())
        body = text[tag.end() : end.start() if end is not None else len(text)]
        if re.search(r"<[^/!?]", _COMMENT.sub("", body)):
            return tag.start()
    return -1


def _needles(message: str) -> list[str]:
    """The texts that may write what ``message`` quotes, most specific first."""
    from xml.sax.saxutils import escape  # an error's path only: it imports urllib and http

    for pattern, templates in _CULPRITS:
        if (m := pattern.search(message)) is not None:
            raw = [t.format(m.group(1)) for t in templates]
            return [*raw, *(escape(n) for n in raw)]
    return []
