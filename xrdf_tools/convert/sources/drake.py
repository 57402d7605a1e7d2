"""Drake's URDF extensions → XRDF: what maps is taken, everything else is said.

* ``<limit drake:acceleration="A">``: the joint's acceleration limit, below a joint limits
  file's and a cuRobo config's (those are read first) and above ``--acceleration``, which
  only fills joints the inputs give none (``convert-drake-acceleration``, info).
* ``<drake:collision_filter_group>``: Drake never checks a member of a group against a member
  of a group it ignores (itself included): those pairs are ignored, as an SRDF's
  ``disable_collisions`` are (``convert-drake-filter-group``, info, the pairs with their
  reason, "Drake collision filter group NAME").
* ``<frame>``: a named pose on a link that no XRDF reader sees (``convert-drake-frame``); one
  named by ``--tool-frame`` is written as an XRDF ``add_frame`` fixed to its link at its pose
  (``convert-frame-added``, info), which every XRDF reader adds.
* any other ``drake:`` element or attribute: one located note per kind
  (``convert-drake-ignored``), a warning where the robot's kinematics or geometry change
  (``drake:joint planar``), else an info.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import TYPE_CHECKING

from ...diagnostics import Severity
from ...robot.drake import DrakeExtensions, DrakeFrame, FilterGroup, drake_extensions
from ...util.errors import SourceError
from ...util.numbers import MAX_LENGTH, MAX_NUMBER, within
from ...util.rotations import quat_from_rpy
from ...util.text import name_list, pair_text
from ...xrdf.model import AddFrame, Orientation
from . import Draft, OfferedFrame, Reporter, RobotTree, known_frame

if TYPE_CHECKING:
    from ...robot.core import Robot

__all__ = ["read_drake", "take_offered_frame"]

#: Why a kind of Drake extension has no XRDF equivalent (by the kind's first word).
_WHY = {
    "drake:joint": "no XRDF reader reads Drake joints, so the links it joins are not joined",
    "drake:capsule": "a Drake-only shape: no reader sees this geometry and no sphere is fitted "
    "to it",
    "drake:ellipsoid": "a Drake-only shape: no reader sees this geometry and no sphere is "
    "fitted to it",
    "drake:declare_convex": "Drake collides with the mesh's convex hull; spheres are fitted "
    "to the geometry as the URDF gives it",
    "drake:proximity_properties": "contact properties of Drake's simulation; an XRDF has none",
    "drake:gear_ratio": "actuator dynamics; an XRDF has none",
    "drake:rotor_inertia": "actuator dynamics; an XRDF has none",
}
#: Kinds that change the robot's kinematics or geometry: warnings, the others are infos.
_SHAPING = (
    "drake:joint",
    "drake:capsule",
    "drake:ellipsoid",
    "drake:ball_constraint",
    "drake:linear_bushing_rpy",
    "drake:mimic",
)


def read_drake(robot: Robot, tree: RobotTree, draft: Draft) -> None:
    """Add what ``robot``'s Drake extensions say to ``draft`` (after the other sources: their
    acceleration limits come first), and say what they hold that an XRDF cannot."""
    ext = drake_extensions(robot)
    if not ext:
        return
    rep = Reporter(robot.path)
    _accelerations(ext, tree, draft, rep)
    _filter_groups(ext, tree, draft, rep)
    _frames(ext, tree, draft, rep)
    for kind, at, count in ext.others:
        first = kind.split(" ", 1)[0]
        severity = Severity.WARNING if first in _SHAPING else Severity.INFO
        why = _WHY.get(first, "Drake-only: an XRDF has no equivalent")
        rep.report(
            "convert-drake-ignored",
            f"{kind} left out ({count} in the file): {why}",
            severity=severity,
            at=at,
        )
    draft.diagnostics.extend(rep.diagnostics)


def _accelerations(ext: DrakeExtensions, tree: RobotTree, draft: Draft, rep: Reporter) -> None:
    """``drake:acceleration`` of the joints no source gave an acceleration limit."""
    taken: list[str] = []
    before: list[str] = []
    for joint, text, at in ext.accelerations:
        value = _positive(text)
        if value is None:
            rep.report(
                "convert-drake-acceleration",
                f"drake:acceleration=\"{text}\" of '{joint}' is not a positive number: left out",
                at=at,
            )
        elif joint in draft.acceleration:
            before.append(joint)
        elif joint in tree.joints:
            draft.acceleration[joint] = value
            taken.append(f"{joint} {value:g}")
    if not taken:
        return
    message = (
        f"acceleration limits from the URDF's drake:acceleration for {len(taken)} joint(s): "
        f"{name_list(taken, 8)}"
    )
    if before:
        message += (
            f"; {name_list(before, 4)} take theirs from the joint limits file or cuRobo config, "
            "which come first"
        )
    first = ext.accelerations[0][2]
    rep.report("convert-drake-acceleration", message, severity=Severity.INFO, at=first)


def _positive(text: str) -> float | None:
    try:
        value = float(text)
    except ValueError:
        return None
    return value if math.isfinite(value) and value > 0 else None


def _filter_groups(ext: DrakeExtensions, tree: RobotTree, draft: Draft, rep: Reporter) -> None:
    """Each group's members × the members of each group it ignores: ignored pairs."""
    groups = {g.name: g for g in ext.filter_groups}
    unknown: set[str] = set()
    for group in ext.filter_groups:
        mine = _member_links(group, groups)
        for link in mine:
            if link not in tree.links and link not in unknown:
                unknown.add(link)
                known_frame(
                    link, tree.links, rep, "", f"drake:member of '{group.name}'", at=group.at
                )
        pairs: dict[frozenset[str], tuple[str, str]] = {}
        for other in group.ignored:
            if other not in groups:
                rep.report(
                    "convert-drake-filter-group",
                    f"Drake collision filter group '{group.name}' ignores group '{other}', "
                    "which the URDF does not define: no pair from it",
                    at=group.at,
                )
                continue
            for a in mine:
                for b in _member_links(groups[other], groups):
                    if a != b and a in tree.links and b in tree.links:
                        pairs.setdefault(frozenset((a, b)), (a, b))
        for a, b in pairs.values():
            draft.add_ignore(a, b)
        if pairs:
            shown = name_list((pair_text(a, b) for a, b in pairs.values()), 6)
            rep.report(
                "convert-drake-filter-group",
                f"{len(pairs)} pair(s) ignored, reason 'Drake collision filter group "
                f"{group.name}' (Drake never checks them): {shown}",
                severity=Severity.INFO,
                at=group.at,
            )


