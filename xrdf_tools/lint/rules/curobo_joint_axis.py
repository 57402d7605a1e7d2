"""With ``--urdf``: a moving joint of the robot cuRobo builds whose axis is not along x, y or z.

cuRobo's kinematics knows rotation about and translation along ±x, ±y and ±z only: its URDF
parser reads a joint as such when one component of ``<axis xyz>`` is exactly 1 or -1, and its
loader raises on any other axis (``0 0.6 0.8``, or ``0 0 0.9999`` from a CAD export) of a
joint on the chains it builds (from the base frame to the tool frames, the sphere frames and
the added frames). Rotate the joint's ``<origin>`` so that the axis is a coordinate axis (the
child link's frame and its meshes, inertia and collision origins move with it), or write the
axis as exact unit numbers.
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ..context import LintContext, Problem, Rule
from ._curobo_tree import curobo_tree_joints
from ._joints import joint_at


def check(ctx: LintContext) -> Iterator[Problem]:
    joints = curobo_tree_joints(ctx)
    if not joints or ctx.robot is None:
        return
    nodes = dict(ctx.cspace_joint_nodes())
    for j in joints:
        if any(abs(a) == 1.0 for a in j.axis):
            continue
        axis = " ".join(f"{a:g}" for a in j.axis)
        yield ctx.problem(
            nodes.get(j.mimic_joint or j.name),
            f"joint {joint_at(j, ctx.robot)} of {ctx.robot.file_name} has "
            f'<axis xyz="{axis}">: cuRobo moves joints about or along x, y or z only and its '
            "loader raises on this one; "
            "rotate the joint's origin so that its axis is a coordinate axis",
            "",
        )


RULE = Rule(
    "curobo-joint-axis",
    Severity.WARNING,
    check,
    __doc__ or "",
    needs_urdf=True,
    reader="curobo",
)
