"""With ``--urdf``: a c-space joint whose URDF ``<limit velocity>`` or ``<limit effort>`` is 0
(or negative).

cuRobo takes joint velocity and effort limits from the URDF only (an XRDF has none, and a
MoveIt ``joint_limits.yaml`` ``max_velocity`` never reaches it): it bounds the joint to
``[-velocity, velocity]`` and ``[-effort, effort]``, and its loader raises ("lower ... limits
must be less than upper ... limits") when a range is empty for a joint it plans for. Vendors
ship such URDFs when the real limits live in ``joint_limits.yaml`` (AUBO's ``aubo_i5.urdf``
writes ``velocity="0"`` on every joint) or in the drives (``effort="0"``). Set the joint's
real limits in the URDF. A ``<limit>`` without ``velocity`` is no finding (cuRobo assumes
100 rad/s or m/s with a warning of its own).
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING

from ...diagnostics import Severity
from ..context import LintContext, Problem, Rule
from ._joints import cspace_joints_where, joint_at, written_in

if TYPE_CHECKING:  # numpy: lint without --urdf stays light
    from ...robot.urdf_joints import JointInfo


def _empty(j: JointInfo) -> tuple[str, ...]:
    """The ``<limit>`` attributes of ``j`` whose range is empty, as written (``velocity="0"``)."""
    if not j.is_actuated:
        return ()
    return tuple(
        f'{name}="{value:g}"'
        for name, value in (("velocity", j.velocity), ("effort", j.effort))
        if value is not None and value <= 0
    )


def check(ctx: LintContext) -> Iterator[Problem]:
    found = cspace_joints_where(ctx, lambda j: bool(_empty(j)))
    if not found or ctx.robot is None:
        return
    written = {_empty(j) for *_, j in found}
    limit = " ".join(written.pop()) if len(written) == 1 else "velocity or effort <= 0"
    names = ", ".join(joint_at(j, ctx.robot) for *_, j in found)
    if len(found) == 1:
        what, them = f"c-space joint {names} has", "it"
    else:
        what, them = f"{len(found)} c-space joints ({names}) have", "them"
    index, node, _ = found[0]
    where = written_in([j for *_, j in found], ctx.robot)
    yield ctx.problem(
        node,
        f"{what} <limit {limit}> in {where}: cuRobo reads velocity and effort "
        f"limits only from the URDF and its loader raises on {them} (an empty range); set the "
        "real limits there (a joint_limits.yaml max_velocity does not reach cuRobo)",
        f"cspace.joint_names[{index}]",
    )


RULE = Rule(
    "curobo-zero-velocity",
    Severity.WARNING,
    check,
    __doc__ or "",
    needs_urdf=True,
    reader="curobo",
)
