"""With ``--urdf``: a link has collision geometry in the URDF but no spheres in the
self- or world-collision group.

The planner only sees spheres, so such a link is invisible to collision checking (a gripper or
a tool flange is the usual culprit). Add spheres for it (``xrdf convert`` can fit them), or
disable the rule for links that cannot collide.
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ..context import LintContext, Problem, Rule


def check(ctx: LintContext) -> Iterator[Problem]:
    robot, kin = ctx.robot, ctx.kin
    if robot is None or kin is None:
        return
    used: set[str] = set()
    sections = ctx.collision_sections()
    if not sections:
        return
    for _, section in sections:
        g = ctx.group_name(section)
        frames = ctx.sphere_frames(g) if g is not None else None
        if frames is None:
            return
        used |= frames
    for frame in kin.frame_names:
        if frame not in robot.collision_counts or frame in used:
            continue
        yield ctx.problem(
            sections[0][1],
            f"link '{frame}' has collision geometry in {robot.path.rsplit('/', 1)[-1]} but no "
            "collision spheres; the planner cannot see it",
            sections[0][0],
        )


RULE = Rule("mesh-without-spheres", Severity.WARNING, check, __doc__ or "", needs_urdf=True)
