"""Shared by the joint rules: why a joint name cannot take a position (or None), and the
c-space joints whose URDF joint has some defect."""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING

from ...util.errors import did_you_mean
from ...yaml.io import YNode
from ..context import LintContext

if TYPE_CHECKING:  # numpy: lint without --urdf stays light
    from ...robot.core import Robot
    from ...robot.urdf_joints import JointInfo


def cspace_joints_where(
    ctx: LintContext, defect: Callable[[JointInfo], bool]
) -> list[tuple[int, YNode, JointInfo]]:
    """The c-space joints of the ``--urdf`` robot whose URDF joint has ``defect``: each with
    its index in ``cspace.joint_names`` and its node."""
    robot = ctx.robot
    if robot is None:
        return []
    out = []
    for i, (n, node) in enumerate(ctx.cspace_joint_nodes()):
        j = robot.joints.get(n)
        if j is not None and defect(j):
            out.append((i, node, j))
    return out


def joint_at(j: JointInfo, robot: Robot | None = None) -> str:
    """``'name' (line N)`` of a URDF joint, for a message; a joint that a macro of an included
    xacro file writes is placed in that file (``'name' (arm_macro.xacro:12)``)."""
    if j.line:
        return f"'{j.name}' (line {j.line})"
    place = robot.include_places.get(("joint", j.name)) if robot is not None else None
    if place is None:
        return f"'{j.name}'"
    return f"'{j.name}' ({os.path.basename(place[0])}:{place[1]})"


def written_in(joints: Sequence[JointInfo], robot: Robot) -> str:
    """The name of the file that writes ``joints``: the included xacro file whose macro writes
    them all (``arm_macro.xacro``, where their ``<limit>`` is edited), else the robot's file."""
    files = {
        None if j.line else robot.include_places.get(("joint", j.name), (None,))[0] for j in joints
    }
    only = files.pop() if len(files) == 1 else None
    return os.path.basename(only) if only else robot.file_name


def joint_problem(ctx: LintContext, joint: str, what: str) -> str | None:
    kin = ctx.kin
    assert kin is not None and ctx.robot is not None
    fname = ctx.robot.file_name
    if joint in kin.actuated_joints:
        why = kin.cspace_reason(joint)
        return f"{what} '{joint}' {why}" if why else None
    if joint in kin.pruned_joints:
        return f"{what} '{joint}' was removed by set_base_frame '{kin.base_frame}'"
    j = kin.joints.get(joint)
    if j is None:
        movable = [n for n, x in kin.joints.items() if x.is_movable]
        return f"{what} '{joint}' is not a joint of {fname}" + did_you_mean(joint, movable)
    if j.is_mimic:
        return (
            f"{what} '{joint}' is a mimic joint (it follows '{j.mimic_joint}'); its position is "
            "set by that joint"
        )
    return (
        f"{what} '{joint}' is a {j.type} joint; only revolute, continuous and prismatic joints move"
    )
