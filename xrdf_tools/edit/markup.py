"""Names and messages on the editor's page, as markdown that shows them and nothing more.

The page's markdown renders raw HTML unsanitised, and every name on it comes from the robot's
files: a link named ``x`<img src=x onerror=…>`` would run in the user's browser if it were
written into a code span as it is. Everything the files or the user supply goes through
:func:`code`, :func:`text` or :func:`pre`.
"""

from __future__ import annotations

import html
import string

__all__ = ["code", "pre", "text"]

_ENTITIES = {"<": "&lt;", ">": "&gt;", "&": "&amp;", '"': "&quot;", "'": "&#39;"}
_ESCAPED = {c: "\\" + c for c in string.punctuation if c not in _ENTITIES}


def text(value: object) -> str:
    """``value`` as literal markdown text: HTML's characters as entities, every other ASCII
    punctuation mark backslash-escaped (no emphasis, link, table cell or code span), line
    breaks as spaces."""
    out = []
    for c in str(value).replace("\r", " ").replace("\n", " "):
        out.append(_ENTITIES.get(c) or _ESCAPED.get(c) or c)
    return "".join(out)


def code(value: object) -> str:
    """``value`` in monospace, literally (a ``<code>`` element around :func:`text`)."""
    return f"<code>{text(value)}</code>"


def pre(value: str) -> str:
    """A block of preformatted text (a diff), literally: the text HTML-escaped in a
    ``<pre><code>`` block. The page's markdown renders a bare ``<pre>`` as a paragraph (lines
    run together); with ``<code>`` inside it keeps every line, in monospace."""
    return f"<pre><code>{html.escape(value)}</code></pre>"
