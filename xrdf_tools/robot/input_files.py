"""The files a robot description is read from: the URDF or xacro, the files its xacro macros
came from, and the mesh files of its links (visual and collision).

Commands that write a file check their output against these, so that an output path that
names a mesh of the robot is refused like one that names the URDF (a mesh overwritten by a
picture or a recording would be lost, and the robot with it).
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..util.errors import XrdfToolsError

if TYPE_CHECKING:
    import yourdfpy

    from .core import Robot

__all__ = ["robot_input_files"]


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
    """The mesh file names of the links' visual and collision elements, in document order.

    Read from the checked XML tree when the robot has one, so that checking an output path
    imports no geometry library (yourdfpy and trimesh take about a second to import)."""
    if robot.document is None:
        return [uri for link in robot.urdf.link_map.values() for uri in _yourdfpy_mesh_uris(link)]
    uris: list[str] = []
    for link in robot.document.findall("link"):
        for element in [*link.findall("visual"), *link.findall("collision")]:
            mesh = element.find("geometry/mesh")
            if mesh is not None and mesh.get("filename"):
                uris.append(str(mesh.get("filename")))
    return uris


def _yourdfpy_mesh_uris(link: Any) -> list[str]:
    """The mesh file names of one yourdfpy link's visual and collision elements."""
    uris: list[str] = []
    for element in [*(link.visuals or ()), *(link.collisions or ())]:
        mesh = getattr(element.geometry, "mesh", None) if element.geometry else None
        if mesh is not None and mesh.filename:
            uris.append(str(mesh.filename))
    return uris
