"""The bounding box of a link's ``<visual>`` (or ``<collision>``) elements, read cheaply.

:func:`elements_bounds` gives the axis-aligned box, in the link frame, of one link's elements
of one kind, each with its ``<origin>`` and mesh ``scale`` applied, without building a mesh:

* ``box``, ``cylinder``, ``sphere`` and ``capsule`` from their sizes (a cylinder by two rings of
  points on its rims, a sphere and a capsule's end spheres exactly);
* binary and ASCII STL and OBJ files by reading their vertices with numpy (no faces, no
  processing: a 400 kB OBJ takes about a millisecond);
* COLLADA files by :func:`~xrdf_tools.robot.collada_points.collada_vertices` (the XML read
  with numpy, the scene's transforms and unit applied, the box trimesh gives); a file it
  gives up on is read like the other formats, unless its scene expands past the reader's
  bounds (then no reader is handed it);
* binary glTF (``.glb``) files by :func:`~xrdf_tools.robot.gltf_points.glb_vertices` (the
  binary chunk read with numpy, the nodes' transforms applied); a file it gives up on (a
  compressed primitive, ...) is read like the other formats, unless its scene expands past
  the reader's bounds (then no reader is handed it);
* other mesh formats (PLY, ...) through trimesh, as the sphere fitter reads them
  (:func:`~xrdf_tools.robot.mesh_files.load_mesh_parts`: COLLADA in metres), only when
  ``other_formats`` is true; else the link is not bounded and :attr:`Unbounded.format` names
  the format.

A link whose elements cannot all be read is :class:`Unbounded` (a box of part of its geometry
would compare wrongly); the reason says which element and why. Files are opened by the guarded
reader with the mesh size limit. Nothing here raises for a bad file.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..util.arrays import FloatArray
from ..util.errors import XrdfToolsError
from ..util.fileio import mesh_bytes_limit, read_input_bytes
from ..util.numbers import vertices_problem
from .collada_points import ColladaNotRead, ColladaTooBig, collada_vertices
from .gltf_points import GltfNotRead, GltfTooBig, glb_vertices
from .link_geometry import GeometrySource
from .mesh_files import binary_stl_size, not_a_file

if TYPE_CHECKING:
    from .core import Robot
    from .packages import PackageResolver

__all__ = ["Box", "Unbounded", "elements_bounds", "mesh_file_vertices"]

#: Points on each rim of a cylinder: the box of a turned cylinder within 0.5 % of its radius.
_RIM_POINTS = 32
_NUMPY_FORMATS = (".stl", ".obj")
_FLOAT = rb"([-+0-9.eEnaNifIF]+)"
_STL_VERTEX = re.compile(rb"vertex\s+" + _FLOAT + rb"\s+" + _FLOAT + rb"\s+" + _FLOAT)
_OBJ_VERTEX = re.compile(rb"^[ \t]*v[ \t]+" + _FLOAT + rb"\s+" + _FLOAT + rb"\s+" + _FLOAT, re.M)


@dataclass(frozen=True)
class Box:
    """An axis-aligned box: corners ``low`` and ``high`` (metres)."""

    low: FloatArray
    high: FloatArray

    @property
    def centre(self) -> FloatArray:
        return np.asarray((self.low + self.high) / 2.0, dtype=np.float64)

    @property
    def extents(self) -> FloatArray:
        return np.asarray(self.high - self.low, dtype=np.float64)

    def describe(self) -> str:
        """``x -0.08…0.08 y -0.205…0 z -0.08…0.08`` (metres, three decimals)."""
        return " ".join(
            f"{axis} {_num(lo)}…{_num(hi)}"
            for axis, lo, hi in zip("xyz", self.low, self.high, strict=True)
        )


@dataclass(frozen=True)
class Unbounded:
    """Why a link's elements have no box: ``reason``; ``format`` (``.dae``) when the only
    cause is a mesh format not read without trimesh."""

    reason: str
    format: str | None = None


def elements_bounds(
    robot: Robot,
    link: str,
    kind: GeometrySource,
    resolver: PackageResolver,
    *,
    other_formats: bool = True,
) -> Box | Unbounded | None:
    """The box of ``link``'s ``kind`` elements in the link frame; None when it has none."""
    element_list = list(getattr(robot.urdf.link_map[link], f"{kind}s", None) or ())
    if not element_list:
        return None
    base = Path(robot.path).resolve().parent
    points: list[FloatArray] = []
    for i, element in enumerate(element_list):
        capsule = (link, kind, i) in robot.capsules
        try:
            local = _element_points(element, capsule, resolver, base, other_formats)
        except _NotRead as e:
            return Unbounded(f"{kind} element {i + 1}: {e.reason}", e.format)
        origin = np.eye(4) if element.origin is None else np.asarray(element.origin, float)
        points.append(local @ origin[:3, :3].T + origin[:3, 3])
    every = np.concatenate(points)
    return Box(every.min(axis=0), every.max(axis=0))


