"""The files a robot description is read from: the URDF or xacro, the files its xacro macros
came from, and the mesh files of its links (visual and collision).

Commands that write a file check their output against these, so that an output path that
names a mesh of the robot is refused like one that names the URDF (a mesh overwritten by a
picture or a recording would be lost, and the robot with it).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal, TypeVar

from ..util.errors import XrdfToolsError

if TYPE_CHECKING:
    import yourdfpy

    from .core import Robot

__all__ = [
    "GeometryChoice",
    "GeometrySource",
    "choose_elements",
    "link_mesh_names",
    "robot_input_files",
]

#: Which kind of a link's elements geometry comes from.
GeometrySource = Literal["collision", "visual"]
#: Which elements are read: only collision, only visual, or collision with visual as the
#: fallback for links without collision elements.
GeometryChoice = Literal["collision", "visual", "auto"]

_Element = TypeVar("_Element")


def robot_input_files(robot: Robot | yourdfpy.URDF) -> list[Path]:
    """The robot file, the files its xacro expansion included, and every mesh
    file its links name that can be found (no mesh is read; a URI that resolves to nothing is
    left out, there is nothing to overwrite there), each once, in document order."""
    from .core import as_robot

    loaded = as_robot(robot)
    files: dict[Path, None] = {}
    if loaded.path and not loaded.path.startswith("<"):
        files[Path(loaded.path)] = None
    for file in loaded.included_files:
        files[Path(file)] = None
    base = Path(loaded.path).resolve().parent
    resolver = loaded.mesh_resolver()
    for uri in _mesh_uris(loaded):
        try:
            files[resolver.resolve_uri(uri, base)] = None
        except XrdfToolsError:
            continue  # not found: nothing on disk that an output could replace
    return list(files)


def _mesh_uris(robot: Robot) -> list[str]:
    """The mesh file names of the links' visual and collision elements, in document order."""
    visual = link_mesh_names(robot, "visual")
    collision = link_mesh_names(robot, "collision")
    return [uri for v, c in zip(visual, collision, strict=True) for uri in [*v[2], *c[2]] if uri]


def choose_elements(
    collisions: list[_Element], visuals: list[_Element], choice: GeometryChoice
) -> tuple[GeometrySource, list[_Element]]:
    """The elements of a link that ``choice`` reads (``auto``: the collision elements, the
    visual ones for a link without any), and which kind they are."""
    if choice == "visual":
        return "visual", visuals
    if collisions or choice == "collision":
        return "collision", collisions
    return "visual", visuals


def link_mesh_names(
    robot: Robot, choice: GeometryChoice, links: Sequence[str] | None = None
) -> list[tuple[str, GeometrySource, list[str | None]]]:
    """Per link of ``links`` (default: every link), the kind of elements ``choice`` reads and
    each element's mesh file name (None: not a mesh; "": a mesh without one).

    Read from the checked XML tree when the robot has one, so that looking for mesh files
    imports no geometry library (yourdfpy and trimesh take about a second to import)."""
    names = robot.links if links is None else list(dict.fromkeys(links))
    if robot.document is None:
        link_map: Mapping[str, Any] = robot.urdf.link_map
        pairs = [
            (name, list(link.collisions or ()), list(link.visuals or ()), _yourdfpy_mesh_name)
            for name in names
            if (link := link_map.get(name)) is not None
        ]
    else:
        by_name: dict[str, Any] = {}
        for link in robot.document.findall("link"):
            by_name.setdefault(str(link.get("name")), link)
        pairs = [
            (name, link.findall("collision"), link.findall("visual"), _xml_mesh_name)
            for name in names
            if (link := by_name.get(name)) is not None
        ]
    out: list[tuple[str, GeometrySource, list[str | None]]] = []
    for name, collisions, visuals, mesh_name in pairs:
        kind, elements = choose_elements(collisions, visuals, choice)
        out.append((name, kind, [mesh_name(e) for e in elements]))
    return out


def _yourdfpy_mesh_name(element: Any) -> str | None:
    mesh = getattr(element.geometry, "mesh", None) if element.geometry is not None else None
    return None if mesh is None else str(mesh.filename or "")


def _xml_mesh_name(element: Any) -> str | None:
    mesh = element.find("geometry/mesh")
    return None if mesh is None else str(mesh.get("filename") or "")
