"""MoveIt SRDF: the parsed document (:class:`Srdf`) and its parser.

Only the elements that matter for an XRDF are kept (groups, group states, end effectors,
virtual and passive joints, collision masks, sphere approximations), each with its source line.
Group expansion and choice are in :mod:`.srdf_groups`, the mapping onto a Draft in :mod:`.srdf`.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass, field, replace
from typing import Any, Protocol

from ...diagnostics import Diagnostic
from ...robot.packages import PackagePaths
from ...robot.xacro_places import ElementKey, Place, included_places
from ...util.errors import SourceError
from ...util.fileio import read_input_bytes
from ...util.frozen import FrozenMap
from ...util.safe_xml import XmlSyntaxError, parse_xml, utf8_xml_bytes
from ...xrdf.model import Sphere

__all__ = [
    "SRDF_KEYS",
    "EndEffector",
    "GroupState",
    "Srdf",
    "SrdfGroup",
    "VirtualJoint",
    "load_srdf",
    "parse_srdf",
    "refuse_urdf",
    "trimmed",
]


#: The attributes that tell the SRDF elements of each tag apart (their :data:`ElementKey`
#: is the tag, then these values): where a macro writes them is found by them.
SRDF_KEYS: Mapping[str, tuple[str, ...]] = FrozenMap(
    {
        "group": ("name",),
        "group_state": ("name", "group"),
        "end_effector": ("name",),
        "virtual_joint": ("name",),
        "passive_joint": ("name",),
        "disable_collisions": ("link1", "link2"),
        "disable_default_collisions": ("link",),
        "enable_collisions": ("link1", "link2"),
        "link_sphere_approximation": ("link",),
    }
)


@dataclass(frozen=True)
class SrdfGroup:
    name: str
    links: tuple[str, ...] = ()
    joints: tuple[str, ...] = ()
    chains: tuple[tuple[str, str], ...] = ()
    subgroups: tuple[str, ...] = ()
    line: int | None = None

    @property
    def key(self) -> ElementKey:
        return ("group", self.name)


@dataclass(frozen=True)
class GroupState:
    name: str
    group: str | None
    values: tuple[tuple[str, float], ...]
    line: int | None = None
    #: The joints whose ``value`` holds more than one number (``value="0 0 0"``: a planar
    #: joint's); ``values`` has the first. MoveIt and pinocchio use a value only when it has
    #: one number per variable of the joint.
    multi: tuple[str, ...] = ()

    @property
    def key(self) -> ElementKey:
        return ("group_state", self.name, self.group or "")


@dataclass(frozen=True)
class VirtualJoint:
    """A ``<virtual_joint>``: its name, type and ``child_link`` (empty when not given)."""

    name: str
    type: str
    child: str
    line: int | None = None

    @property
    def key(self) -> ElementKey:
        return ("virtual_joint", self.name)


@dataclass(frozen=True)
class EndEffector:
    name: str
    parent_link: str
    group: str | None
    parent_group: str | None
    line: int | None = None

    @property
    def key(self) -> ElementKey:
        return ("end_effector", self.name)


class _Placed(Protocol):
    @property
    def key(self) -> ElementKey: ...

    @property
    def line(self) -> int | None: ...


@dataclass(frozen=True)
class Srdf:
    path: str
    robot_name: str
    groups: dict[str, SrdfGroup] = field(default_factory=dict)
    group_states: tuple[GroupState, ...] = ()
    end_effectors: tuple[EndEffector, ...] = ()
    virtual_joints: tuple[VirtualJoint, ...] = ()
    passive_joints: tuple[str, ...] = ()
    passive_joint_lines: tuple[int | None, ...] = ()  # the line of each passive_joints entry
    disable_collisions: tuple[tuple[str, str, str, int | None], ...] = ()  # l1, l2, reason, line
    disable_default: tuple[tuple[str, int | None], ...] = ()
    enable_collisions: tuple[tuple[str, str, int | None], ...] = ()
    spheres: tuple[tuple[str, tuple[Sphere, ...], int | None], ...] = ()
    #: What reading the file said that is no error (xacro's warnings for an SRDF xacro).
    warnings: tuple[Diagnostic, ...] = ()
    #: ``key -> (file, line)`` of the elements of an SRDF xacro that a macro of an included
    #: file writes (their ``line``, a line of :attr:`path`, is None): see
    #: :mod:`xrdf_tools.robot.xacro_places`.
    include_places: Mapping[ElementKey, Place] = field(default_factory=FrozenMap)

    def where(self, key: ElementKey, line: int | None) -> tuple[str, int | None]:
        """File and line of the element ``key`` whose line in :attr:`path` is ``line``: that
        line, else where an included file writes it, else ``(path, None)``."""
        if line is None and key in self.include_places:
            return self.include_places[key]
        return self.path, line

    def at(self, element: _Placed) -> tuple[str, int | None]:
        """File and line of a group, group state, end effector or virtual joint."""
        return self.where(element.key, element.line)

    def element_keys(self) -> Iterator[tuple[ElementKey, int | None]]:
        """Every element read, by key, with its line in :attr:`path`."""
        for g in self.groups.values():
            yield g.key, g.line
        elements: list[_Placed] = [*self.group_states, *self.end_effectors, *self.virtual_joints]
        for el in elements:
            yield el.key, el.line
        for name, line in zip(self.passive_joints, self.passive_joint_lines, strict=False):
            yield ("passive_joint", name), line
        for l1, l2, _, line in self.disable_collisions:
            yield ("disable_collisions", l1, l2), line
        for link, line in self.disable_default:
            yield ("disable_default_collisions", link), line
        for l1, l2, line in self.enable_collisions:
            yield ("enable_collisions", l1, l2), line
        for link, _, line in self.spheres:
            yield ("link_sphere_approximation", link), line


def load_srdf(
    path: str | os.PathLike[str],
    *,
    xacro_args: Mapping[str, str] | None = None,
    package_paths: PackagePaths | None = None,
) -> Srdf:
    """Read an SRDF file; raises :class:`SourceError` (with the line) when it cannot be used.

    An SRDF xacro (``robot.srdf.xacro``, as MoveIt configurations ship them) is expanded with
    ``xacro_args`` and ``package_paths`` first, as MoveIt's launch files do (the robot's
    arguments: one it does not read is no finding); an element written literally in the xacro
    file is reported at its line there, one a macro of an included file writes at its line in
    that file (:attr:`Srdf.include_places`, :meth:`Srdf.where`), or at the macro call that
    makes it when its name is all expressions."""
    from ...robot.xacro_source import expand_xacro, uses_xacro

    p = os.fspath(path)
    data = read_input_bytes(p, what="SRDF file", error=SourceError)
    if not (p.endswith(".xacro") or uses_xacro(data)):
        return parse_srdf(data, p)
    said: list[Diagnostic] = []
    included: list[str] = []
    text = expand_xacro(
        p,
        xacro_args,
        package_paths,
        data=data,
        warnings=said,
        warn_unread_args=False,
        includes=included,
    )
    source = data.decode("utf-8", errors="replace")
    srdf = parse_srdf(text, p, xacro_source=source)
    unplaced = [key for key, line in srdf.element_keys() if line is None]
    places = included_places(unplaced, [p, *included], SRDF_KEYS)
    return replace(srdf, warnings=tuple(said), include_places=FrozenMap(places))


def parse_srdf(
    data: bytes | str,
    path: str = "<srdf>",
    *,
    located: bool = True,
    xacro_source: str | None = None,
) -> Srdf:
    """Parse SRDF text; raises :class:`SourceError` (with the line) for malformed XML, a root
    that is not ``<robot>``, a missing attribute, a value that is not a number, or a group
    defined twice. Elements other than those MoveIt defines are ignored. ``located=False``:
    the text is not the file at ``path``, so no element has a line; ``xacro_source``: the text
    is the expansion of the xacro file at ``path`` whose text this is, so an element has the
    line it is written at there (none when a macro made it)."""
    from ...robot.urdf_source import relocate_expansion

    try:
        root = parse_xml(utf8_xml_bytes(data), keep_comments=False)
    except XmlSyntaxError as e:
        raise SourceError(f"malformed SRDF XML: {e.verbatim}", path=path, line=e.line) from None
    if root is None or root.tag != "robot":
        raise SourceError("the root element of an SRDF must be <robot>", path=path, line=1)
    if xacro_source is not None:
        relocate_expansion(root, xacro_source)
    refuse_urdf(root, path, located=located)
    p = _Parser(path, located)
    for el in root:
        if isinstance(el.tag, str) and el.tag in _ELEMENTS:
            _ELEMENTS[el.tag](p, el)
    return Srdf(
        path=path,
        robot_name=root.get("name") or "",
        groups=p.groups,
        group_states=tuple(p.states),
        end_effectors=tuple(p.ees),
        virtual_joints=tuple(p.vjs),
        passive_joints=tuple(p.passive),
        passive_joint_lines=tuple(p.passive_lines),
        disable_collisions=tuple(p.disabled),
        disable_default=tuple(p.disable_default),
        enable_collisions=tuple(p.enabled),
        spheres=tuple(p.spheres),
    )


def refuse_urdf(root: Any, path: str, *, located: bool = True) -> None:
    """:class:`SourceError` when the ``<robot>`` element ``root`` is a URDF's: it has
    ``<link>``/``<joint>`` children and none of the elements an SRDF defines (the URDF and the
    SRDF of a MoveIt configuration share the root tag, so one passed for the other would
    otherwise read as an SRDF that says nothing)."""
    kids = [el for el in root if isinstance(el.tag, str)]
    if any(el.tag in _ELEMENTS for el in kids):
        return
    urdf = next((el for el in kids if el.tag in ("link", "joint")), None)
    if urdf is None:
        return
    raise SourceError(
        f"a URDF, not a MoveIt SRDF: it defines <{urdf.tag} name='{urdf.get('name') or ''}'> "
        "and no SRDF element (group, group_state, disable_collisions, ...); give the MoveIt "
        "configuration's .srdf (or .srdf.xacro)",
        path=path,
        line=int(urdf.sourceline) if located and urdf.sourceline is not None else None,
    )


class _Parser:
    """What has been read so far, and attribute access that raises at the element's line."""

    def __init__(self, path: str, located: bool = True) -> None:
        self.path = path
        self.located = located
        self.groups: dict[str, SrdfGroup] = {}
        self.states: list[GroupState] = []
        self.ees: list[EndEffector] = []
        self.vjs: list[VirtualJoint] = []
        self.passive: list[str] = []
        self.passive_lines: list[int | None] = []
        self.disabled: list[tuple[str, str, str, int | None]] = []
        self.disable_default: list[tuple[str, int | None]] = []
        self.enabled: list[tuple[str, str, int | None]] = []
        self.spheres: list[tuple[str, tuple[Sphere, ...], int | None]] = []

    def line(self, el: Any) -> int | None:
        """The line of ``el`` in the file, when the parsed text is the file."""
        return int(el.sourceline) if self.located and el.sourceline is not None else None

    def req(self, el: Any, attr: str) -> str:
        """A required, non-empty attribute, trimmed of surrounding spaces as MoveIt's SRDF
        reader trims names (``link1=" a"`` names link ``a``)."""
        v = trimmed(el, attr)
        if not v:
            raise SourceError(
                f"<{el.tag}> needs a '{attr}' attribute", path=self.path, line=self.line(el)
            )
        return v

    def num(self, el: Any, attr: str) -> float:
        """A required number attribute (its first word, as MoveIt reads it)."""
        raw_v = self.req(el, attr)
        try:
            return float(raw_v.split()[0])
        except (ValueError, IndexError):
            raise SourceError(
                f"<{el.tag}> {attr}='{raw_v}' is not a number", path=self.path, line=self.line(el)
            ) from None


