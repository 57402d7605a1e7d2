"""``format_version`` is written as a string (``"2.0"``).

cuRobo compares the version with a number and raises a TypeError on a string; PyYAML-based
tools read it as text. Write ``format_version: 2.0`` unquoted.
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ...yaml.io import YScalar
from ..context import LintContext, Problem, Rule


def check(ctx: LintContext) -> Iterator[Problem]:
    node = ctx.get("format_version")
    if ctx.version is not None and isinstance(node, YScalar) and isinstance(node.value, str):
        yield ctx.problem(
            node,
            f"format_version is the string '{node.value}'; cuRobo needs a number: write "
            f"format_version: {ctx.version}",
            "format_version",
        )


RULE = Rule("curobo-quoted-version", Severity.WARNING, check, __doc__ or "", reader="curobo")
