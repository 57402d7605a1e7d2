"""Read a URDF through yourdfpy, without meshes, with errors that name the file and line.

The XML is parsed strictly by lxml first (entities are not resolved, no network), then checked
for what yourdfpy would crash on or silently get wrong: missing names, unknown joint types,
duplicate links or joints, joints that refer to unknown links, numbers that do not parse. Only
then is the tree handed to yourdfpy. Every failure is a :class:`UrdfError` whose one-line
message starts with ``path:line:`` when the line is known.

:class:`JointInfo`, :func:`joints_of` and :func:`links_of` give a plain, typed view of a loaded
URDF for the kinematics, the linter and the converter. yourdfpy is imported lazily so that
commands which never read a URDF start fast.
"""

from __future__ import annotations

import math
import os
import re
from collections.abc import Callable, Mapping
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
import numpy.typing as npt

from .errors import UrdfError, UrdfReadError, XrdfToolsError, did_you_mean

if TYPE_CHECKING:
    import yourdfpy

    from .robot import Robot

FloatArray = npt.NDArray[np.float64]

JOINT_TYPES = ("revolute", "continuous", "prismatic", "fixed", "floating", "planar")
MOVABLE_TYPES = ("revolute", "continuous", "prismatic")
XACRO_NS = "http://www.ros.org/wiki/xacro"

__all__ = [
    "JOINT_TYPES",
    "MOVABLE_TYPES",
    "JointInfo",
    "joint_info",
    "joints_of",
    "links_of",
    "load_urdf",
    "make_filename_handler",
    "parse_robot",
    "parse_urdf_string",
    "read_robot",
    "source_line",
    "urdf_path",
]


# --------------------------------------------------------------------------------------------
# Joint view
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class JointInfo:
    """One URDF joint as plain values.

    ``origin`` is the (4, 4) read-only transform from the parent link to the joint frame (which
    is also the child link frame at joint value 0). ``axis`` is the axis as written (default
    ``(1, 0, 0)``, not normalised). ``lower``/``upper``/``velocity`` are ``None`` when the URDF
    does not give them. A mimic follower has ``mimic_joint`` set and moves as
    ``mimic_multiplier * q[mimic_joint] + mimic_offset``. ``line`` is the line of the
    ``<joint>`` element when known.
    """

    name: str
    type: str
    parent: str
    child: str
    origin: FloatArray
    axis: tuple[float, float, float] = (1.0, 0.0, 0.0)
    lower: float | None = None
    upper: float | None = None
    velocity: float | None = None
    mimic_joint: str | None = None
    mimic_multiplier: float = 1.0
    mimic_offset: float = 0.0
    line: int | None = None

    def __post_init__(self) -> None:
        origin = np.array(self.origin, dtype=np.float64, copy=True)
        if origin.shape != (4, 4):
            raise ValueError(f"joint '{self.name}': origin must be 4x4, got {origin.shape}")
        origin.flags.writeable = False
        object.__setattr__(self, "origin", origin)

    @property
    def is_movable(self) -> bool:
        """Revolute, continuous or prismatic (floating and planar joints are not modelled)."""
        return self.type in MOVABLE_TYPES

    @property
    def is_mimic(self) -> bool:
        return self.mimic_joint is not None

    @property
    def is_actuated(self) -> bool:
        """Movable and not a mimic follower: a coordinate of the configuration."""
        return self.is_movable and not self.is_mimic

    def replace(self, **changes: Any) -> JointInfo:
        return replace(self, **changes)

    def _key(self) -> tuple[Any, ...]:
        return (
            self.name,
            self.type,
            self.parent,
            self.child,
            self.origin.tobytes(),
            self.axis,
            self.lower,
            self.upper,
            self.velocity,
            self.mimic_joint,
            self.mimic_multiplier,
            self.mimic_offset,
        )

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, JointInfo):
            return NotImplemented
        return self._key() == other._key()

    def __hash__(self) -> int:
        return hash((self.name, self.type, self.parent, self.child))


def links_of(urdf: Robot | yourdfpy.URDF) -> list[str]:
    """Link names in document order."""
    from .robot import as_robot

    return list(as_robot(urdf).links)


def root_link(urdf: Robot | yourdfpy.URDF) -> str:
    """The one link that is no joint's child; :class:`UrdfError` when there is not exactly one."""
    from .robot import as_robot

    return as_robot(urdf).root_link()


