"""Drake's URDF extensions → XRDF: what maps is taken, everything else is said.

* ``<limit drake:acceleration="A">``: the joint's acceleration limit, below a joint limits
  file's and a cuRobo config's (those are read first) and above ``--acceleration``, which
  only fills joints the inputs give none (``convert-drake-acceleration``, info).
* ``<drake:collision_filter_group>``: Drake never checks a member of a group against a member
  of a group it ignores (itself included): those pairs are ignored, as an SRDF's
  ``disable_collisions`` are (``convert-drake-filter-group``, info, the pairs with their
  reason, "Drake collision filter group NAME").
* ``<frame>``: a named pose on a link that no XRDF reader sees (``convert-drake-frame``); one
  named by ``--tool-frame`` stops convert with the fixed link to write in its place.
* any other ``drake:`` element or attribute: one located note per kind
  (``convert-drake-ignored``), a warning where the robot's kinematics or geometry change
  (``drake:joint planar``), else an info.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from ...diagnostics import Severity
from ...robot.drake import DrakeExtensions, DrakeFrame, FilterGroup, drake_extensions
from ...util.text import name_list, pair_text
from . import Draft, Reporter, RobotTree, known_frame

if TYPE_CHECKING:
    from ...robot.core import Robot

__all__ = ["read_drake"]

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
    for frame in ext.frames:
        _frame(frame, draft, rep)
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


def _frame(frame: DrakeFrame, draft: Draft, rep: Reporter) -> None:
    """A Drake ``<frame>``: said, and kept as the way to a fixed link for ``--tool-frame``."""
    rep.report(
        "convert-drake-frame",
        f"Drake <frame> '{frame.name}' on link '{frame.link}' is no link: no XRDF reader "
        "sees it, so it cannot be a tool frame (--tool-frame says how to make it one)",
        at=frame.at,
    )
    link = (
        f'<link name="{frame.name}"/><joint name="{frame.name}_joint" type="fixed">'
        f'<parent link="{frame.link}"/><child link="{frame.name}"/>'
        f'<origin xyz="{frame.xyz}" rpy="{frame.rpy}"/></joint>'
    )
    draft.unseen_frames[frame.name] = (
        f"--tool-frame '{frame.name}' is a Drake <frame> on link '{frame.link}', which no "
        f"XRDF reader sees; replace it in the URDF by a fixed link (Drake reads that too): "
        f"{link}",
        frame.at,
    )
