"""With ``--urdf``: a c-space joint whose URDF ``<limit velocity>`` is 0 (or negative).

cuRobo takes joint velocity limits from the URDF only (an XRDF has none, and a MoveIt
``joint_limits.yaml`` ``max_velocity`` never reaches it): it bounds the joint's velocity to
``[-velocity, velocity]``, and its loader raises ("lower velocity limits must be less than
upper velocity limits") when that range is empty for a joint it plans for. Vendors ship such
URDFs when the real limits live in ``joint_limits.yaml`` (AUBO's ``aubo_i5.urdf`` writes
``velocity="0"`` on every joint). Set the joint's real velocity limit in the URDF. A
``<limit>`` without ``velocity`` is no finding (cuRobo assumes 100 rad/s or m/s with a warning
of its own).
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING

from ...diagnostics import Severity
from ..context import LintContext, Problem, Rule
from ._joints import cspace_joints_where, joint_at

if TYPE_CHECKING:  # numpy: lint without --urdf stays light
    from ...robot.urdf_joints import JointInfo


def _still(j: JointInfo) -> bool:
    return j.is_actuated and j.velocity is not None and j.velocity <= 0


def check(ctx: LintContext) -> Iterator[Problem]:
    found = cspace_joints_where(ctx, _still)
    if not found or ctx.robot is None:
        return
    values = {j.velocity for *_, j in found}
    limit = f'velocity="{values.pop():g}"' if len(values) == 1 else "velocity <= 0"
    names = ", ".join(joint_at(j) for *_, j in found)
    if len(found) == 1:
        what, them = f"c-space joint {names} has", "it"
    else:
        what, them = f"{len(found)} c-space joints ({names}) have", "them"
    index, node, _ = found[0]
    yield ctx.problem(
        node,
        f"{what} <limit {limit}> in {ctx.robot.file_name}: cuRobo reads velocity limits only "
        f"from the URDF and its loader raises on {them} (an empty velocity range); set the real "
        "limits there (a joint_limits.yaml max_velocity does not reach cuRobo)",
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
