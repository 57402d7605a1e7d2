"""With ``--urdf``: a revolute or prismatic c-space joint whose URDF limits are equal
(``lower="0" upper="0"``).

Such a joint cannot move: every reader bounds it to that one position, so the c-space has a
coordinate no plan can use, and the arm plans as if that joint were welded. CAD exporters
write ``<limit lower="0" upper="0">`` for limits never set (SolidWorks' exporter does), and a
MoveIt configuration made from that URDF puts the joint in its arm group. Give the joint its
real limits in the URDF, or leave it out of the c-space (a joint held on purpose).
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ..context import LintContext, Problem, Rule


def check(ctx: LintContext) -> Iterator[Problem]:
    robot = ctx.robot
    if robot is None:
        return
    found = []
    for i, (n, node) in enumerate(ctx.cspace_joint_nodes()):
        j = robot.joints.get(n)
        if j is None or j.type not in ("revolute", "prismatic") or j.lower is None:
            continue
        if j.lower == j.upper:
            where = f" (line {j.line})" if j.line else ""
            found.append((i, node, f"'{n}'{where} [{j.lower:g}, {j.upper:g}]"))
    if not found:
        return
    fname = robot.path.replace("\\", "/").rsplit("/", 1)[-1]
    names = ", ".join(text for *_, text in found)
    what = f"c-space joint {names} is" if len(found) == 1 else f"c-space joints {names} are"
    yield ctx.problem(
        found[0][1],
        f"{what} held still by equal lower and upper limits in {fname}: no plan can move "
        f"{'it' if len(found) == 1 else 'them'} (a CAD exporter writes 0 0 for limits never "
        "set); give the URDF the real limits, or leave such a joint out of the c-space",
        f"cspace.joint_names[{found[0][0]}]",
    )


RULE = Rule(
    "cspace-joint-held",
    Severity.WARNING,
    check,
    __doc__ or "",
    needs_urdf=True,
)
