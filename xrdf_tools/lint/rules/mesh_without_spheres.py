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
that cannot be found stays a warning too: the user said those are expected. So does a
placeholder, a link whose collision primitives span less than 2 cm (UR's ``ee_link``, a 1 cm
box, which NVIDIA's own UR XRDFs give no sphere). Without the flag, such a link is said to
have mesh files that cannot be found, with what to do (``--package-path PKG=DIR`` for a
``package://`` mesh, putting the file where the URDF names it for a relative one, or
``--allow-missing-meshes`` when they are not at hand): fitting spheres again would not find
them either.

Spheres written on a frame without collision geometry of its own (a fingertip frame, an added
frame) stand for the first link above it, across fixed joints, that has geometry: NVIDIA's
cuMotion ``franka.xrdf`` puts the finger spheres on ``panda_leftfingertip`` and
``panda_rightfingertip``, fixed below ``panda_leftfinger`` and ``panda_rightfinger``, so the
fingers are seen. Attached-object slots (radius <= -1) stand for nothing.

A frame written with an empty list (``link: []``, what deleting every sphere of a link in
``xrdf edit`` leaves) has no spheres: cuRobo and cuMotion load none for it, so it is reported
as a frame that is not written at all, at its key.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterator
from typing import TYPE_CHECKING

from ...diagnostics import Severity
from ...yaml.io import YMap, YNode, YSeq
from ..context import LintContext, Problem, Rule, finite_number, is_null, name

if TYPE_CHECKING:
    from ...robot.core import Robot

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
    written: dict[str, tuple[YNode, str]] = {}  # frames written with no sphere: key, path
    for _, section in sections:
        g = ctx.group_name(section)
        refs = ctx.resolved_spheres(g) if g is not None else None
        if g is None or refs is None:
            return  # an undefined group: undefined-group says so
        used |= {s.frame for s in refs} | _links_served(ctx, g)
        written |= _empty_entries(ctx, g)
    anchor, key = (sections[0][1], sections[0][0]) if sections else (None, "")
    where = "" if sections else " (the file has no collision section)"
    bare = [f for f in kin.frame_names if f in robot.collision_counts and f not in used]
    absent = _only_missing_meshes(ctx, bare)
    tiny = _placeholders(robot) if planning and bare else {}
    for frame in bare:
        moved = planning and bool(cspace.intersection(kin.joints_on_path(kin.base_frame, frame)))
        excused = (frame in absent and ctx.allow_missing_meshes) or frame in tiny
        severity = Severity.ERROR if moved and not excused else Severity.WARNING
        node, path = written.get(frame, (anchor, key))
        yield ctx.problem(
            node,
            f"link '{frame}' has collision geometry in {robot.path.rsplit('/', 1)[-1]} but no "
            f"collision spheres{' (its list is empty)' if frame in written else where}"
            f"{_why(frame, absent, tiny, ctx.allow_missing_meshes)}; the planner cannot see it",
            path,
            severity,
        )


def _empty_entries(ctx: LintContext, group: str) -> dict[str, tuple[YNode, str]]:
    """The frames of ``group`` (clones merged) written with a key but no sphere (``link: []``
    or ``link:``), with the key and its path."""
    out: dict[str, tuple[YNode, str]] = {}
    for g in ctx.clone_closure(group) or ():
        gnode = ctx.groups[g]
        spheres = gnode.get("spheres") if isinstance(gnode, YMap) else None
        if isinstance(spheres, YMap):
            for k, v in spheres.pairs:
                n = name(k)
                if n is not None and (is_null(v) or (isinstance(v, YSeq) and not v.items)):
                    out.setdefault(n, (k, f"geometry.{g}.spheres.{n}"))
    return out


def _placeholders(robot: Robot) -> dict[str, float]:
    from ...robot.placeholders import placeholder_links  # with --urdf only: lint stays light

    return placeholder_links(robot)


def _why(frame: str, absent: dict[str, str], tiny: dict[str, float], allowed: bool) -> str:
    """Why a link has no spheres (its meshes cannot be found), or why a moved link without
    spheres is a warning, not an error, for a planner. ``--package-path`` is offered only for
    a ``package://`` or ``model://`` mesh: it cannot move a file named relative to the URDF
    (LEAP Hand's ``palm_lower.stl``)."""
    if frame in absent and allowed:
        return " (its collision meshes cannot be found: --allow-missing-meshes)"
    if frame in absent:
        from ...robot.packages import package_scheme  # with --urdf only: lint stays light

        uri = absent[frame]
        scheme = package_scheme(uri)
        where = (
            f"pass --package-path {uri[len(scheme) :].partition('/')[0]}=DIR to fit spheres to them"
            if scheme
            else f"{uri} is not where the URDF names it; put it there to fit spheres to it"
        )
        return (
            f" (its collision meshes cannot be found: {where}, or --allow-missing-meshes when "
            "they are not at hand)"
        )
    if frame in tiny:
        return f" (a placeholder, {tiny[frame] * 1000:.0f} mm across: nothing to plan around)"
    return ""


def _links_served(ctx: LintContext, group: str | None) -> set[str]:
    """The links whose geometry spheres on a geometry-less frame below them stand for: from
    each such frame with a real sphere (not an attached-object slot), up across fixed joints
    to the first link with collision geometry."""
    from ...robot.kinematics.base import JointType  # numpy: only with --urdf

    robot, kin = ctx.robot, ctx.kin
    refs = ctx.resolved_spheres(group) if group is not None else None
    if robot is None or kin is None or not refs:
        return set()
    real = {s.frame for s in refs if (r := finite_number(s.field("radius"))) is None or r > -1}
    out: set[str] = set()
    for frame in real - set(robot.collision_counts):
        if not kin.has_frame(frame):
            continue
        i = kin.frame_index(frame)
        while kin.joint_type[i] == JointType.FIXED and kin.parent[i] >= 0:
            i = int(kin.parent[i])
            if kin.frame_names[i] in robot.collision_counts:
                out.add(kin.frame_names[i])
                break
    return out


def _only_missing_meshes(ctx: LintContext, links: list[str]) -> dict[str, str]:
    """The ``links`` whose every collision element is a mesh file that cannot be found, each
    with the first such file's URI as written (read from the URDF's XML: no geometry library
    is imported, and the default install, without the 'fit' extra, reads them too)."""
    from ...robot.link_geometry import missing_meshes

    robot = ctx.robot
    if robot is None or not links:
        return {}
    failures = missing_meshes(robot, "collision", links=links)
    counts = Counter(f.link for f in failures)
    first: dict[str, str] = {}
    for f in failures:
        first.setdefault(f.link, f.uri or "")
    return {
        link: first[link] for link, n in counts.items() if n == robot.collision_counts.get(link)
    }


RULE = Rule("mesh-without-spheres", Severity.WARNING, check, __doc__ or "", needs_urdf=True)
