"""The yourdfpy object of a loaded robot, for the readers of link geometry.

:class:`~xrdf_tools.robot.core.Robot` is read from the project's own checked XML parse; only code
that reads meshes needs yourdfpy (and trimesh, the ``fit`` extra). :func:`build_yourdfpy` builds
it from the same checked tree, with :func:`make_filename_handler` resolving ``package://``,
``file://`` and relative mesh URIs without ROS.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..util.errors import UrdfError, XrdfToolsError

if TYPE_CHECKING:
    import yourdfpy

    from .packages import PackagePaths

__all__ = ["build_yourdfpy", "make_filename_handler"]


def make_filename_handler(
    path: str | os.PathLike[str] | None,
    package_paths: PackagePaths | None = None,
) -> Callable[[str], str]:
    """A yourdfpy ``filename_handler``: ``package://``, ``file://`` and relative mesh URIs.

    Packages come from ``package_paths`` first, then from ``package.xml`` files near ``path``
    (:class:`xrdf_tools.robot.packages.PackageResolver`). An unresolvable URI is returned unchanged
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


def build_yourdfpy(
    document: Any, path: str, package_paths: PackagePaths, build_scene_graph: bool
) -> yourdfpy.URDF:
    """The yourdfpy object of a loaded robot's checked ``<robot>`` tree (no meshes loaded)."""
    from ..util.extras import FIT, require

    require(FIT, "fit", "reading link geometry")
    import yourdfpy

    try:
        parsed = yourdfpy.URDF._parse_robot(xml_element=document)
        return yourdfpy.URDF(
            robot=parsed,
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
