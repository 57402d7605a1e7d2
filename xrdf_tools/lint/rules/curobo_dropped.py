"""cuRobo's XRDF loader silently drops this XRDF 2.0 construct.

cuRobo reads each group's ``spheres`` only: a group built with ``clone`` loses the cloned
spheres, and ``remove_mimic_attributes`` is ignored (the joint stays a mimic follower). The file
is valid for cuMotion; disable this rule if cuRobo is not a consumer.
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ...yaml.io import YMap, YSeq
from ..context import LintContext, Problem, Rule


def check(ctx: LintContext) -> Iterator[Problem]:
    for gname, gnode in ctx.groups.items():
        clone = gnode.get("clone") if isinstance(gnode, YMap) else None
        if isinstance(clone, YSeq) and len(clone):
            yield ctx.problem(
                gnode.key_node("clone") if isinstance(gnode, YMap) else clone,
                f"cuRobo ignores 'clone': group '{gname}' would lose the spheres of "
                f"{len(clone)} cloned group{'s' if len(clone) != 1 else ''} "
                "(xrdf export xrdf FILE --target curobo writes 1.0 with them flattened)",
                f"geometry.{gname}.clone",
            )
    for i, kind, knode, _ in ctx.modifier_items:
        if kind == "remove_mimic_attributes":
            yield ctx.problem(
                knode,
                "cuRobo ignores 'remove_mimic_attributes': the joint stays a mimic follower",
                f"modifiers[{i}]",
            )


RULE = Rule("curobo-dropped", Severity.WARNING, check, __doc__ or "", reader="curobo")
