"""Names and messages on the editor's page: markdown that shows them literally."""

from __future__ import annotations

import html
import re

from xrdf_tools.edit.markup import code, pre, text

HOSTILE = [
    'x`<img src=x onerror="alert(1)">`y',
    "<script>alert(1)</script>",
    "a | b",
    "**bold** _em_ [link](javascript:alert(1))",
    "line\nbreak",
    "```\n<b>fence</b>\n```",
]


def _unescaped(md: str) -> str:
    """What a markdown renderer shows for our escaped text: backslash escapes and entities
    undone (nothing else of markdown can be left in it)."""
    return html.unescape(re.sub(r"\\(.)", r"\1", md))


def test_text_has_no_markup_left_and_reads_back_as_the_value() -> None:
    for value in HOSTILE:
        md = text(value)
        assert "<" not in md and ">" not in md and "\n" not in md
        assert not re.search(r"(?<!\\)[`*_|\[\]()]", md), md
        assert _unescaped(md) == value.replace("\n", " ")


def test_code_wraps_escaped_text() -> None:
    md = code(HOSTILE[0])
    assert md.startswith("<code>") and md.endswith("</code>")
    assert _unescaped(md[len("<code>") : -len("</code>")]) == HOSTILE[0]


def test_pre_keeps_lines_and_escapes_html() -> None:
    md = pre(HOSTILE[5])
    head, tail = "<pre><code>", "</code></pre>"
    assert md.startswith(head) and md.endswith(tail)
    assert "<b>" not in md and html.unescape(md[len(head) : -len(tail)]) == HOSTILE[5]
