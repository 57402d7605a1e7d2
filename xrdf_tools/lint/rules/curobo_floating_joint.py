"""With ``--urdf``: a floating or planar joint stays in the robot cuRobo would build.

cuRobo's URDF parser knows fixed, revolute, continuous and prismatic joints only: it raises
("Joint type not supported") on any other joint between its base and the links it builds, so
the robot does not load. A humanoid exported with ``world`` → ``pelvis`` floating, or a mobile
base's ``odom`` → ``base_footprint`` planar joint, does this when the XRDF keeps the URDF root
as its base. Make the joint's child the base (``modifiers: [{set_base_frame: pelvis}]``; ``xrdf
convert`` does so itself) or remove the joint from the URDF.
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ..context import LintContext, Problem, Rule


def check(ctx: LintContext) -> Iterator[Problem]:
    kin = ctx.kin
    if kin is None:
        return
    from ...robot.kinematics.base import JointType  # numpy: lint without --urdf stays light

    unloadable = {JointType.FLOATING: "floating", JointType.PLANAR: "planar"}
    for frame, joint, code in zip(
        kin.frame_names, kin.joint_of_frame, kin.joint_type.tolist(), strict=True
    ):
        kind = unloadable.get(JointType(code))
        if kind is None or joint is None:
            continue
        yield ctx.problem(
            ctx.get("modifiers"),
            f"'{joint}' is a {kind} joint below the base '{kin.base_frame}': cuRobo cannot "
            f"load the robot ('Joint type not supported'); set its child as the base "
            f"(modifiers: - set_base_frame: {frame})",
            "modifiers",
        )


RULE = Rule(
    "curobo-floating-joint",
    Severity.WARNING,
    check,
    __doc__ or "",
    needs_urdf=True,
    reader="curobo",
)
