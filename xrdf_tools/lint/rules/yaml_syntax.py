"""The file is not valid YAML.

A syntax error (bad indentation, an unclosed bracket, a tab used for indentation, a second
document) stops every other check: the error points at the line and column where the YAML parser
gave up and, for the usual hand edits, says what to check (the indentation, the tab to replace,
the line of the ``[`` left open or of the key without ``:``). An XML file (a URDF or SRDF given
where the XRDF goes) is named as such at 1:1. Files must also be UTF-8 text.
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ...yaml.hints import XML_NOT_YAML
from ..context import LintContext, Problem, Rule
from .format_key import XML_GIVEN


def check(ctx: LintContext) -> Iterator[Problem]:
    err = ctx.syntax_error
    if err is not None:
        yield Problem(err.line, err.col, XML_GIVEN if err.message == XML_NOT_YAML else err.message)


RULE = Rule("yaml-syntax", Severity.ERROR, check, __doc__ or "")
