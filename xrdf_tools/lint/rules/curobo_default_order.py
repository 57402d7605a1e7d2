"""With ``--urdf``: cuRobo would load other default joint positions than the file says.

cuRobo's XRDF loader (0.7.x and main) fills the default configuration by walking the URDF's
controlled joints in URDF order, then pairs those values with ``cspace.joint_names`` in the
XRDF's order (a bug in cuRobo). When the two orders differ and the defaults differ, every
robot cuRobo loads from this file starts from a scrambled retract configuration. Order
``cspace.joint_names`` as the URDF does, or make the affected defaults equal.
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ...util.text import name_list
from ..context import LintContext, Problem, Rule, finite_number


def check(ctx: LintContext) -> Iterator[Problem]:
    robot = ctx.robot
    cspace = ctx.cspace_joint_nodes()
    if robot is None or not cspace:
        return
    defaults = {n: finite_number(v) or 0.0 for n, _, v in ctx.default_position_nodes()}
    active = [n for n, _ in cspace]
    urdf_order = [n for n, j in robot.joints.items() if j.is_actuated and n in active]
    if len(urdf_order) != len(active):
        return  # unknown or non-actuated c-space joints: cspace-joint reports them
    loaded = {n: defaults.get(u, 0.0) for n, u in zip(active, urdf_order, strict=True)}
    wrong = [n for n in active if loaded[n] != defaults.get(n, 0.0)]
    if not wrong:
        return
    shown = name_list((f"{n} = {loaded[n]:g} (not {defaults.get(n, 0.0):g})" for n in wrong), 3)
    yield ctx.problem(
        cspace[0][1],
        f"cuRobo fills defaults in URDF joint order, not c-space order: it would load {shown}"
        f"; order cspace.joint_names as the URDF does ({name_list(urdf_order, 12)})",
        "cspace.joint_names",
    )


RULE = Rule(
    "curobo-default-order",
    Severity.WARNING,
    check,
    __doc__ or "",
    needs_urdf=True,
    reader="curobo",
)