def joints_of(urdf: Robot | yourdfpy.URDF) -> dict[str, JointInfo]:
    """Every ``<joint>`` of the robot as :class:`JointInfo`, keyed by name, in document order."""
    from .robot import as_robot

    return dict(as_robot(urdf).joints)


def joint_info(j: Any, line: int | None) -> JointInfo:
    """One yourdfpy joint as :class:`JointInfo` (``line``: of its ``<joint>`` element)."""
    name = str(j.name)
    origin = np.eye(4) if j.origin is None else np.asarray(j.origin, dtype=np.float64)
    axis_arr = np.array([1.0, 0.0, 0.0]) if j.axis is None else np.asarray(j.axis, dtype=np.float64)
    limit = j.limit
    mimic = j.mimic
    return JointInfo(
        name=name,
        type=str(j.type),
        parent=str(j.parent),
        child=str(j.child),
        origin=origin,
        axis=(float(axis_arr[0]), float(axis_arr[1]), float(axis_arr[2])),
        lower=_opt_float(limit.lower) if limit is not None else None,
        upper=_opt_float(limit.upper) if limit is not None else None,
        velocity=_opt_float(limit.velocity) if limit is not None else None,
        mimic_joint=str(mimic.joint) if mimic is not None else None,
        mimic_multiplier=(
            1.0 if mimic is None or mimic.multiplier is None else float(mimic.multiplier)
        ),
        mimic_offset=0.0 if mimic is None or mimic.offset is None else float(mimic.offset),
        line=line,
    )


def _opt_float(v: Any) -> float | None:
    return None if v is None else float(v)


# --------------------------------------------------------------------------------------------
# Where a loaded URDF came from (fields of its :class:`~xrdf_tools.robot.Robot`)
# --------------------------------------------------------------------------------------------
def urdf_path(urdf: Robot | yourdfpy.URDF) -> str:
    """The path a URDF was loaded from by this module, or ``"<urdf>"``."""
    from .robot import as_robot

    return as_robot(urdf).path


def urdf_text(urdf: Robot | yourdfpy.URDF) -> str | None:
    """The text a URDF was parsed from by this module (an expanded xacro: the expansion)."""
    from .robot import as_robot

    return as_robot(urdf).text


def urdf_package_paths(urdf: Robot | yourdfpy.URDF) -> dict[str, str]:
    """The ``package_paths`` a URDF was loaded with (``{}`` when unknown)."""
    from .robot import as_robot

    return dict(as_robot(urdf).package_paths)


def source_line(
    urdf: Robot | yourdfpy.URDF, kind: Literal["link", "joint"], name: str
) -> int | None:
    """Line of the ``<link>``/``<joint>`` element named ``name`` (None if unknown)."""
    from .robot import as_robot

    return as_robot(urdf).source_line(kind, name)


# --------------------------------------------------------------------------------------------
# Loading
# --------------------------------------------------------------------------------------------
def load_urdf(
    path: str | os.PathLike[str],
    *,
    package_paths: Mapping[str, str] | None = None,
    build_scene_graph: bool = False,
) -> yourdfpy.URDF:
    """Load a URDF file without loading any mesh: the yourdfpy object of :func:`read_robot`
    (which carries its :class:`~xrdf_tools.robot.Robot`, see :func:`xrdf_tools.robot.as_robot`).
    """
    return read_robot(path, package_paths=package_paths, build_scene_graph=build_scene_graph).urdf


def read_robot(
    path: str | os.PathLike[str],
    *,
    package_paths: Mapping[str, str] | None = None,
    build_scene_graph: bool = False,
    data: bytes | None = None,
) -> Robot:
    """Load a URDF file without loading any mesh, as a :class:`~xrdf_tools.robot.Robot`.

    ``package_paths`` (``{"pkg": "/dir"}``) resolves ``package://pkg/...`` mesh URIs for
    whoever loads meshes later (see :func:`make_filename_handler`); meshes are never read here.
    ``build_scene_graph`` builds yourdfpy's scene graph (needed only for yourdfpy's own
    ``get_transform``; :mod:`xrdf_tools.kinematics` does not need it). ``data``: the file's
    bytes when the caller has already read them (:func:`read_urdf_bytes`): not read again.

    Raises :class:`UrdfError` (one line, with the path, and the line when known).
    """
    p = os.fspath(path)
    if data is None:
        data = read_urdf_bytes(p)
    return _parse_bytes(data, p, package_paths=package_paths, build_scene_graph=build_scene_graph)


