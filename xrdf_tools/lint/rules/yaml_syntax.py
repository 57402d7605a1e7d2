"""The file is not valid YAML.

A syntax error (bad indentation, an unclosed bracket, a tab used for indentation, a second
document) stops every other check: the error points at the line and column where the YAML parser
gave up and, for the usual hand edits, says what to check (the indentation, the tab to replace,
the line of the ``[`` left open or of the key without ``:``). Files must also be UTF-8 text.
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ..context import LintContext, Problem, Rule


def check(ctx: LintContext) -> Iterator[Problem]:
    err = ctx.syntax_error
    if err is not None:
        yield Problem(err.line, err.col, err.message)


RULE = Rule("yaml-syntax", Severity.ERROR, check, __doc__ or "")
