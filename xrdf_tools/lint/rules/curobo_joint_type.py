"""An ``add_frame`` joint type that cuRobo's loader rejects: missing, or not spelled ``FIXED``.

cuRobo raises a KeyError when ``joint_type`` is absent and accepts only the uppercase
``FIXED`` (its own 2.0 writer emits ``fixed``, which its reader then rejects). cuMotion accepts
either case.
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ...yaml.io import YMap
from ..context import LintContext, Problem, Rule, name


def check(ctx: LintContext) -> Iterator[Problem]:
    for i, kind, knode, v in ctx.modifier_items:
        if kind != "add_frame" or not isinstance(v, YMap):
            continue
        jt = v.get("joint_type")
        n = name(jt)
        if "joint_type" not in v:
            yield ctx.problem(
                knode,
                "add_frame has no joint_type; cuRobo's loader requires 'joint_type: FIXED'",
                f"modifiers[{i}].add_frame",
            )
        elif n is not None and n != "FIXED" and n.lower() == "fixed":
            yield ctx.problem(
                jt,
                f"joint_type '{n}': cuRobo's loader accepts only 'FIXED'",
                f"modifiers[{i}].add_frame.joint_type",
            )


RULE = Rule("curobo-joint-type", Severity.WARNING, check, __doc__ or "", reader="curobo")