class _NotRead(Exception):
    def __init__(self, reason: str, format: str | None = None) -> None:
        super().__init__(reason)
        self.reason = reason
        self.format = format


def _element_points(
    element: Any, capsule: bool, resolver: PackageResolver, base: Path, other_formats: bool
) -> FloatArray:
    """Points in the element frame whose box, turned by any origin, holds the element's."""
    geometry = element.geometry
    if geometry is None:
        raise _NotRead("no geometry")
    if geometry.mesh is not None:
        return _mesh_points(geometry.mesh, resolver, base, other_formats)
    if geometry.box is not None:
        half = np.asarray(geometry.box.size, dtype=np.float64) / 2.0
        signs = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])
        return np.asarray(signs * half, dtype=np.float64)
    if geometry.cylinder is not None:
        radius, length = float(geometry.cylinder.radius), float(geometry.cylinder.length)
        if capsule:
            ends = np.array([[0.0, 0.0, -length / 2.0], [0.0, 0.0, length / 2.0]])
            return _ball_points(ends, radius)
        angle = np.linspace(0.0, 2.0 * np.pi, _RIM_POINTS, endpoint=False)
        ring = np.stack([radius * np.cos(angle), radius * np.sin(angle)], axis=1)
        return np.concatenate(
            [np.column_stack([ring, np.full(_RIM_POINTS, z)]) for z in (-length / 2, length / 2)]
        )
    if geometry.sphere is not None:
        return _ball_points(np.zeros((1, 3)), float(geometry.sphere.radius))
    raise _NotRead("unsupported geometry")


def _ball_points(centres: FloatArray, radius: float) -> FloatArray:
    """The six extreme points of a ball of ``radius`` about each centre: their box, turned,
    is the ball's box turned, and a ball's box does not depend on the turn."""
    axes = np.concatenate([np.eye(3), -np.eye(3)]) * radius
    return np.asarray((centres[:, None, :] + axes[None, :, :]).reshape(-1, 3), dtype=np.float64)


def _mesh_points(
    mesh: Any, resolver: PackageResolver, base: Path, other_formats: bool
) -> FloatArray:
    uri = mesh.filename or ""
    try:
        path = resolver.resolve_uri(uri, base)
    except XrdfToolsError as e:
        raise _NotRead(f"{uri}: {e.message}") from None
    why = not_a_file(path)
    if why is not None:
        raise _NotRead(f"{uri}: {why}")
    suffix = path.suffix.lower()
    vertices = _vertices_or_why(uri, lambda: _cheap_vertices(path, suffix))
    if vertices is None and not other_formats:
        raise _NotRead(f"{uri}: {suffix or 'no suffix'} not read", suffix or "(none)")
    if vertices is None:
        vertices = _vertices_or_why(uri, lambda: mesh_file_vertices(path))
    assert vertices is not None
    if not len(vertices):
        raise _NotRead(f"{uri}: no vertices")
    factors = np.broadcast_to(np.asarray(1.0 if mesh.scale is None else mesh.scale, float), (3,))
    problem = vertices_problem(vertices, factors)
    if problem is not None:
        raise _NotRead(f"{uri}: {problem}")
    return np.asarray(vertices * factors, dtype=np.float64)


