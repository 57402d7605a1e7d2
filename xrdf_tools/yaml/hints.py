"""What to do about a YAML syntax error: the fix a person editing a file by hand needs, added
to libyaml's own words (which stay, as people search for them).

Hand edits break YAML in a few ways: a tab, a line indented one space off, a missing ``:``,
an unclosed ``[``, a ``: `` inside a value. libyaml names the token it did not expect
(``expected <block end>, but found '<block sequence start>'``); :func:`syntax_hint` says
what that usually means. A URDF or SRDF given where YAML is read is named as such
(:func:`looks_like_xml`), not reported as the YAML error its text happens to make.
"""

from __future__ import annotations

import yaml

#: An XML file where YAML is read: a URDF or SRDF given in place of an XRDF or a YAML config
#: (whether its text happens to be a YAML error or a valid YAML string).
XML_NOT_YAML = "an XML document (a URDF, xacro or SRDF?), not YAML"

_INDENT = "check the indentation of this line against the lines above (spaces only)"

#: libyaml's problem (its start) → what to check.
_HINTS = (
    ("found character '\\t'", "YAML indents with spaces: replace the tab"),
    ("found a tab character", "YAML indents with spaces: replace the tab"),
    ("expected <block end>", _INDENT),
    ("did not find expected key", _INDENT),
    ("did not find expected '-' indicator", _INDENT),
    (
        "mapping values are not allowed here",
        "check the indentation of this line and the one above, or quote a value that contains ': '",
    ),
)

#: The context libyaml names for an unclosed bracket → the bracket.
_OPENED = {"while parsing a flow sequence": "[", "while parsing a flow mapping": "{"}


def looks_like_xml(text: object) -> bool:
    """``text`` starts (after a byte-order mark and blank space) with ``<``: XML, not YAML."""
    if isinstance(text, bytes):
        text = text[:256].decode("utf-8", "replace")
    return isinstance(text, str) and text[:256].lstrip("\ufeff \t\r\n").startswith("<")


def syntax_hint(exc: yaml.MarkedYAMLError) -> str:
    """What to check for libyaml's error ``exc``: '' when it has no usual cause."""
    problem = exc.problem or ""
    opened = _OPENED.get(exc.context or "")
    mark = exc.context_mark
    if opened and mark is not None and problem.startswith("expected ','"):
        return f"the '{opened}' on line {mark.line + 1}, column {mark.column + 1} is not closed"
    if problem.startswith("could not find expected ':'") and mark is not None:
        return f"the key that starts on line {mark.line + 1} needs ':' and a space after it"
    return next((hint for start, hint in _HINTS if problem.startswith(start)), "")