def trimmed(el: Any, attr: str) -> str | None:
    """Attribute ``attr`` of ``el`` without surrounding spaces, as MoveIt's SRDF reader
    trims names (None when absent)."""
    v = el.get(attr)
    return None if v is None else str(v).strip()


def _group(p: _Parser, el: Any) -> None:
    name = p.req(el, "name")
    links, joints, chains, subs = [], [], [], []
    for c in el:
        if c.tag == "link":
            links.append(p.req(c, "name"))
        elif c.tag == "joint":
            joints.append(p.req(c, "name"))
        elif c.tag == "chain":
            chains.append((p.req(c, "base_link"), p.req(c, "tip_link")))
        elif c.tag == "group":
            subs.append(p.req(c, "name"))
    if name in p.groups:
        raise SourceError(
            f"group '{name}' is defined twice"
            + (f" (first on line {first})" if (first := p.groups[name].line) else ""),
            path=p.path,
            line=p.line(el),
        )
    p.groups[name] = SrdfGroup(
        name, tuple(links), tuple(joints), tuple(chains), tuple(subs), p.line(el)
    )


def _group_state(p: _Parser, el: Any) -> None:
    joints = [j for j in el if j.tag == "joint"]
    values = tuple((p.req(j, "name"), p.num(j, "value")) for j in joints)
    multi = tuple(p.req(j, "name") for j in joints if len(j.get("value").split()) > 1)
    p.states.append(GroupState(p.req(el, "name"), trimmed(el, "group"), values, p.line(el), multi))


