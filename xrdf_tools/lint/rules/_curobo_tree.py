"""The joints of the robot cuRobo builds from an XRDF: those on the chains from the base frame
to the tool frames, the sphere frames of the world-collision group and the added frames."""

from __future__ import annotations

from typing import TYPE_CHECKING

from ...yaml.io import YMap, YSeq
from ..context import LintContext, name

if TYPE_CHECKING:  # numpy: lint without --urdf stays light
    from ...robot.urdf_joints import JointInfo


def fixed_targets(ctx: LintContext) -> set[str]:
    """The tool frames and the added frames: the chains that fitting spheres never changes."""
    out = set(ctx.added_frames)
    tools = ctx.get("tool_frames")
    if isinstance(tools, YSeq):
        out.update(n for item in tools.items if (n := name(item)) is not None)
    return out


def sphere_targets(ctx: LintContext) -> set[str]:
    """The sphere frames of the world-collision group (fitting spheres adds to them)."""
    world = ctx.get(ctx.world_key())
    group = ctx.group_name(world) if isinstance(world, YMap) else None
    if group is None or group not in ctx.groups:
        return set()
    return ctx.sphere_frames(group) or set()


def _targets(ctx: LintContext) -> set[str]:
    return fixed_targets(ctx) | sphere_targets(ctx)


def curobo_tree_joints(ctx: LintContext) -> list[JointInfo] | None:
    """The moving URDF joints (mimic followers included) on those chains, each once; None
    without ``--urdf``. Frames the robot lacks are skipped (another rule reports them)."""
    found = joints_to_frames(ctx, _targets(ctx))
    return None if found is None else [info for info, _ in found.values()]


def joints_to_frames(ctx: LintContext, frames: set[str]) -> dict[str, tuple[JointInfo, str]] | None:
    """The moving URDF joints on the chains from the base to ``frames``, by name, each once
    with the first frame (by name) it moves; None without ``--urdf``."""
    kin = ctx.kin
    if kin is None:
        return None
    out: dict[str, tuple[JointInfo, str]] = {}
    for frame in sorted(frames):
        if frame not in kin.frame_names:
            continue
        i = kin.frame_index(frame)
        while i > 0:
            joint = kin.joint_of_frame[i]
            info = kin.joints.get(joint) if joint is not None else None
            if info is not None and info.type != "fixed":
                out.setdefault(info.name, (info, frame))
            i = int(kin.parent[i])
    return out
