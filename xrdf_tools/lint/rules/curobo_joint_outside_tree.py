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
from ...yaml.io import YMap, YSeq
from ..context import LintContext, Problem, Rule, name


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


def check(ctx: LintContext) -> Iterator[Problem]:
    kin = ctx.kin
    if kin is None:
        return
    moving: set[str] = set()
    for frame in _targets(ctx):
        if frame not in kin.frame_names:
            continue  # an unknown frame is another rule's finding
        i = kin.frame_index(frame)
        while i > 0:
            joint = kin.joint_of_frame[i]
            info = kin.joints.get(joint) if joint is not None else None
            if info is not None and info.type != "fixed":
                moving.add(info.mimic_joint or info.name)
            i = int(kin.parent[i])
    for index, (joint, node) in enumerate(ctx.cspace_joint_nodes()):
        if joint in kin.joints and joint not in moving:
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
