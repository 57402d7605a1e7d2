"""Link geometry from a URDF (visual or collision elements) as plain triangle meshes.

Each ``<visual>``/``<collision>`` element becomes one or more :class:`MeshPart` in the link
frame: the element's ``origin`` and the mesh ``scale`` are applied to the vertices, so back-ends
only need the link pose. Mesh URIs (``package://``, ``file://``, relative) are resolved with
:class:`xrdf_tools.packages.PackageResolver`; files are read with trimesh (imported lazily).

A mesh that cannot be found or read is not an error: it becomes a ``mesh-not-loaded`` warning
and the link is drawn without it.
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
import numpy.typing as npt

from ..diagnostics import Diagnostic, Severity
from ..errors import XrdfToolsError
from ..fileio import check_input_file, mesh_bytes_limit

if TYPE_CHECKING:
    import yourdfpy

FloatArray = npt.NDArray[np.float64]
IntArray = npt.NDArray[np.int64]
Rgba = tuple[float, float, float, float]
MeshKind = Literal["visual", "collision", "none"]

DEFAULT_MESH_COLOR: Rgba = (0.72, 0.72, 0.75, 1.0)


@dataclass(frozen=True, eq=False)
class MeshPart:
    """A triangle mesh in its link's frame: ``vertices`` [V, 3] (m), ``faces`` [T, 3], colour."""

    vertices: FloatArray
    faces: IntArray
    color: Rgba
    source: str

    @property
    def n_triangles(self) -> int:
        return int(self.faces.shape[0])


def load_link_meshes(
    urdf: yourdfpy.URDF,
    links: Sequence[str],
    kind: MeshKind,
    *,
    urdf_path: str | os.PathLike[str] | None = None,
    package_paths: Mapping[str, str] | None = None,
) -> tuple[dict[str, tuple[MeshPart, ...]], list[Diagnostic]]:
    """Meshes of ``links`` from their ``kind`` elements (``none``: nothing is read).

    Returns ``{link: parts}`` (links without geometry are left out) and ``mesh-not-loaded``
    warnings for elements that could not be read.
    """
    diags: list[Diagnostic] = []
    out: dict[str, tuple[MeshPart, ...]] = {}
    if kind == "none":
        return out, diags
    from ..packages import PackageResolver

    upath = os.fspath(urdf_path) if urdf_path is not None else "<urdf>"
    start = Path(upath) if urdf_path is not None and Path(upath).exists() else Path.cwd()
    resolver = PackageResolver(start, dict(package_paths or {}))
    materials = _global_materials(urdf)
    link_map: Mapping[str, Any] = getattr(urdf, "link_map", {})
    for name in links:
        link = link_map.get(name)
        if link is None:
            continue  # an XRDF added frame has no geometry
        elements = link.visuals if kind == "visual" else link.collisions
        parts: list[MeshPart] = []
        for element in elements or ():
            try:
                parts.extend(_element_parts(element, kind, resolver, materials))
            except _MeshError as e:
                diags.append(
                    Diagnostic(
                        upath,
                        None,
                        None,
                        "mesh-not-loaded",
                        Severity.WARNING,
                        f"link '{name}': {kind} mesh not drawn: {e}",
                    )
                )
        if parts:
            out[name] = tuple(parts)
    return out, diags


class _MeshError(Exception):
    pass


def _global_materials(urdf: yourdfpy.URDF) -> dict[str, Rgba]:
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


def _element_parts(
    element: Any,
    kind: MeshKind,
    resolver: Any,
    materials: Mapping[str, Rgba],
) -> list[MeshPart]:
    import trimesh

    origin = np.eye(4) if element.origin is None else np.asarray(element.origin, dtype=np.float64)
    urdf_color: Rgba | None = None
    if kind == "visual" and getattr(element, "material", None) is not None:
        urdf_color = _material_rgba(element.material) or materials.get(element.material.name)
    geometry = element.geometry
    meshes: list[tuple[Any, Rgba | None]] = []
    source = ""
    if geometry.mesh is not None:
        uri = geometry.mesh.filename
        source = uri
        try:
            path = resolver.resolve_uri(uri)
        except XrdfToolsError as e:
            raise _MeshError(e.message) from None
        if not Path(path).is_file():
            raise _MeshError(f"'{uri}' resolves to {path}, which does not exist")
        try:
            check_input_file(path, what="mesh file", max_bytes=mesh_bytes_limit())
        except XrdfToolsError as e:
            raise _MeshError(e.message) from None
        try:
            loaded: Any = trimesh.load(str(path), force="scene")
            parts = loaded.dump(concatenate=False)
        except Exception as e:  # trimesh raises many exception types for unreadable files
            detail = str(e).splitlines()[0] if str(e) else type(e).__name__
            raise _MeshError(f"cannot read {path}: {detail}") from None
        scale = geometry.mesh.scale
        s = np.ones(3) if scale is None else np.broadcast_to(np.asarray(scale, float), (3,))
        for part in parts:
            if not hasattr(part, "faces") or len(part.faces) == 0:
                continue
            color = urdf_color or _trimesh_color(part) or None
            meshes.append((_scaled(part, s), color))
        source = str(path)
    elif geometry.box is not None:
        meshes.append((trimesh.creation.box(extents=np.asarray(geometry.box.size, float)), None))
        source = "box"
    elif geometry.cylinder is not None:
        c = geometry.cylinder
        meshes.append(
            (trimesh.creation.cylinder(radius=float(c.radius), height=float(c.length)), None)
        )
        source = "cylinder"
    elif geometry.sphere is not None:
        meshes.append((trimesh.creation.icosphere(2, radius=float(geometry.sphere.radius)), None))
        source = "sphere"
    out: list[MeshPart] = []
    for mesh, color in meshes:
        v = np.asarray(mesh.vertices, dtype=np.float64)
        v = v @ origin[:3, :3].T + origin[:3, 3]
        f = np.asarray(mesh.faces, dtype=np.int64)
        rgba = color or urdf_color or DEFAULT_MESH_COLOR
        v.flags.writeable = False
        f.flags.writeable = False
        out.append(MeshPart(v, f, rgba, source))
    return out


def _scaled(mesh: Any, scale: FloatArray) -> Any:
    if np.allclose(scale, 1.0):
        return mesh
    m = mesh.copy()
    m.vertices = np.asarray(m.vertices) * scale
    return m


def _trimesh_color(mesh: Any) -> Rgba | None:
    """The main colour of a trimesh's visual (material base colour or face colours)."""
    visual = getattr(mesh, "visual", None)
    if visual is None:
        return None
    try:
        if getattr(visual, "kind", None) == "texture":
            material = getattr(visual, "material", None)
            base = getattr(material, "baseColorFactor", None)
            c = base if base is not None else getattr(material, "main_color", None)
        elif getattr(visual, "kind", None) in ("face", "vertex"):
            c = visual.main_color
        else:
            return None
    except Exception:  # trimesh computes colours lazily and may fail on odd visuals
        return None
    if c is None:
        return None
    arr = np.asarray(c, dtype=np.float64).ravel()
    if arr.size < 3:
        return None
    if arr.max() > 1.0:
        arr = arr / 255.0
    a = float(arr[3]) if arr.size > 3 else 1.0
    return (float(arr[0]), float(arr[1]), float(arr[2]), a if a > 0 else 1.0)
