"""World and self collision use different geometry groups, which cuRobo rejects.

cuRobo's XRDF loader (and Isaac Sim's editor, which ignores the self group) need one group for
both sections. cuMotion 1.1 accepts different groups.
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ...yaml.io import YMap
from ..context import WORLD_KEYS, LintContext, Problem, Rule


def check(ctx: LintContext) -> Iterator[Problem]:
    world = next((k for k in WORLD_KEYS if isinstance(ctx.get(k), YMap)), None)
    self_c = ctx.get("self_collision")
    if world is None or not isinstance(self_c, YMap):
        return
    w_sec = ctx.get(world)
    assert isinstance(w_sec, YMap)
    w, s = ctx.group_name(w_sec), ctx.group_name(self_c)
    if w is not None and s is not None and w != s:
        yield ctx.problem(
            self_c.get("geometry"),
            f"{world} uses group '{w}' but self_collision uses '{s}': cuRobo's loader raises "
            "an error (it supports one group for both)",
            "self_collision.geometry",
        )


RULE = Rule("curobo-different-groups", Severity.WARNING, check, __doc__ or "", reader="curobo")