def _member_links(group: FilterGroup, groups: dict[str, FilterGroup]) -> list[str]:
    """The links of ``group``: its members, then those of its member groups (each once)."""
    links: dict[str, None] = {}
    seen: set[str] = set()
    todo = [group]
    while todo:
        g = todo.pop(0)
        if g.name in seen:
            continue
        seen.add(g.name)
        links.update(dict.fromkeys(g.members))
        todo += [groups[n] for n in g.member_groups if n in groups]
    return list(links)


def _frames(ext: DrakeExtensions, tree: RobotTree, draft: Draft, rep: Reporter) -> None:
    """Each Drake ``<frame>``: said, and offered to ``--tool-frame`` where Drake would make it
    a frame (a name of its own, on a link of the URDF, at a pose of usable numbers)."""
    lines: dict[str, list[int | None]] = {}
    for frame in ext.frames:
        lines.setdefault(frame.name, []).append(frame.at[1])
    for frame in ext.frames:
        _frame(frame, tree, draft, rep, _refused(frame, tree, lines[frame.name]))


def _refused(frame: DrakeFrame, tree: RobotTree, same_name: list[int | None]) -> str | None:
    """Why Drake refuses ``frame``, which ``--tool-frame`` then cannot add (None: it would
    not). Drake's frames share one namespace with its links' frames, so a name taken twice
    or a link's name is refused, as a frame without a name or a link is."""
    if not frame.name:
        return "it has no name"
    if frame.name in tree.links:
        return f"a link is named '{frame.name}' too (--tool-frame {frame.name} is that link)"
    if len(same_name) > 1:
        at = ", ".join(str(n) for n in same_name if n is not None)
        return f"{len(same_name)} <frame> elements are named '{frame.name}'" + (
            f" (lines {at})" if at else ""
        )
    if not frame.link:
        return "it names no link"
    if frame.link not in tree.links:
        return f"its link '{frame.link}' is not a link of the URDF"
    return None