def read_urdf_bytes(path: str | os.PathLike[str]) -> bytes:
    """The bytes of a URDF file, read through :func:`xrdf_tools.fileio.read_input_bytes`
    (regular files only, size limit); any failure is a one-line :class:`UrdfReadError` (the file
    cannot be used at all: a usage error, not a finding about the robot)."""
    from .fileio import read_input_bytes

    return read_input_bytes(path, what="URDF file", error=UrdfReadError)


_ENCODING_DECL = re.compile(r"^(\s*<\?xml[^>]*?)\s+encoding\s*=\s*(['\"])[^'\"]*\2", re.I)


def parse_urdf_string(
    text: str,
    path: str = "<string>",
    *,
    package_paths: Mapping[str, str] | None = None,
    build_scene_graph: bool = False,
) -> yourdfpy.URDF:
    """Parse URDF text (e.g. expanded xacro output); ``path`` is used in messages and to
    resolve relative mesh paths. See :func:`load_urdf`."""
    return parse_robot(
        text, path, package_paths=package_paths, build_scene_graph=build_scene_graph
    ).urdf


def parse_robot(
    text: str,
    path: str = "<string>",
    *,
    package_paths: Mapping[str, str] | None = None,
    build_scene_graph: bool = False,
    expanded: bool = False,
) -> Robot:
    """:func:`parse_urdf_string` as a :class:`~xrdf_tools.robot.Robot` (``expanded``: the
    text is the expansion of the xacro file ``path``)."""
    text = _ENCODING_DECL.sub(r"\1", text, count=1)
    return _parse_bytes(
        text.encode("utf-8"),
        path,
        package_paths=package_paths,
        build_scene_graph=build_scene_graph,
        expanded=expanded,
    )


def make_filename_handler(
    path: str | os.PathLike[str] | None,
    package_paths: Mapping[str, str] | None = None,
) -> Callable[[str], str]:
    """A yourdfpy ``filename_handler``: ``package://``, ``file://`` and relative mesh URIs.

    Packages come from ``package_paths`` first, then from ``package.xml`` files near ``path``
    (:class:`xrdf_tools.packages.PackageResolver`). An unresolvable URI is returned unchanged
    (yourdfpy then reports the missing mesh when it tries to load it).
    """
    from .packages import PackageResolver

    start = Path(os.fspath(path)) if path is not None else Path.cwd()
    if not start.exists():
        start = Path.cwd()
    resolver = PackageResolver(start, dict(package_paths or {}))

    def handler(fname: str) -> str:
        try:
            return str(resolver.resolve_uri(fname))
        except XrdfToolsError:
            return fname

    return handler


def _parse_bytes(
    data: bytes,
    path: str,
    *,
    package_paths: Mapping[str, str] | None,
    build_scene_graph: bool,
    expanded: bool = False,
) -> Robot:
    from lxml import etree

    from .frozen import FrozenMap
    from .robot import Robot, attach

    parser = etree.XMLParser(
        remove_blank_text=True, resolve_entities=False, no_network=True, huge_tree=True
    )
    try:
        root = etree.fromstring(data, parser)
    except etree.XMLSyntaxError as e:
        line, col = e.position if e.position else (e.lineno, None)
        msg = (e.msg or str(e) or "not well-formed").splitlines()[0]
        msg = re.sub(r",? line \d+, column \d+\s*$", "", msg)
        raise UrdfError(f"malformed XML: {msg}", path=path, line=line, col=col) from None
    if root is None:
        raise UrdfError("the file is empty", path=path, line=1)

    etree.strip_tags(root, etree.Comment)
    link_lines, joint_lines = _check_tree(root, path)
    etree.cleanup_namespaces(root)

    import yourdfpy

    try:
        robot = yourdfpy.URDF._parse_robot(xml_element=root)
        urdf = yourdfpy.URDF(
            robot=robot,
            build_scene_graph=build_scene_graph,
            build_collision_scene_graph=False,
            load_meshes=False,
            load_collision_meshes=False,
            filename_handler=make_filename_handler(path, package_paths),
            mesh_dir=os.path.dirname(path),
        )
    except Exception as e:  # yourdfpy raises bare KeyError/ValueError/AttributeError
        detail = str(e).splitlines()[0] if str(e) else type(e).__name__
        raise UrdfError(f"yourdfpy cannot read this URDF: {detail}", path=path) from None
    robot = Robot(
        urdf,
        path,
        data.decode("utf-8", errors="replace"),
        expanded,
        FrozenMap(link_lines),
        FrozenMap(joint_lines),
        FrozenMap(package_paths or {}),
    )
    attach(robot)
    return robot


