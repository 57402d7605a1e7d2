"""With ``--urdf``: a c-space joint whose URDF ``<limit velocity>`` is 0 (or negative).

cuRobo takes joint velocity limits from the URDF only (an XRDF has none, and a MoveIt
``joint_limits.yaml`` ``max_velocity`` never reaches it): it bounds the joint's velocity to
``[-velocity, velocity]``, so a joint whose URDF says ``velocity="0"`` cannot move and every
plan that needs it fails. Vendors ship such URDFs when the real limits live in
``joint_limits.yaml`` (AUBO's ``aubo_i5.urdf`` writes ``velocity="0"`` on every joint). Set
the joint's real velocity limit in the URDF. A ``<limit>`` without ``velocity`` is no finding
(cuRobo assumes 100 rad/s or m/s with a warning of its own).
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ..context import LintContext, Problem, Rule


def check(ctx: LintContext) -> Iterator[Problem]:
    robot = ctx.robot
    if robot is None:
        return
    for i, (n, node) in enumerate(ctx.cspace_joint_nodes()):
        j = robot.joints.get(n)
        if j is None or not j.is_actuated or j.velocity is None or j.velocity > 0:
            continue
        fname = robot.path.replace("\\", "/").rsplit("/", 1)[-1]
        where = f"{fname}:{j.line}" if j.line else fname
        yield ctx.problem(
            node,
            f"c-space joint '{n}' has <limit velocity=\"{j.velocity:g}\"> in the URDF ({where}): "
            "cuRobo reads velocity limits only from the URDF and cannot move this joint; "
            "set its real velocity limit there (a joint_limits.yaml max_velocity does not "
            "reach cuRobo)",
            f"cspace.joint_names[{i}]",
        )


RULE = Rule(
    "curobo-zero-velocity",
    Severity.WARNING,
    check,
    __doc__ or "",
    needs_urdf=True,
    reader="curobo",
)
