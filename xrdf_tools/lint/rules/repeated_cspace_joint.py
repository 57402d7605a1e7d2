"""A joint appears more than once in ``cspace.joint_names``.

Each c-space coordinate is one joint; a repeated name makes the c-space vector ambiguous.
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ..context import LintContext, Problem, Rule
from ._repeats import repeats


def check(ctx: LintContext) -> Iterator[Problem]:
    named = ((n, (i, node)) for i, (n, node) in enumerate(ctx.cspace_joint_nodes()))
    for n, (i, node), (first, _) in repeats(named):
        yield ctx.problem(
            node,
            f"joint '{n}' is already c-space coordinate {first}; each joint may appear once",
            f"cspace.joint_names[{i}]",
        )


RULE = Rule("repeated-cspace-joint", Severity.ERROR, check, __doc__ or "")
