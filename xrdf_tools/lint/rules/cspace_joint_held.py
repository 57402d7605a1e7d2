"""With ``--urdf``: a revolute or prismatic c-space joint whose URDF limits are equal
(``lower="0" upper="0"``).

Such a joint cannot move: every reader bounds it to that one position, so the c-space has a
coordinate no plan can use, and the arm plans as if that joint were welded. CAD exporters
write ``<limit lower="0" upper="0">`` for limits never set (SolidWorks' exporter does), and a
MoveIt configuration made from that URDF puts the joint in its arm group. Give the joint its
real limits in the URDF, or leave it out of the c-space (a joint held on purpose).

An error with ``--target curobo``: cuRobo's loader raises on an empty position range of a
joint it plans for ("lower limits must be less than upper limits"), so ``xrdf export curobo``
stops on it too.
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ..context import LintContext, Problem, Rule
from ._joints import cspace_joints_where, joint_at, written_in


def check(ctx: LintContext) -> Iterator[Problem]:
    found = cspace_joints_where(ctx, lambda j: j.is_held)
    if not found or ctx.robot is None:
        return
    names = ", ".join(f"{joint_at(j, ctx.robot)} [{j.lower:g}, {j.upper:g}]" for *_, j in found)
    what = f"c-space joint {names} is" if len(found) == 1 else f"c-space joints {names} are"
    index, node, _ = found[0]
    where = written_in([j for *_, j in found], ctx.robot)
    them = "it" if len(found) == 1 else "them"
    curobo = ctx.target == "curobo"
    yield ctx.problem(
        node,
        f"{what} held still by equal lower and upper limits in {where}: no plan "
        f"can move {them} (a CAD exporter writes 0 0 for limits never set)"
        + (f"; cuRobo's loader raises on {them} (an empty range)" if curobo else "")
        + "; give the URDF the real limits, or leave such a joint out of the c-space",
        f"cspace.joint_names[{index}]",
        Severity.ERROR if curobo else None,
    )


RULE = Rule(
    "cspace-joint-held",
    Severity.WARNING,
    check,
    __doc__ or "",
    needs_urdf=True,
)
