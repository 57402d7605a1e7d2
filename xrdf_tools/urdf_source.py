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

import os
import re
from collections.abc import Callable, Mapping
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
import numpy.typing as npt

from .errors import UrdfError, UrdfReadError, XrdfToolsError
from .urdf_check import JOINT_TYPES, check_urdf_tree

if TYPE_CHECKING:
    import yourdfpy

    from .robot import Robot

FloatArray = npt.NDArray[np.float64]

MOVABLE_TYPES = ("revolute", "continuous", "prismatic")

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
    from .link_geometry import capsules_as_cylinders
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
    link_lines, joint_lines = check_urdf_tree(root, path)
    etree.cleanup_namespaces(root)
    capsules = capsules_as_cylinders(root)  # yourdfpy knows no <capsule>

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
        capsules,
    )
    attach(robot)
    return robot