def _vertices_or_why(uri: str, read: Callable[[], FloatArray | None]) -> FloatArray | None:
    """``read()``, or :class:`_NotRead` saying why the mesh ``uri`` cannot be read."""
    try:
        return read()
    except XrdfToolsError as e:
        line = "" if e.line is None else f":{e.line}"
        raise _NotRead(f"{uri}{line}: {e.message}") from None
    except ValueError as e:
        raise _NotRead(f"{uri}: {e}") from None
    except Exception as e:  # trimesh raises many exception types for bad files
        raise _NotRead(f"{uri}: cannot read mesh ({type(e).__name__})") from None


def _cheap_vertices(path: Path, suffix: str) -> FloatArray | None:
    """The vertices of an STL, OBJ, COLLADA or GLB file read without trimesh; None for another
    format or a COLLADA or GLB file its reader gives up on."""
    if suffix in _NUMPY_FORMATS:
        return mesh_file_vertices(path)
    if suffix == ".glb":
        try:
            return glb_vertices(
                read_input_bytes(path, what="mesh file", max_bytes=mesh_bytes_limit())
            )
        except GltfTooBig as e:  # trimesh would copy every instance: not handed on
            raise XrdfToolsError(f"cannot read mesh ({e})") from None
        except GltfNotRead:
            return None
    if suffix != ".dae":
        return None
    data = read_input_bytes(path, what="mesh file", max_bytes=mesh_bytes_limit())
    try:
        return collada_vertices(data)
    except ColladaTooBig:
        raise
    except ColladaNotRead:
        return None


def mesh_file_vertices(path: Path) -> FloatArray:
    """The vertices [N, 3] of the mesh file ``path`` in its own frame: STL (binary or ASCII)
    and OBJ parsed with numpy, any other format through trimesh (COLLADA in metres). Raises
    :class:`XrdfToolsError` for a file that cannot be read, ``ValueError`` for bad numbers."""
    suffix = path.suffix.lower()
    if suffix not in _NUMPY_FORMATS:
        return _trimesh_vertices(path)
    data = read_input_bytes(path, what="mesh file", max_bytes=mesh_bytes_limit())
    if suffix == ".obj":
        return _matched(_OBJ_VERTEX, data)
    if len(data) >= 84:
        count = int(np.frombuffer(data, dtype="<u4", count=1, offset=80)[0])
        if len(data) == binary_stl_size(data[:84]):
            return _binary_stl(data, count)
    return _matched(_STL_VERTEX, data)


def _binary_stl(data: bytes, count: int) -> FloatArray:
    record = np.dtype([("normal", "<f4", 3), ("corners", "<f4", (3, 3)), ("attr", "<u2")])
    faces = np.frombuffer(data, dtype=record, count=count, offset=84)
    return np.asarray(faces["corners"].reshape(-1, 3), dtype=np.float64)


def _matched(pattern: re.Pattern[bytes], data: bytes) -> FloatArray:
    found = pattern.findall(data)
    return np.asarray(found, dtype=np.float64).reshape(-1, 3)


def _trimesh_vertices(path: Path) -> FloatArray:
    from ..util.fileio import check_input_file
    from .mesh_files import load_mesh_parts

    check_input_file(path, what="mesh file", max_bytes=mesh_bytes_limit())
    parts = load_mesh_parts(path)
    pieces = [np.asarray(p.vertices, dtype=np.float64) for p in parts if len(p.vertices)]
    return np.concatenate(pieces) if pieces else np.zeros((0, 3))


def _num(value: float) -> str:
    text = f"{value:.3f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text
