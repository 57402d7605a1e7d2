"""With ``--urdf``: a c-space joint that moves no tool frame, no sphere frame and no added
frame.

cuRobo builds its robot from the chains between the base frame and those frames only: the
chain to ``tool_frames[0]`` first, then to the other tool frames, to every frame of the
collision geometry group and to every ``add_frame``. A c-space joint on none of these chains is
not in that robot, and its loader raises ("cspace contains joints that are not active in the
configured tree and are not explicitly locked"). Add a tool frame or spheres below the joint,
or leave it out of the c-space (cuRobo then holds it at its default position).
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ..context import LintContext, Problem, Rule
from ._curobo_tree import curobo_tree_joints


def check(ctx: LintContext) -> Iterator[Problem]:
    joints = curobo_tree_joints(ctx)
    if joints is None or ctx.kin is None:
        return
    moving = {j.mimic_joint or j.name for j in joints}
    for index, (joint, node) in enumerate(ctx.cspace_joint_nodes()):
        if joint in ctx.kin.joints and joint not in moving:
            yield ctx.problem(
                node,
                f"c-space joint '{joint}' moves no tool frame, sphere frame or added frame: "
                "cuRobo builds its robot from the chains to those frames and raises ('cspace "
                "contains joints that are not active in the configured tree'); add a tool "
                "frame or spheres below it, or leave it out of the c-space",
                f"cspace.joint_names[{index}]",
            )


RULE = Rule(
    "curobo-joint-outside-tree",
    Severity.WARNING,
    check,
    __doc__ or "",
    needs_urdf=True,
    reader="curobo",
)
