"""The joints of the robot cuRobo builds from an XRDF: those on the chains from the base frame
to the tool frames, the sphere frames of the world-collision group and the added frames."""

from __future__ import annotations

from typing import TYPE_CHECKING

from ...yaml.io import YMap, YSeq
from ..context import LintContext, name

if TYPE_CHECKING:  # numpy: lint without --urdf stays light
    from ...robot.urdf_joints import JointInfo


def _targets(ctx: LintContext) -> set[str]:
    out = set(ctx.added_frames)
    tools = ctx.get("tool_frames")
    if isinstance(tools, YSeq):
        out.update(n for item in tools.items if (n := name(item)) is not None)
    world = ctx.get(ctx.world_key())
    group = ctx.group_name(world) if isinstance(world, YMap) else None
    if group is not None and group in ctx.groups:
        out.update(ctx.sphere_frames(group) or ())
    return out


def curobo_tree_joints(ctx: LintContext) -> list[JointInfo] | None:
    """The moving URDF joints (mimic followers included) on those chains, each once; None
    without ``--urdf``. Frames the robot lacks are skipped (another rule reports them)."""
    kin = ctx.kin
    if kin is None:
        return None
    out: dict[str, JointInfo] = {}
    for frame in sorted(_targets(ctx)):
        if frame not in kin.frame_names:
            continue
        i = kin.frame_index(frame)
        while i > 0:
            joint = kin.joint_of_frame[i]
            info = kin.joints.get(joint) if joint is not None else None
            if info is not None and info.type != "fixed":
                out.setdefault(info.name, info)
            i = int(kin.parent[i])
    return list(out.values())
