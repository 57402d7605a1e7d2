"""Odd meshes for the tests and benchmarks of the sphere fit: CAD slivers (a cone whose side
and base are fans from one centre, a cylinder whose caps are fans from one rim vertex, as CAD
exporters tessellate them) and a screw bag (many separate bodies in one mesh)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import trimesh


def fan_cone(triangles: int) -> trimesh.Trimesh:
    """A closed cone (5 cm radius, 10 cm tall) whose side and base are each a fan of
    ``triangles // 2`` slivers from one centre."""
    n = triangles // 2
    t = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
    rim = np.stack([0.05 * np.cos(t), 0.05 * np.sin(t), np.zeros(n)], 1)
    i = np.arange(n)
    j = (i + 1) % n
    faces = np.vstack([np.stack([np.full(n, n), i, j], 1), np.stack([np.full(n, n + 1), j, i], 1)])
    return trimesh.Trimesh(np.vstack([rim, [[0, 0, 0.1]], [[0, 0, 0]]]), faces, process=False)


def fan_capped_cylinder(sides: int, slant: tuple[float, float] = (0.0, 0.0)) -> trimesh.Trimesh:
    """A closed cylinder of 1 cm radius and 20 cm along z, of ``sides`` long side slivers a
    pair, whose caps are fans from one rim vertex; its top moved by ``slant`` in xy (so that
    its walls are seen, not edge-on, from above)."""
    t = np.linspace(0.0, 2.0 * np.pi, sides, endpoint=False)
    bottom = np.stack([0.01 * np.cos(t), 0.01 * np.sin(t), np.zeros(sides)], 1)
    vertices = np.vstack([bottom, bottom + np.array([slant[0], slant[1], 0.2])])
    i = np.arange(sides)
    j = (i + 1) % sides
    k = np.arange(1, sides - 1)
    faces = np.vstack(
        [
            np.stack([i, j, j + sides], 1),
            np.stack([i, j + sides, i + sides], 1),
            np.stack([np.zeros(sides - 2, dtype=int), k + 1, k], 1),
            np.stack([np.full(sides - 2, sides), k + sides, k + 1 + sides], 1),
        ]
    )
    return trimesh.Trimesh(vertices, faces, process=False)


def screw_bag(n: int, size: float = 0.004, spacing: float = 0.01) -> trimesh.Trimesh:
    """``n`` separate cubes on a grid in one mesh."""
    side = int(np.ceil(n ** (1 / 3)))
    cube = trimesh.creation.box((size, size, size))
    at = np.array(np.unravel_index(np.arange(n), (side, side, side))).T * spacing
    vertices = (cube.vertices[None] + at[:, None]).reshape(-1, 3)
    faces = (cube.faces[None] + 8 * np.arange(n)[:, None, None]).reshape(-1, 3)
    return trimesh.Trimesh(vertices, faces, process=False)


def one_link_urdf(tmp_path: Path, mesh: trimesh.Trimesh) -> Path:
    """``r.urdf`` in ``tmp_path``: one link ``part`` whose collision is ``mesh`` (as
    ``part.stl`` beside it)."""
    (tmp_path / "part.stl").write_bytes(mesh.export(file_type="stl"))
    (tmp_path / "r.urdf").write_text(
        '<robot name="r"><link name="part"><collision><geometry><mesh filename="part.stl"/>'
        "</geometry></collision></link></robot>"
    )
    return tmp_path / "r.urdf"
