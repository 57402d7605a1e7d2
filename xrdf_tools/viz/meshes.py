"""Link meshes as drawn: the parts of :func:`xrdf_tools.robot.link_geometry.link_geometry` with
colours.

Each ``<visual>``/``<collision>`` element becomes one :class:`MeshPart` per sub-mesh, in the
link frame (the element's ``origin`` applied to the vertices), so back-ends only need the link
pose. What is viz-specific is the colour: the URDF material of a visual element, else the
sub-mesh's own colour (material or face colours of the file), else a neutral grey.

A mesh that cannot be found or read is not an error: it becomes a ``mesh-not-loaded`` warning
and the link is drawn without it. A sub-mesh of more than :data:`DRAWN_TRIANGLES` triangles (a
CAD export) is drawn simplified (:func:`simplified`: its vertices merged on a grid, a
deterministic vertex clustering), said in a ``mesh-simplified`` note: a recording stays small
and quick to write, and a viewer quick to draw it.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from ..diagnostics import Diagnostic, Severity
from ..robot.link_geometry import Rgba, link_frame_vertices
from ..util.arrays import FloatArray
from ..util.arrays import Int64Array as IntArray

if TYPE_CHECKING:
    import yourdfpy

    from ..robot.core import Robot
    from ..robot.link_geometry import GeometryPart
    from ..robot.packages import PackagePaths

__all__ = [
    "DEFAULT_MESH_COLOR",
    "DRAWN_TRIANGLES",
    "MeshKind",
    "MeshPart",
    "Rgba",
    "load_link_meshes",
    "simplified",
]

MeshKind = Literal["visual", "collision", "none"]

DEFAULT_MESH_COLOR: Rgba = (0.72, 0.72, 0.75, 1.0)
#: Sub-meshes of more triangles than this are drawn simplified to at most this many.
DRAWN_TRIANGLES = 100_000


@dataclass(frozen=True, eq=False)
class MeshPart:
    """A triangle mesh in its link's frame: ``vertices`` [V, 3] (m), ``faces`` [T, 3], colour;
    ``source`` is the mesh file, or the primitive (``box``, ``cylinder``, ...)."""

    vertices: FloatArray
    faces: IntArray
    color: Rgba
    source: str

    @property
    def n_triangles(self) -> int:
        return int(self.faces.shape[0])


def load_link_meshes(
    urdf: Robot | yourdfpy.URDF,
    links: Sequence[str],
    kind: MeshKind,
    *,
    urdf_path: str | os.PathLike[str] | None = None,
    package_paths: PackagePaths | None = None,
) -> tuple[dict[str, tuple[MeshPart, ...]], list[Diagnostic]]:
    """Meshes of ``links`` from their ``kind`` elements (``none``: nothing is read).

    Returns ``{link: parts}`` (links without geometry, and names that are not links, are left
    out) and ``mesh-not-loaded`` warnings for elements that could not be read. ``urdf_path``
    names the URDF in the warnings (default: the robot's path); ``package_paths`` replaces the
    robot's own.
    """
    diags: list[Diagnostic] = []
    out: dict[str, tuple[MeshPart, ...]] = {}
    if kind == "none":
        return out, diags
    from ..robot.core import as_robot
    from ..robot.link_geometry import link_geometry

    robot = as_robot(urdf)
    upath = os.fspath(urdf_path) if urdf_path is not None else robot.path
    loaded = link_geometry(robot, kind, links=links, package_paths=package_paths)
    for name, link in loaded.items():
        for failure in link.failures:
            diags.append(
                Diagnostic(
                    upath,
                    None,
                    None,
                    "mesh-not-loaded",
                    Severity.WARNING,
                    f"link '{name}': {kind} mesh not drawn: {failure.reason}",
                )
            )
        parts = [m for part in link.parts for m in _drawn(part)]
        simpler = [_simplified_part(m, DRAWN_TRIANGLES) for m in parts]
        for before, after in zip(parts, simpler, strict=True):
            if after is not before:
                diags.append(_simplified_note(upath, name, kind, before, after))
        parts = simpler
        if parts:
            out[name] = tuple(parts)
    return out, diags


def _drawn(part: GeometryPart) -> list[MeshPart]:
    """The pieces of one element in the link frame, each with its colour."""
    origin = part.origin
    out: list[MeshPart] = []
    for piece in part.pieces:
        v = link_frame_vertices(piece.vertices, origin)
        f = np.array(piece.faces, dtype=np.int64)
        color = part.material or _trimesh_color(piece) or DEFAULT_MESH_COLOR
        v.flags.writeable = False
        f.flags.writeable = False
        out.append(MeshPart(v, f, color, part.file or part.shape))
    return out


def _simplified_part(part: MeshPart, most: int) -> MeshPart:
    """``part`` itself when it has at most ``most`` triangles, else a simplified copy."""
    if part.n_triangles <= most:
        return part
    v, f = simplified(part.vertices, part.faces, most)
    v.flags.writeable = False
    f.flags.writeable = False
    return MeshPart(v, f, part.color, part.source)


def _simplified_note(
    path: str, link: str, kind: str, before: MeshPart, after: MeshPart
) -> Diagnostic:
    return Diagnostic(
        path,
        None,
        None,
        "mesh-simplified",
        Severity.INFO,
        f"link '{link}': {kind} mesh {before.source} drawn with {after.n_triangles:,} of its "
        f"{before.n_triangles:,} triangles (vertices merged on a grid)",
    )


def simplified(vertices: FloatArray, faces: IntArray, most: int) -> tuple[FloatArray, IntArray]:
    """The mesh ``(vertices, faces)`` with at most ``most`` triangles, for drawing: vertices
    merged in the cells of a grid (each becomes the mean of its cell's), the triangles left
    with three corners kept once each, in their first order. The grid is made coarser until
    the triangles fit; the same mesh gives the same bits."""
    v = np.asarray(vertices, dtype=np.float64)
    f = np.asarray(faces, dtype=np.int64)
    lo = v.min(0)
    extent = float(np.max(v.max(0) - lo)) or 1.0
    cells = max(2.0, 2.0 * np.sqrt(most))
    while True:
        grid = np.floor((v - lo) / (extent / cells)).astype(np.int64)
        side = int(grid.max()) + 1
        cell, merged = np.unique(
            (grid[:, 0] * side + grid[:, 1]) * side + grid[:, 2], return_inverse=True
        )
        tri = merged.reshape(-1)[f]
        kept = (tri[:, 0] != tri[:, 1]) & (tri[:, 1] != tri[:, 2]) & (tri[:, 0] != tri[:, 2])
        _, first = np.unique(np.sort(tri[kept], axis=1), axis=0, return_index=True)
        tri = tri[kept][np.sort(first)]
        if len(tri) <= most or cells <= 2.0:
            break
        cells *= 0.7 * np.sqrt(most / len(tri)) if len(tri) > 2 * most else 0.85
    weight = np.bincount(merged.reshape(-1), minlength=len(cell)).astype(np.float64)
    mean = np.stack(
        [np.bincount(merged.reshape(-1), weights=v[:, k], minlength=len(cell)) for k in range(3)],
        axis=1,
    )
    used, compact = np.unique(tri, return_inverse=True)
    out_v: FloatArray = (mean / weight[:, None])[used]
    out_f: IntArray = compact.reshape(-1, 3).astype(np.int64)
    return out_v, out_f


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
    arr: FloatArray = np.asarray(c, dtype=np.float64).ravel()
    if arr.size < 3:
        return None
    if arr.max() > 1.0:
        arr = arr / 255.0
    a = float(arr[3]) if arr.size > 3 else 1.0
    return (float(arr[0]), float(arr[1]), float(arr[2]), a if a > 0 else 1.0)
