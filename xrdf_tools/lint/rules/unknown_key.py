"""A key that no XRDF version defines (often a typo).

cuMotion ignores or rejects unknown keys depending on the section, so a misspelt
``buffer_distances`` or ``jerk_limit`` silently loses its content. The message suggests the
closest valid key. Keys valid in the other XRDF version are reported by ``version-key``.
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ...util.errors import did_you_mean
from ..context import LintContext, Problem, Rule
from ..schema import walk


def check(ctx: LintContext) -> Iterator[Problem]:
    if ctx.top is None:
        return
    for ev in walk(ctx.top):
        if ev.kind == "unknown":
            hint = did_you_mean(ev.key, ev.choices) or f"; valid: {', '.join(ev.choices)}"
            yield ctx.problem(ev.node, ev.message + hint, ev.key_path)


RULE = Rule("unknown-key", Severity.WARNING, check, __doc__ or "")
