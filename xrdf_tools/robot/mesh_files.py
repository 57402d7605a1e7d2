"""Read one mesh file as ROS's mesh loader reads it (RViz, MoveIt, Gazebo: assimp).

trimesh differs from it on two COLLADA points that real robot descriptions rely on:

* ``<asset><unit meter="0.001"/>``: assimp scales the scene to metres; trimesh keeps the file's
  numbers, so a part modelled in millimetres would come out 1000 times too large.
* a node whose ``<instance_material>`` names a material the file does not define (some CAD
  exporters write one): assimp draws the geometry without that material; pycollada rejects the
  node, and trimesh drops it with its geometry, so the part would read as "no triangles".
  Such bindings are removed and the file read again; materials play no part in collision.

A COLLADA file is checked first by :func:`~xrdf_tools.robot.collada_points.check_collada_bounds`:
pycollada expands every ``<instance_node>`` without a bound (a node instanced twice at each
of 60 levels never ends), so a scene past the bounds raises
:class:`~xrdf_tools.robot.collada_points.ColladaTooBig` before trimesh sees it.
"""

from __future__ import annotations

import errno
import io
import os
import stat
from pathlib import Path
from typing import Any

from ..util.errors import XrdfToolsError
from ..util.fileio import BINARY_STL_TRIANGLE_BYTES, file_kind
from ..util.safe_xml import XmlSyntaxError, parse_xml

__all__ = [
    "MeshTooBig",
    "binary_stl_counts",
    "binary_stl_size",
    "drawn_triangles",
    "load_mesh_parts",
    "load_mesh_scene",
    "not_a_file",
    "too_many_triangles",
    "unreadable",
    "without_broken_material_bindings",
]


def load_mesh_scene(path: Path) -> Any:
    """The file at ``path`` as an unprocessed ``trimesh.Scene``, in metres for COLLADA.
    numpy's warnings on a file with non-finite vertices are not printed: the caller checks
    the vertices and says which file."""
    import numpy as np

    with np.errstate(all="ignore"):
        return _load_scene(path)


def load_mesh_parts(path: Path, max_triangles: int | None = None) -> list[Any]:
    """The meshes of the file at ``path`` (``trimesh.Scene.dump``: each in the scene frame,
    which applies the scene's transforms), without numpy's warnings, as
    :func:`load_mesh_scene`. Raises :class:`MeshTooBig` when the scene draws more than
    ``max_triangles`` triangles (default :func:`~xrdf_tools.util.fileio.mesh_triangle_limit`),
    every instance counted, before they are copied: a 4 MB glTF file drawing one mesh from
    5,000 nodes would dump 36 GB."""
    import numpy as np

    from ..util.fileio import mesh_triangle_limit

    limit = mesh_triangle_limit() if max_triangles is None else max_triangles
    with np.errstate(all="ignore"):
        scene = _load_scene(path)
        count = drawn_triangles(scene)
        if count > limit:
            raise MeshTooBig(too_many_triangles(count, limit))
        return list(scene.dump())


class MeshTooBig(XrdfToolsError):
    """A mesh file whose scene draws more triangles than the limit (the message says so)."""


def drawn_triangles(scene: Any) -> int:
    """The triangles ``scene`` (a ``trimesh.Scene``) draws: each geometry's once per node
    that instances it, as ``scene.dump()`` copies them."""
    total = 0
    for node in scene.graph.nodes_geometry:
        faces = getattr(scene.geometry.get(scene.graph[node][1]), "faces", None)
        total += 0 if faces is None else len(faces)
    return total


def _load_scene(path: Path) -> Any:
    import trimesh

    if path.suffix.lower() == ".dae":
        from ..util.fileio import mesh_bytes_limit, read_input_bytes
        from .collada_points import check_collada_bounds

        check_collada_bounds(read_input_bytes(path, what="mesh file", max_bytes=mesh_bytes_limit()))
    scene: Any = trimesh.load(str(path), force="scene", process=False)
    if path.suffix.lower() != ".dae":
        return scene
    if not scene.geometry:
        repaired = without_broken_material_bindings(path.read_bytes())
        if repaired is not None:
            scene = trimesh.load(
                io.BytesIO(repaired),
                file_type="dae",
                force="scene",
                process=False,
                resolver=trimesh.resolvers.FilePathResolver(str(path)),
            )
    if scene.geometry and scene.units not in (None, "meters"):
        scene = scene.convert_units("meters")
    return scene


