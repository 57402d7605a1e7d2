"""An acceleration or jerk limit is negative or zero.

Limits are maximum magnitudes (symmetric), so they must be > 0; a zero limit means the joint
can never move.
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ...yaml.io import YMap, YSeq
from ..context import LintContext, Problem, Rule, finite_number


def check(ctx: LintContext) -> Iterator[Problem]:
    cs = ctx.get("cspace")
    if not isinstance(cs, YMap):
        return
    joints = [n for n, _ in ctx.cspace_joint_nodes()]
    for key in ("acceleration_limits", "jerk_limits"):
        node = cs.get(key)
        if not isinstance(node, YSeq):
            continue
        for i, item in enumerate(node.items):
            v = finite_number(item)
            if v is not None and v <= 0:
                joint = f" (joint '{joints[i]}')" if i < len(joints) else ""
                yield ctx.problem(
                    item,
                    f"cspace.{key}[{i}]{joint} is {v:g}; limits are magnitudes and must be > 0",
                    f"cspace.{key}[{i}]",
                )


RULE = Rule("limits-value", Severity.ERROR, check, __doc__ or "")
