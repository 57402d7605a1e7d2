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
from ...yaml.io import YNode
from ..context import LintContext, Problem, Rule


def check(ctx: LintContext) -> Iterator[Problem]:
    robot = ctx.robot
    if robot is None:
        return
    found: list[tuple[int, YNode, str, float]] = []
    for i, (n, node) in enumerate(ctx.cspace_joint_nodes()):
        j = robot.joints.get(n)
        if j is None or not j.is_actuated or j.velocity is None or j.velocity > 0:
            continue
        found.append((i, node, f"'{n}'" + (f" (line {j.line})" if j.line else ""), j.velocity))
    if not found:
        return
    fname = robot.path.replace("\\", "/").rsplit("/", 1)[-1]
    values = {v for *_, v in found}
    limit = f'velocity="{values.pop():g}"' if len(values) == 1 else "velocity <= 0"
    names = ", ".join(text for _, _, text, _ in found)
    if len(found) == 1:
        what, them = f"c-space joint {names} has", "it"
    else:
        what, them = f"{len(found)} c-space joints ({names}) have", "them"
    yield ctx.problem(
        found[0][1],
        f"{what} <limit {limit}> in {fname}: cuRobo reads velocity limits only from the "
        f"URDF and cannot move {them}; set the real limits there (a joint_limits.yaml "
        "max_velocity does not reach cuRobo)",
        f"cspace.joint_names[{found[0][0]}]",
    )


RULE = Rule(
    "curobo-zero-velocity",
    Severity.WARNING,
    check,
    __doc__ or "",
    needs_urdf=True,
    reader="curobo",
)