def without_broken_material_bindings(data: bytes) -> bytes | None:
    """The COLLADA document ``data`` without the ``<instance_material>`` elements whose target
    is not a ``<material>`` of the document, or None when there is none (or it is not XML)."""
    try:
        root = parse_xml(data, keep_comments=False)
    except XmlSyntaxError:
        return None
    defined = {m.get("id") for m in root.iter("{*}material") if m.get("id")}
    broken = [
        binding
        for binding in root.iter("{*}instance_material")
        if (binding.get("target") or "").removeprefix("#") not in defined
    ]
    if not broken:
        return None
    for binding in broken:
        binding.getparent().remove(binding)
    from lxml import etree

    return bytes(etree.tostring(root, xml_declaration=True, encoding="utf-8"))


def unreadable(path: Path, e: Exception | None) -> str:
    """Why the mesh file ``path`` gave no mesh: the reader's error ``e`` (None: the file read
    but held no triangles), or a Git LFS pointer in place of the mesh (a clone without
    git-lfs), with what to do."""
    with open(path, "rb") as f:
        if f.read(len(_LFS_POINTER)) == _LFS_POINTER:
            return "a Git LFS pointer, not the mesh: run `git lfs pull` in its repository"
    if e is None:
        counts = binary_stl_counts(path)
        if counts is not None and counts[0] != counts[1]:
            return (
                f"a binary STL whose header counts {counts[0]:,} triangles, but whose "
                f"{path.stat().st_size:,} bytes hold {counts[1]:,}"
            )
        return "no triangles in the file"
    if isinstance(e, _READER_SLIPS) or not str(e):
        kind = path.suffix.lstrip(".").upper() or "mesh"
        return f"a malformed {kind} file, or one of a form the mesh reader does not know"
    return str(e).splitlines()[0]


def binary_stl_counts(path: Path) -> tuple[int, int] | None:
    """For a file named ``*.stl`` that is not ASCII STL: the number of triangles its header
    counts and the number its size holds (84 bytes of header, 50 a triangle); else None."""
    if path.suffix.lower() != ".stl":
        return None
    size = path.stat().st_size
    with open(path, "rb") as f:
        head = f.read(84)
    if len(head) < _STL_HEAD or (head[:5].lower() == b"solid" and size != binary_stl_size(head)):
        return None
    return int.from_bytes(head[80:_STL_HEAD], "little"), (size - _STL_HEAD) // _STL_TRIANGLE


#: Bytes of a binary STL's header (80 of text, 4 of triangle count) and of each triangle.
_STL_HEAD, _STL_TRIANGLE = 84, BINARY_STL_TRIANGLE_BYTES


def binary_stl_size(head: bytes) -> int:
    """The size of a binary STL whose first 84 bytes are ``head``, by its header's count."""
    return _STL_HEAD + _STL_TRIANGLE * int.from_bytes(head[80:_STL_HEAD], "little")


def too_many_triangles(count: int, limit: int) -> str:
    """Why a mesh of ``count`` triangles is not read, past ``limit``: with what to do."""
    return (
        f"{count:,} triangles, more than the {limit:,} a mesh may have (what a binary STL at "
        f"the mesh size limit holds); simplify it (a collision mesh needs far fewer) or raise "
        f"XRDF_TOOLS_MAX_INPUT_MB"
    )


#: What the mesh readers raise when their own code trips over a malformed file: the message
#: ("'NoneType' object has no attribute 'nodes'") says nothing about the file.
_READER_SLIPS = (AttributeError, TypeError, IndexError, KeyError)

_LFS_POINTER = b"version https://git-lfs.github.com/spec/"


def _as_looked_for(path: Path) -> str:
    """``path`` without its ``dir/..`` parts, unless that names a file that exists: the system
    does not drop ``x/..`` when ``x`` is missing, so ``x/../a.stl`` is not found even where
    ``a.stl`` is."""
    short = os.path.normpath(path)
    return str(path) if os.path.exists(short) else short


def not_a_file(path: Path) -> str | None:
    """Why ``path`` cannot be opened as a mesh file, or None when it is a regular file."""
    try:
        st = os.stat(path)
    except OSError as e:
        if e.errno in (errno.ENOENT, errno.ENOTDIR):
            return f"mesh file not found ({_as_looked_for(path)})"
        if e.errno == errno.ELOOP:
            return f"a symbolic link loop, not a mesh file ({path})"
        if e.errno == errno.ENAMETOOLONG:
            longest = max((len(part.encode()) for part in path.parts), default=0)
            return (
                f"file name too long for this file system ({longest} bytes in one name, "
                f"{len(os.fsencode(path))} in the path)"
            )
        return f"cannot open the mesh file: {e.strerror or e} ({path})"
    if stat.S_ISREG(st.st_mode):
        return None
    return f"{file_kind(st.st_mode)}, not a mesh file ({path})"
