"""The link geometry of a loaded robot as triangle meshes: the one loader (viz, spheres, lint).

:func:`link_geometry` takes a loaded :class:`~xrdf_tools.robot.core.Robot` and returns, per link,
the parts of its ``<collision>`` or ``<visual>`` elements as the yourdfpy object holds them (the
URDF XML is not parsed again):

* the primitives ``box``, ``cylinder``, ``sphere`` and ``capsule`` tessellated (cylinder and
  capsule along z, centred, like URDF's cylinder), finely enough that sphere-fitting metrics do
  not see the facets;
* meshes that trimesh reads (STL, OBJ, DAE, PLY, ...), found with
  :class:`~xrdf_tools.robot.packages.PackageResolver` (``package://``, ``file://``, relative to the
  URDF) and read through :func:`~xrdf_tools.util.fileio.check_input_file` with the mesh size limit;
  ``scale`` applied;
* each with its element's ``origin`` (the transform into the link frame), the URDF material
  colour of a visual element, and the line of its ``<link>``.

A part that cannot be read is a :class:`PartFailure` with the reason, never an exception;
each caller words its own diagnostic. ``<capsule>`` is not standard URDF and yourdfpy knows
none: the robot loader hands it to yourdfpy as a cylinder of the same radius and length and
records which elements were capsules (:func:`capsules_as_cylinders`, :attr:`Robot.capsules`).
trimesh is imported lazily.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from ..util.arrays import FloatArray
from ..util.errors import SourceError, XrdfToolsError
from ..util.fileio import check_input_file, mesh_bytes_limit, mesh_triangle_limit
from ..util.fixed_order import quantized, transform_points
from ..util.numbers import vertices_problem
from ..util.text import name_list
from .input_files import GeometryChoice, GeometrySource, choose_elements, link_mesh_names
from .mesh_files import (
    MeshTooBig,
    binary_stl_counts,
    load_mesh_parts,
    not_a_file,
    too_many_triangles,
    unreadable,
)

if TYPE_CHECKING:
    import trimesh
    import yourdfpy

    from .core import Robot
    from .packages import PackagePaths, PackageResolver

Rgba = tuple[float, float, float, float]
Shape = Literal["box", "cylinder", "capsule", "sphere", "mesh"]

__all__ = [
    "GeometryChoice",
    "GeometryPart",
    "GeometrySource",
    "LinkParts",
    "MissingMeshError",
    "PartFailure",
    "Rgba",
    "capsules_as_cylinders",
    "link_geometry",
    "missing_meshes",
    "require_meshes",
]

# Cylinders, capsules and spheres are tessellated finely enough that the facet error stays far
# below the sampling noise of the sphere-fitting metrics (< 0.2 % of the radius).
CYLINDER_SECTIONS = 96
SPHERE_SUBDIVISIONS = 4
CAPSULE_COUNT = (48, 48)


@dataclass(frozen=True, eq=False)
class GeometryPart:
    """One ``<collision>``/``<visual>`` element of a link, read.

    ``pieces`` are its triangle meshes in the element frame (``scale`` applied): one for a
    primitive, one per sub-mesh of a mesh file (a COLLADA file with several materials has
    several). ``origin`` (4x4, read-only) places the element in the link frame. ``index`` is
    the element's position among the link's elements of its ``source``; ``file`` the resolved
    mesh path; ``material`` the URDF material colour (visual elements only).
    """

    link: str
    source: GeometrySource
    index: int
    shape: Shape
    origin: FloatArray
    pieces: tuple[trimesh.Trimesh, ...]
    file: str | None = None
    material: Rgba | None = None
    #: A ``<sphere>``'s radius as the URDF writes it (None for other shapes).
    radius: float | None = None

    @cached_property
    def mesh(self) -> trimesh.Trimesh:
        """All pieces as one mesh, in the element frame."""
        if len(self.pieces) == 1:
            return self.pieces[0]
        import trimesh

        combined: Any = trimesh.util.concatenate(list(self.pieces))  # a Trimesh for Trimeshes
        mesh: trimesh.Trimesh = combined
        return mesh

    def in_link_frame(self) -> trimesh.Trimesh:
        """A copy of :attr:`mesh` moved into the link frame by :attr:`origin`, its vertices
        on the grid of :func:`link_frame_vertices`."""
        out = self.mesh.copy()
        out.vertices = link_frame_vertices(out.vertices, self.origin)
        return out


def link_frame_vertices(vertices: Any, origin: FloatArray) -> FloatArray:
    """Element-frame ``vertices`` [N, 3] placed in the link frame by ``origin`` (4x4), with
    the same bits on every machine: the transform is summed term by term, and the result is
    rounded to a 0.14 µm grid, which also absorbs the last-bit differences a mesh loader's own
    transforms (a COLLADA node's matrix) leave on another machine's BLAS
    (:mod:`xrdf_tools.util.fixed_order`)."""
    return quantized(transform_points(origin, vertices))


@dataclass(frozen=True)
class PartFailure:
    """An element that could not be read: ``reason`` says why (``"<uri>: ..."`` for meshes).

    ``missing`` is true when the mesh file could not be found or opened as a file at all (an
    unknown package, no such file, a directory, device, FIFO, a symbolic link loop, a name
    too long), as opposed to a file that was found but could not be read as a mesh; ``uri``
    is the mesh ``filename`` as written in the URDF.
    """

    link: str
    source: GeometrySource
    index: int
    reason: str
    unsupported: bool = False
    missing: bool = False
    uri: str | None = None


@dataclass(frozen=True)
class LinkParts:
    """The elements of one link of one ``source``: ``elements`` of them, read into ``parts``
    or not (``failures``), in document order; ``line`` is the line of the ``<link>``."""

    link: str
    source: GeometrySource
    elements: int
    parts: tuple[GeometryPart, ...]
    failures: tuple[PartFailure, ...]
    line: int | None = None


def link_geometry(
    robot: Robot | yourdfpy.URDF,
    source: GeometryChoice = "auto",
    *,
    links: Sequence[str] | None = None,
    package_paths: PackagePaths | None = None,
) -> dict[str, LinkParts]:
    """The geometry of ``links`` (in that order; default: every link, in URDF order) of a
    loaded robot.

    ``source`` is ``collision``, ``visual``, or ``auto`` (collision; visual for a link without
    collision elements: :attr:`LinkParts.source` says which). Every link of the robot named in
    ``links`` gets an entry, also without elements; other names (e.g. an XRDF's added frames)
    are skipped. ``package_paths`` replaces the robot's own for resolving ``package://``.
    """
    from .core import as_robot

    loaded = as_robot(robot)
    reader = _MeshReader(loaded.mesh_resolver(package_paths), Path(loaded.path).resolve().parent)
    link_map: Mapping[str, Any] = loaded.urdf.link_map
    materials = _global_materials(loaded.urdf)
    out: dict[str, LinkParts] = {}
    for name in loaded.links if links is None else dict.fromkeys(links):
        link = link_map.get(name)
        if link is None:
            continue
        kind, elements = _elements(link, source)
        parts: list[GeometryPart] = []
        failures: list[PartFailure] = []
        for i, element in enumerate(elements):
            capsule = (name, kind, i) in loaded.capsules
            try:
                parts.append(_part(name, kind, i, element, capsule, reader, materials))
            except _PartError as e:
                failures.append(
                    PartFailure(name, kind, i, e.reason, e.unsupported, e.missing, e.uri)
                )
        out[name] = LinkParts(
            name, kind, len(elements), tuple(parts), tuple(failures), loaded.link_lines.get(name)
        )
    return out


def missing_meshes(
    robot: Robot | yourdfpy.URDF,
    source: GeometryChoice = "collision",
    *,
    links: Sequence[str] | None = None,
    package_paths: PackagePaths | None = None,
) -> list[PartFailure]:
    """The mesh elements of ``links`` (as :func:`link_geometry` chooses them) whose file cannot
    be found or is no file (see :attr:`PartFailure.missing`), without reading any mesh: a
    check that costs a ``stat`` per mesh, made before long work that needs the meshes."""
    from .core import as_robot

    loaded = as_robot(robot)
    reader = _MeshReader(loaded.mesh_resolver(package_paths), Path(loaded.path).resolve().parent)
    out: list[PartFailure] = []
    for name, kind, uris in link_mesh_names(loaded, source, links):
        for i, uri in enumerate(uris):
            if uri is None:
                continue
            try:
                if not uri:
                    raise _PartError("<mesh> without a filename", missing=True, uri=uri)
                reader.locate(uri)
            except _PartError as e:
                out.append(PartFailure(name, kind, i, e.reason, missing=True, uri=uri))
    return out


class MissingMeshError(SourceError):
    """Mesh files a command needs cannot be found; ``failures`` lists each (link, URI, why)."""

    def __init__(self, message: str, failures: Sequence[PartFailure], **where: Any) -> None:
        super().__init__(message, **where)
        self.failures = tuple(failures)


#: How many other links a missing-mesh error names before it counts the rest.
_NAMED = 6


def require_meshes(
    robot: Robot | yourdfpy.URDF,
    source: GeometryChoice = "collision",
    *,
    links: Sequence[str] | None = None,
    package_paths: PackagePaths | None = None,
    allow_missing: bool = False,
) -> list[PartFailure]:
    """Raise :class:`MissingMeshError` when a mesh of ``links`` cannot be found (the first in
    full: its URI and the package directories searched, then the other links), unless
    ``allow_missing``; then return the missing meshes (the readers warn for each)."""
    from .core import as_robot
    from .packages import unfound_packages_note

    loaded = as_robot(robot)
    failures = missing_meshes(loaded, source, links=links, package_paths=package_paths)
    if not failures or allow_missing:
        return failures
    first = failures[0]
    others = list(dict.fromkeys(f.link for f in failures[1:]))
    message = f"{len(failures)} mesh file(s) cannot be found: link '{first.link}' {first.source}: "
    message += first.reason
    if others:
        message += f"; also meshes of {name_list(others, _NAMED)}"
    message += unfound_packages_note((f.uri, f.reason) for f in failures)
    message += "; pass --allow-missing-meshes to go on without them"
    path, line = loaded.place("link", first.link)
    raise MissingMeshError(message, failures, path=path, line=line)


def capsules_as_cylinders(root: Any) -> frozenset[tuple[str, GeometrySource, int]]:
    """Rename each ``<capsule>`` of a URDF's lxml tree to ``<cylinder>`` (the same radius and
    length) so that yourdfpy reads it, and return ``(link, source, index)`` of those elements
    (``index`` among the link's elements of that source, as yourdfpy lists them)."""
    found: set[tuple[str, GeometrySource, int]] = set()
    sources: tuple[GeometrySource, ...] = ("visual", "collision")
    for link in root.findall("link"):
        for kind in sources:
            for i, element in enumerate(link.findall(kind)):
                geometry = element.find("geometry")
                if geometry is not None and len(geometry) and geometry[0].tag == "capsule":
                    geometry[0].tag = "cylinder"  # yourdfpy reads only the first child
                    found.add((str(link.get("name")), kind, i))
    return frozenset(found)


# --------------------------------------------------------------------------------------------
# Elements and parts
# --------------------------------------------------------------------------------------------
def _elements(link: Any, choice: GeometryChoice) -> tuple[GeometrySource, list[Any]]:
    """The elements of one yourdfpy link for ``choice``, and which kind they are."""
    return choose_elements(list(link.collisions or ()), list(link.visuals or ()), choice)


class _PartError(Exception):
    def __init__(
        self,
        reason: str,
        unsupported: bool = False,
        *,
        missing: bool = False,
        uri: str | None = None,
    ) -> None:
        super().__init__(reason)
        self.reason = reason
        self.unsupported = unsupported
        self.missing = missing
        self.uri = uri


_UNSUPPORTED = "unsupported geometry (no box, cylinder, sphere or mesh)"


def _part(
    link: str,
    kind: GeometrySource,
    index: int,
    element: Any,
    capsule: bool,
    reader: _MeshReader,
    materials: Mapping[str, Rgba],
) -> GeometryPart:
    import trimesh

    origin = np.eye(4) if element.origin is None else np.array(element.origin, dtype=np.float64)
    origin.flags.writeable = False
    material = None
    if kind == "visual" and getattr(element, "material", None) is not None:
        material = _material_rgba(element.material) or materials.get(element.material.name)
    geometry = element.geometry
    if geometry is None:
        raise _PartError(_UNSUPPORTED, unsupported=True)
    shape: Shape
    file = None
    radius: float | None = None
    if geometry.mesh is not None:
        shape = "mesh"
        pieces, file = reader.read(geometry.mesh.filename or "", geometry.mesh.scale)
    elif geometry.box is not None:
        shape = "box"
        pieces = (trimesh.creation.box(extents=np.asarray(geometry.box.size, dtype=float)),)
    elif geometry.cylinder is not None:
        across, length = float(geometry.cylinder.radius), float(geometry.cylinder.length)
        if capsule:
            shape = "capsule"
            pieces = (
                trimesh.creation.capsule(height=length, radius=across, count=list(CAPSULE_COUNT)),
            )
        else:
            shape = "cylinder"
            pieces = (
                trimesh.creation.cylinder(radius=across, height=length, sections=CYLINDER_SECTIONS),
            )
    elif geometry.sphere is not None:
        shape = "sphere"
        radius = float(geometry.sphere.radius)
        if radius > 0:
            pieces = (trimesh.creation.icosphere(subdivisions=SPHERE_SUBDIVISIONS, radius=radius),)
        else:  # trimesh divides by the radius: a point, as a box of zero size is
            pieces = (trimesh.creation.box(extents=np.zeros(3)),)
    else:  # a yourdfpy object built in code; the robot loader refuses unknown shapes
        raise _PartError(_UNSUPPORTED, unsupported=True)
    return GeometryPart(link, kind, index, shape, origin, pieces, file, material, radius)


@dataclass
class _MeshReader:
    """Reads mesh files for one robot: URIs resolved, size checked, trimesh parses."""

    resolver: PackageResolver
    base: Path

    def read(self, uri: str, scale: Any) -> tuple[tuple[trimesh.Trimesh, ...], str]:
        """The sub-meshes of the file ``uri`` (scaled) and its resolved path."""
        import trimesh

        if not uri:
            raise _PartError("<mesh> without a filename", missing=True, uri=uri)
        path = self.locate(uri)
        try:
            check_input_file(path, what="mesh file", max_bytes=mesh_bytes_limit())
        except XrdfToolsError as e:
            raise _PartError(f"{uri}: {e.message}", uri=uri) from None
        try:
            factors = np.broadcast_to(np.asarray(1.0 if scale is None else scale, float), (3,))
        except ValueError:
            raise _PartError(f"{uri}: scale must be one or three numbers", uri=uri) from None
        limit = mesh_triangle_limit()
        claimed = binary_stl_counts(path)
        if claimed is not None and min(claimed) > limit:  # refused before it is parsed
            raise _PartError(f"{uri}: {too_many_triangles(min(claimed), limit)}", uri=uri)
        try:
            parts = load_mesh_parts(path, limit)  # refused past it before the costly processing
            pieces = tuple(p for p in parts if isinstance(p, trimesh.Trimesh) and len(p.faces))
        except MeshTooBig as e:
            raise _PartError(f"{uri}: {e.message}", uri=uri) from None
        except Exception as e:  # trimesh raises many exception types for bad files
            raise _PartError(f"{uri}: cannot read mesh ({unreadable(path, e)})", uri=uri) from None
        # processing would drop a NaN vertex and its faces without a word; the bound is on
        # the scaled vertices (metres), the file's own numbers may be millimetres
        bad = next(filter(None, (vertices_problem(p.vertices, factors) for p in pieces)), None)
        try:
            for p in () if bad else pieces:
                p.process()
        except Exception as e:
            raise _PartError(f"{uri}: cannot read mesh ({unreadable(path, e)})", uri=uri) from None
        if not pieces:
            why = unreadable(path, None)
            raise _PartError(f"{uri}: cannot read mesh ({why})", uri=uri)
        if not np.array_equal(factors, np.ones(3)):
            for piece in pieces:  # scene.dump() made copies: scaling them in place is safe
                piece.vertices = np.asarray(piece.vertices, dtype=np.float64) * factors
                if np.prod(factors) < 0:  # a mirror: keep the faces turned outward
                    piece.faces = np.ascontiguousarray(np.fliplr(piece.faces))
        if bad:
            raise _PartError(f"{uri}: {bad}")
        return pieces, str(path)

    def locate(self, uri: str) -> Path:
        """The path of the mesh file ``uri``; raises a ``missing`` :class:`_PartError` saying
        what is there instead of a mesh file (nothing, a directory, a FIFO, ...)."""
        try:
            path = self.resolver.resolve_uri(uri, self.base)
        except XrdfToolsError as e:
            raise _PartError(f"{uri}: {e.message}", missing=True, uri=uri) from None
        why = not_a_file(path)
        if why is not None:
            raise _PartError(f"{uri}: {why}", missing=True, uri=uri)
        return path


# --------------------------------------------------------------------------------------------
# Material colours
# --------------------------------------------------------------------------------------------
def _global_materials(urdf: Any) -> dict[str, Rgba]:
    """The colours of the robot's top-level ``<material>`` elements, by name."""
    out: dict[str, Rgba] = {}
    robot = getattr(urdf, "robot", None)
    for m in getattr(robot, "materials", None) or ():
        rgba = _material_rgba(m)
        if m.name and rgba is not None:
            out[m.name] = rgba
    return out


def _material_rgba(material: Any) -> Rgba | None:
    color = getattr(material, "color", None)
    rgba = getattr(color, "rgba", None)
    if rgba is None:
        return None
    values = [float(v) for v in np.asarray(rgba, dtype=np.float64).ravel()[:4]]
    if len(values) != 4:
        return None
    return (values[0], values[1], values[2], values[3])
