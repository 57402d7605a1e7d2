"""With ``--urdf``: a default joint position names a joint that does not exist, cannot move
(fixed), is a mimic follower, or lies outside the joint's URDF limits.

Default positions may also be given for movable joints outside c-space (auxiliary
coordinates held at that value); the same checks apply. Continuous joints have no limits.
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ..context import LintContext, Problem, Rule, finite_number
from ._joints import joint_problem


def check(ctx: LintContext) -> Iterator[Problem]:
    kin = ctx.kin
    if kin is None:
        return
    for n, knode, vnode in ctx.default_position_nodes():
        kp = f"default_joint_positions.{n}"
        msg = joint_problem(ctx, n, "default position for")
        if msg:
            yield ctx.problem(knode, msg, kp)
            continue
        v = finite_number(vnode)
        outside = "" if v is None else kin.outside_limits(n, v)
        if outside:
            yield ctx.problem(vnode, f"default position {v:g} of '{n}' {outside}", kp)


RULE = Rule("default-position", Severity.ERROR, check, __doc__ or "", needs_urdf=True)
