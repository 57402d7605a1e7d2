"""A collision section or a ``clone`` names a geometry group that is not defined.

``world_collision.geometry`` (``collision`` in 1.0), ``self_collision.geometry`` and every
entry of a group's ``clone`` list must name a group under the top-level ``geometry`` key, which
must therefore exist whenever a collision section does.
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ...util.errors import did_you_mean
from ..context import LintContext, Problem, Rule


def _hint(missing: str, ctx: LintContext) -> str:
    defined = list(ctx.groups)
    return did_you_mean(missing, defined) or (
        f" (defined: {', '.join(defined)})" if defined else " (no group is defined)"
    )


def check(ctx: LintContext) -> Iterator[Problem]:
    if ctx.top is None:
        return
    for key, section in ctx.collision_sections():
        g = ctx.group_name(section)
        if g is None:
            continue
        node = section.get("geometry")
        if not ctx.has("geometry"):
            yield ctx.problem(
                node,
                f"{key} uses geometry group '{g}', but the file has no 'geometry' section",
                f"{key}.geometry",
            )
        elif g not in ctx.groups:
            yield ctx.problem(
                node, f"geometry group '{g}' is not defined" + _hint(g, ctx), f"{key}.geometry"
            )
    for gname in ctx.groups:
        for child, node in ctx.clones_of(gname):
            if child not in ctx.groups:
                yield ctx.problem(
                    node,
                    f"geometry group '{gname}' clones '{child}', which is not defined"
                    + _hint(child, ctx),
                    f"geometry.{gname}.clone",
                )


RULE = Rule("undefined-group", Severity.ERROR, check, __doc__ or "")