def _end_effector(p: _Parser, el: Any) -> None:
    p.ees.append(
        EndEffector(
            p.req(el, "name"),
            p.req(el, "parent_link"),
            trimmed(el, "group"),
            trimmed(el, "parent_group"),
            p.line(el),
        )
    )


def _virtual_joint(p: _Parser, el: Any) -> None:
    p.vjs.append(
        VirtualJoint(
            p.req(el, "name"),
            trimmed(el, "type") or "",
            trimmed(el, "child_link") or "",
            p.line(el),
        )
    )


def _passive_joint(p: _Parser, el: Any) -> None:
    p.passive.append(p.req(el, "name"))
    p.passive_lines.append(p.line(el))


def _disable_collisions(p: _Parser, el: Any) -> None:
    p.disabled.append((p.req(el, "link1"), p.req(el, "link2"), el.get("reason") or "", p.line(el)))


def _disable_default(p: _Parser, el: Any) -> None:
    p.disable_default.append((p.req(el, "link"), p.line(el)))


def _enable_collisions(p: _Parser, el: Any) -> None:
    p.enabled.append((p.req(el, "link1"), p.req(el, "link2"), p.line(el)))


def _sphere_approximation(p: _Parser, el: Any) -> None:
    ss = []
    for s in el:
        if s.tag != "sphere":
            continue
        c = p.req(s, "center").split()
        try:
            center = (float(c[0]), float(c[1]), float(c[2]))
        except (ValueError, IndexError):
            raise SourceError(
                f"sphere center '{' '.join(c)}' must be three numbers",
                path=p.path,
                line=p.line(s),
            ) from None
        ss.append(Sphere(center, p.num(s, "radius")))
    p.spheres.append((p.req(el, "link"), tuple(ss), p.line(el)))


#: The SRDF elements read, by tag, each with its reader.
_ELEMENTS: dict[str, Callable[[_Parser, Any], None]] = {
    "group": _group,
    "group_state": _group_state,
    "end_effector": _end_effector,
    "virtual_joint": _virtual_joint,
    "passive_joint": _passive_joint,
    "disable_collisions": _disable_collisions,
    "disable_default_collisions": _disable_default,
    "enable_collisions": _enable_collisions,
    "link_sphere_approximation": _sphere_approximation,
}
