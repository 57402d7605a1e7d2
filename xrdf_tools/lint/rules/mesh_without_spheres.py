"""With ``--urdf``: a link has collision geometry in the URDF but no spheres in the
self- or world-collision group.

The planner only sees spheres, so such a link is invisible to collision checking (a gripper or
a tool flange is the usual culprit). Add spheres for it (``xrdf convert --fit-spheres`` fits
them), or disable the rule for links that cannot collide.

A warning by default. For a planning reader (``--target curobo`` or ``--target cumotion``) it
is an error when a c-space joint moves the link: the planner would move it through obstacles
(a file without any collision section is then reported too, once per such link). A link no
c-space joint moves (a base bolted to the table) stays a warning: no plan can change its
clearance. With ``--allow-missing-meshes`` a link whose collision geometry is only mesh files
that cannot be found stays a warning too: the user said those are expected.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterator

from ...diagnostics import Severity
from ..context import LintContext, Problem, Rule

#: The readers that plan with the spheres: a link they cannot see is an error for them.
PLANNING_TARGETS = frozenset({"curobo", "cumotion"})


def check(ctx: LintContext) -> Iterator[Problem]:
    robot, kin = ctx.robot, ctx.kin
    if robot is None or kin is None:
        return
    planning = ctx.target in PLANNING_TARGETS
    cspace = {n for n, _ in ctx.cspace_joint_nodes()}
    used: set[str] = set()
    sections = ctx.collision_sections()
    if not sections and not planning:
        return
    for _, section in sections:
        g = ctx.group_name(section)
        frames = ctx.sphere_frames(g) if g is not None else None
        if frames is None:
            return  # an undefined group: undefined-group says so
        used |= frames
    anchor, key = (sections[0][1], sections[0][0]) if sections else (None, "")
    where = "" if sections else " (the file has no collision section)"
    bare = [f for f in kin.frame_names if f in robot.collision_counts and f not in used]
    absent = _only_missing_meshes(ctx, bare) if planning and ctx.allow_missing_meshes else set()
    for frame in bare:
        moved = planning and bool(cspace.intersection(kin.joints_on_path(kin.base_frame, frame)))
        severity = Severity.ERROR if moved and frame not in absent else Severity.WARNING
        why = " (its collision meshes cannot be found: --allow-missing-meshes)"
        yield ctx.problem(
            anchor,
            f"link '{frame}' has collision geometry in {robot.path.rsplit('/', 1)[-1]} but no "
            f"collision spheres{where}{why if frame in absent else ''}; the planner cannot see it",
            key,
            severity,
        )


def _only_missing_meshes(ctx: LintContext, links: list[str]) -> set[str]:
    """The ``links`` whose every collision element is a mesh file that cannot be found."""
    from ...robot.link_geometry import missing_meshes

    robot = ctx.robot
    if robot is None or not links:
        return set()
    counts = Counter(f.link for f in missing_meshes(robot, "collision", links=links))
    return {link for link, n in counts.items() if n == robot.collision_counts.get(link)}


RULE = Rule("mesh-without-spheres", Severity.WARNING, check, __doc__ or "", needs_urdf=True)