def _check_tree(root: Any, path: str) -> tuple[dict[str, int], dict[str, int]]:
    """Check what yourdfpy needs; return the line of every link and joint."""
    from lxml import etree

    def fail(msg: str, el: Any) -> UrdfError:
        return UrdfError(msg, path=path, line=getattr(el, "sourceline", None))

    tag = etree.QName(root).localname if isinstance(root.tag, str) else str(root.tag)
    if tag != "robot":
        raise fail(f"the root element must be <robot>, not <{tag}>", root)
    for el in root.iter():
        if isinstance(el.tag, str) and etree.QName(el).namespace == XACRO_NS:
            raise fail(
                f"<xacro:{etree.QName(el).localname}> found: this is a xacro file; expand it "
                "first (xrdf convert reads .xacro files)",
                el,
            )
    if not root.get("name"):
        raise fail("<robot> has no 'name' attribute", root)

    link_lines: dict[str, int] = {}
    for el in root.findall("link"):
        name = el.get("name")
        if not name:
            raise fail("<link> has no 'name' attribute", el)
        if name in link_lines:
            raise fail(f"link '{name}' is defined twice (first on line {link_lines[name]})", el)
        link_lines[name] = el.sourceline or 0

    for el in root.findall("link"):
        _check_geometry(el, fail)

    joint_lines: dict[str, int] = {}
    edges: list[tuple[str, str, str, Any]] = []  # joint, parent, child, element
    for el in root.findall("joint"):
        name = el.get("name")
        if not name:
            raise fail("<joint> has no 'name' attribute", el)
        if name in joint_lines:
            raise fail(f"joint '{name}' is defined twice (first on line {joint_lines[name]})", el)
        joint_lines[name] = el.sourceline or 0
        jtype = el.get("type")
        if jtype not in JOINT_TYPES:
            what = f"type '{jtype}'" if jtype else "no 'type'"
            raise fail(
                f"joint '{name}' has {what}; valid: {', '.join(JOINT_TYPES)}"
                + (did_you_mean(jtype, JOINT_TYPES) if jtype else ""),
                el,
            )
        for role in ("parent", "child"):
            sub = el.find(role)
            link = sub.get("link") if sub is not None else None
            if not link:
                raise fail(f"joint '{name}' has no <{role} link='...'/>", el)
            if link not in link_lines:
                raise fail(
                    f"joint '{name}' refers to unknown {role} link '{link}'"
                    + did_you_mean(link, link_lines),
                    sub,
                )
        edges.append((name, el.find("parent").get("link"), el.find("child").get("link"), el))
        _check_numbers(el.find("origin"), ("xyz", "rpy"), 3, f"joint '{name}' <origin>", fail)
        _check_numbers(el.find("axis"), ("xyz",), 3, f"joint '{name}' <axis>", fail)
        _check_limit(el, name, jtype, fail)
        mimic = el.find("mimic")
        if mimic is not None:
            if not mimic.get("joint"):
                raise fail(f"joint '{name}' <mimic> has no 'joint' attribute", mimic)
            _check_numbers(mimic, ("multiplier", "offset"), 1, f"joint '{name}' <mimic>", fail)
    _check_is_tree(edges, joint_lines, fail)
    return link_lines, joint_lines


def _check_limit(el: Any, name: str, jtype: str, fail: Callable[[str, Any], UrdfError]) -> None:
    """Limit numbers are finite; a revolute or prismatic joint has ``lower <= upper``."""
    limit = el.find("limit")
    what = f"joint '{name}' <limit>"
    _check_numbers(limit, ("lower", "upper", "velocity", "effort"), 1, what, fail)
    if limit is None or jtype not in ("revolute", "prismatic"):
        return
    lower, upper = limit.get("lower"), limit.get("upper")
    if lower is not None and upper is not None and float(lower) > float(upper):
        raise fail(f"{what} lower={lower.strip()} is above upper={upper.strip()}", limit)


