"""Shared by the joint rules: why a joint name cannot take a position (or None)."""

from __future__ import annotations

from ...util.errors import did_you_mean
from ..context import LintContext


def joint_problem(ctx: LintContext, joint: str, what: str) -> str | None:
    kin = ctx.kin
    assert kin is not None and ctx.robot is not None
    fname = ctx.robot.path.replace("\\", "/").rsplit("/", 1)[-1]
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
