"""Geometry groups clone each other in a cycle (``a`` clones ``b`` clones ``a``, or a group
clones itself).

Clones are resolved transitively, so a cycle has no finite result.
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ...yaml.io import YMap
from ..context import LintContext, Problem, Rule


def check(ctx: LintContext) -> Iterator[Problem]:
    for gname in sorted(ctx.cyclic_groups):
        gnode = ctx.groups[gname]
        node = gnode.key_node("clone") if isinstance(gnode, YMap) else gnode
        loop = [c for c, _ in ctx.clones_of(gname) if c in ctx.cyclic_groups]
        yield ctx.problem(
            node,
            f"geometry group '{gname}' is part of a clone cycle (it clones "
            f"{', '.join(repr(c) for c in loop)}, which lead back to it)",
            f"geometry.{gname}.clone",
        )


RULE = Rule("clone-cycle", Severity.ERROR, check, __doc__ or "")