def _check_is_tree(
    edges: list[tuple[str, str, str, Any]],
    joint_lines: Mapping[str, int],
    fail: Callable[[str, Any], UrdfError],
) -> None:
    """Each link is the child of at most one joint, and parent links never loop back."""
    from .graph import find_cycle, show_path

    parent_of: dict[str, tuple[str, str]] = {}  # child link -> (joint, parent link)
    element: dict[str, Any] = {}
    for joint, parent, child, el in edges:
        element[joint] = el
        if parent == child:
            raise fail(f"joint '{joint}' has link '{child}' as both parent and child", el)
        if child in parent_of:
            first = parent_of[child][0]
            raise fail(
                f"link '{child}' is the child of two joints, '{first}' (line "
                f"{joint_lines.get(first)}) and '{joint}'; a URDF must be a tree",
                el,
            )
        parent_of[child] = (joint, parent)
    cycle = find_cycle(parent_of, lambda link: [parent_of[link][1]] if link in parent_of else [])
    if cycle is not None:
        joints = [parent_of[link][0] for link in cycle[:-1]]
        raise fail(
            f"the joints form a cycle ({show_path(list(reversed(cycle)))}, through joints "
            f"{show_path(list(reversed(joints)))}); a URDF must be a tree",
            element[joints[-1]],
        )


#: Numbers each geometry needs: element -> ((attribute, count, required), ...).
_GEOMETRY: dict[str, tuple[tuple[str, tuple[int, ...], bool], ...]] = {
    "box": (("size", (3,), True),),
    "cylinder": (("radius", (1,), True), ("length", (1,), True)),
    "capsule": (("radius", (1,), True), ("length", (1,), True)),
    "sphere": (("radius", (1,), True),),
    "mesh": (("scale", (3, 1), False),),
}


def _check_geometry(link: Any, fail: Callable[[str, Any], UrdfError]) -> None:
    """Visual and collision shapes have the numbers their type needs (finite, not negative)."""
    name = link.get("name")
    for kind in ("visual", "collision"):
        for item in link.findall(kind):
            _check_numbers(item.find("origin"), ("xyz", "rpy"), 3, f"link '{name}' <{kind}>", fail)
            geometry = item.find("geometry")
            for shape in () if geometry is None else geometry:
                for attr, counts, required in _GEOMETRY.get(shape.tag, ()):
                    what = f"link '{name}' <{kind}> <{shape.tag}>"
                    raw = shape.get(attr)
                    if raw is None:
                        if required:
                            raise fail(f"{what} has no '{attr}' attribute", shape)
                        continue
                    _check_numbers(shape, (attr,), counts, what, fail)
                    if shape.tag != "mesh" and any(float(x) < 0 for x in raw.split()):
                        raise fail(f"{what} {attr}='{raw}' must not be negative", shape)


def _check_numbers(
    el: Any,
    attrs: tuple[str, ...],
    count: int | tuple[int, ...],
    what: str,
    fail: Callable[[str, Any], UrdfError],
) -> None:
    """Each attribute present holds ``count`` finite numbers (one of the counts of a tuple)."""
    if el is None:
        return
    counts = (count,) if isinstance(count, int) else count
    for attr in attrs:
        raw = el.get(attr)
        if raw is None:
            continue
        parts = raw.split()
        shown = _shown(raw)
        try:
            values = [float(x) for x in parts]
        except ValueError:
            raise fail(f"{what} {attr}='{shown}' is not a number list", el) from None
        if len(parts) not in counts:
            n = " or ".join("a number" if c == 1 else f"{c} numbers" for c in counts)
            raise fail(f"{what} {attr}='{shown}' must be {n}", el)
        if not all(math.isfinite(v) for v in values):
            raise fail(f"{what} {attr}='{shown}' must be finite", el)


def _shown(raw: str, limit: int = 60) -> str:
    """An attribute value for a one-line message: whitespace folded, long values cut."""
    text = " ".join(raw.split())
    return text if len(text) <= limit else text[: limit - 3] + "..."
