"""Drake's URDF extensions, as written in a loaded robot (RobotLocomotion's models).

Drake's parser reads more than the URDF spec: a joint's ``<limit drake:acceleration="…">``,
``<drake:collision_filter_group>`` (links whose pairs Drake never checks), ``<frame>`` elements
(named frames fixed to a link, no links themselves) and other ``drake:`` elements and
attributes (``<drake:joint type="planar">``, ``<drake:declare_convex/>``, actuator dynamics).
:func:`drake_extensions` collects them from the checked XML tree, each with the file and line
it is written at; what they mean for an XRDF is :mod:`xrdf_tools.convert.sources.drake`'s to
say. Drake matches the ``drake:`` prefix as written, so any URI bound to ``drake`` counts (the
namespace Drake declares, ``xmlns:drake="http://drake.mit.edu"``, or another), and so does an
undeclared ``drake:`` (the loader moves it into :data:`UNDECLARED_DRAKE`); another prefix bound
to Drake's URI (``xmlns:d="http://drake.mit.edu"``, ``<d:collision_filter_group>``) does not,
as Drake reads ``d:collision_filter_group`` as no element of its own.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from .core import Robot

__all__ = [
    "DRAKE_NS",
    "UNDECLARED_DRAKE",
    "DrakeExtensions",
    "DrakeFrame",
    "FilterGroup",
    "drake_extensions",
]

DRAKE_NS = "http://drake.mit.edu"
#: Where the loader puts names written with an undeclared ``drake:`` prefix (no URI of a file).
UNDECLARED_DRAKE = "urn:xrdf-tools:undeclared-drake-prefix"

#: A file and a line (None: not known).
Place = tuple[str, "int | None"]

#: The children of a ``<drake:collision_filter_group>`` it is read with.
_GROUP_PARTS = ("member", "member_group", "ignored_collision_filter_group")


@dataclass(frozen=True)
class DrakeFrame:
    """A ``<frame name link xyz rpy>`` of the robot: a named pose on ``link`` (``name`` or
    ``link`` "" when the element has none)."""

    name: str
    link: str
    xyz: str
    rpy: str
    at: Place


@dataclass(frozen=True)
class FilterGroup:
    """A ``<drake:collision_filter_group>``: its member links, the groups whose members it
    takes too (``drake:member_group``) and the groups it ignores (itself included)."""

    name: str
    members: tuple[str, ...]
    member_groups: tuple[str, ...]
    ignored: tuple[str, ...]
    at: Place


@dataclass(frozen=True)
class DrakeExtensions:
    """What a robot writes for Drake alone."""

    #: ``(joint, value as written, place)`` of each ``<limit drake:acceleration>``.
    accelerations: tuple[tuple[str, str, Place], ...] = ()
    filter_groups: tuple[FilterGroup, ...] = ()
    frames: tuple[DrakeFrame, ...] = ()
    #: Every other kind (``drake:joint planar``, ``drake:declare_convex``): its first place
    #: and how many the file has, in document order.
    others: tuple[tuple[str, Place, int], ...] = ()

    def __bool__(self) -> bool:
        return bool(self.accelerations or self.filter_groups or self.frames or self.others)


def drake_extensions(robot: Robot) -> DrakeExtensions:
    """The Drake extensions of ``robot`` (none for a robot without its XML tree)."""
    root = robot.document
    if root is None:
        return DrakeExtensions()
    key = ("drake_extensions",)
    if key not in robot.derived:
        robot.derived[key] = _read(robot, root)
    found: DrakeExtensions = robot.derived[key]
    return found


def _read(robot: Robot, root: Any) -> DrakeExtensions:
    uris = {UNDECLARED_DRAKE}
    uris.update(el.nsmap["drake"] for el in root.iter() if "drake" in (el.nsmap or {}))
    accelerations: list[tuple[str, str, Place]] = []
    groups: list[FilterGroup] = []
    others: dict[str, tuple[Place, int]] = {}
    for joint in root.iterchildren("joint"):
        limit = joint.find("limit")
        for key, value in () if limit is None else limit.attrib.items():
            if _drake_name(key, uris) == "acceleration":
                where = _place(robot, limit, "joint", str(joint.get("name")))
                accelerations.append((str(joint.get("name")), str(value), where))
    for el in root.iter():
        if not isinstance(el.tag, str):
            continue
        name = _drake_name(el.tag, uris)
        if name == "collision_filter_group" and el.getparent() is root:
            groups.append(_group(robot, el, uris))
        elif name is not None and not _in_group(el, uris):
            _count(others, _element_kind(name, el), _place(robot, el))
        for key in el.attrib:
            attr = _drake_name(key, uris)
            if attr is not None and not (attr == "acceleration" and _tag(el) == "limit"):
                _count(others, f"drake:{attr} on <{_tag(el)}>", _place(robot, el))
    frames = tuple(
        DrakeFrame(
            str(f.get("name") or ""),
            str(f.get("link") or ""),
            " ".join(str(f.get("xyz") or "0 0 0").split()),
            " ".join(str(f.get("rpy") or "0 0 0").split()),
            _place(robot, f),
        )
        for f in root.iterchildren("frame")
    )
    kinds = tuple((k, at, n) for k, (at, n) in others.items())
    return DrakeExtensions(tuple(accelerations), tuple(groups), frames, kinds)


def _drake_name(qualified: str, uris: set[str]) -> str | None:
    """The local name of a ``{uri}name`` tag or attribute in a Drake namespace, else None."""
    if not qualified.startswith("{"):
        return None
    uri, _, local = qualified[1:].partition("}")
    return local if uri in uris else None


def _tag(el: Any) -> str:
    tag = str(el.tag)
    return tag.rpartition("}")[2]


def _in_group(el: Any, uris: set[str]) -> bool:
    """Whether ``el`` is a part of a filter group (read with the group)."""
    parent = el.getparent()
    return (
        parent is not None
        and _drake_name(str(parent.tag), uris) == "collision_filter_group"
        and _tag(el) in _GROUP_PARTS
    )


def _element_kind(name: str, el: Any) -> str:
    """``drake:joint planar`` for a Drake joint (its type tells what is lost), else the tag."""
    if name == "joint":
        return f"drake:joint {el.get('type') or '(no type)'}"
    return f"drake:{name}"


def _count(others: dict[str, tuple[Place, int]], kind: str, at: Place) -> None:
    first, n = others.get(kind, (at, 0))
    others[kind] = (first, n + 1)


def _group(robot: Robot, el: Any, uris: set[str]) -> FilterGroup:
    parts: dict[str, list[str]] = {p: [] for p in _GROUP_PARTS}
    for child in el:
        local = _drake_name(str(child.tag), uris) if isinstance(child.tag, str) else None
        if local in parts:
            value = child.get("link") if local == "member" else child.get("name")
            if value:
                parts[local].append(str(value))
    return FilterGroup(
        str(el.get("name") or ""),
        tuple(parts["member"]),
        tuple(parts["member_group"]),
        tuple(parts["ignored_collision_filter_group"]),
        _place(robot, el),
    )


def _place(robot: Robot, el: Any, kind: str | None = None, name: str = "") -> Place:
    """Where ``el`` is written: its line in the robot's file; in an expanded xacro, the line
    of the element it belongs to when the xacro writes that literally, else where the
    ``kind`` element ``name`` is written (an included file's macro)."""
    line = el.sourceline or None
    if line is None and kind in ("link", "joint"):
        return robot.place("link" if kind == "link" else "joint", name)
    return robot.path, line