def _frame(
    frame: DrakeFrame, tree: RobotTree, draft: Draft, rep: Reporter, refused: str | None
) -> None:
    """A Drake ``<frame>``: said, and offered to ``--tool-frame`` as an ``add_frame``."""
    on = f"on link '{frame.link}'" if frame.link else "on no link"
    what = f"a Drake <frame> {on}"
    xyz, rpy = _numbers(frame.xyz, metres=True), _numbers(frame.rpy, metres=False)
    why = f"Drake refuses it: {refused}" if refused else None
    why = why or _pose_problem(frame, xyz is None, rpy is None)
    named = f"'{frame.name}'" if frame.name else "without a name"
    said = f"Drake <frame> {named} {on} is no link: no XRDF reader sees it"
    if refused is not None:
        said += f", and Drake refuses it: {refused}"
    elif why is not None:
        said += f", and --tool-frame cannot add it: {why}"
    else:
        said += f" unless it is added (--tool-frame {frame.name} writes it as an add_frame)"
    rep.report("convert-drake-frame", said, at=frame.at)
    if not frame.name or frame.name in tree.links:
        return  # --tool-frame NAME names the link, not this frame
    if why is not None or xyz is None or rpy is None:
        offer = OfferedFrame(None, what, frame.at, why or "")
        draft.offered_frames.setdefault(frame.name, offer)
        return
    added = AddFrame(
        frame_name=frame.name,
        parent_frame_name=frame.link,
        joint_name="",
        position=xyz,
        orientation=Orientation.from_wxyz(*quat_from_rpy(*rpy)),
    )
    draft.offered_frames[frame.name] = OfferedFrame(added, what, frame.at)


def _pose_problem(frame: DrakeFrame, bad_xyz: bool, bad_rpy: bool) -> str | None:
    """What is wrong with the frame's numbers, or None."""
    problems = []
    if bad_xyz:
        problems.append(f"its xyz '{frame.xyz}' must be three numbers within ±{MAX_LENGTH:g} m")
    if bad_rpy:
        problems.append(f"its rpy '{frame.rpy}' must be three numbers within ±{MAX_NUMBER:g}")
    return "; ".join(problems) or None


def _numbers(text: str, *, metres: bool) -> tuple[float, float, float] | None:
    """Three numbers written apart by spaces, each within the bounds of a length
    (``metres``) or of any number (:mod:`xrdf_tools.util.numbers`), else None."""
    try:
        values = [float(v) for v in text.split()]
    except ValueError:
        return None
    bound = MAX_LENGTH if metres else MAX_NUMBER
    if len(values) != 3 or not all(within(v, bound) for v in values):
        return None
    return values[0], values[1], values[2]


def take_offered_frame(draft: Draft, tree: RobotTree, name: str, rep: Reporter) -> None:
    """Make the offered frame ``name`` (``--tool-frame`` named it) an ``add_frame`` of the
    XRDF, its joint named ``<name>_joint`` (numbered past names taken), and say so; raise
    where it cannot be one."""
    offer = draft.offered_frames[name]
    if offer.added is None:
        path, line = offer.at
        raise SourceError(
            f"--tool-frame '{name}' is {offer.what}, which no XRDF reader sees, and cannot be "
            f"added as an add_frame: {offer.why}",
            path=path,
            line=line,
        )
    taken = set(tree.joints) | {m.joint_name for m in draft.modifiers if isinstance(m, AddFrame)}
    joint = f"{name}_joint"
    n = 2
    while joint in taken:
        joint, n = f"{name}_joint_{n}", n + 1
    draft.modifiers.append(replace(offer.added, joint_name=joint))
    x, y, z = offer.added.position
    rep.report(
        "convert-frame-added",
        f"--tool-frame '{name}' is {offer.what}, which no XRDF reader sees: written as an "
        f"add_frame fixed to '{offer.added.parent_frame_name}' (joint '{joint}', position "
        f"{x:g} {y:g} {z:g}), which the readers add before they plan",
        severity=Severity.INFO,
        at=offer.at,
    )
