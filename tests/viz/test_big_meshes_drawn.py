"""A CAD-sized mesh is drawn simplified (:func:`xrdf_tools.viz.meshes.simplified`), said in a
``mesh-simplified`` note; an ordinary one is drawn as it is. The threshold is lowered here so
that a small mesh stands in for a big one."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import trimesh

from xrdf_tools.robot.xacro_source import load_robot
from xrdf_tools.viz import meshes
from xrdf_tools.viz.meshes import load_link_meshes, simplified

ROBOT = """<robot name="r">
  <link name="arm"><visual><geometry><mesh filename="ball.stl"/></geometry></visual></link>
</robot>
"""


def _drawn(tmp_path: Path) -> tuple[dict[str, tuple[meshes.MeshPart, ...]], list[str]]:
    trimesh.creation.icosphere(subdivisions=3, radius=0.1).export(tmp_path / "ball.stl")
    urdf = tmp_path / "r.urdf"
    urdf.write_text(ROBOT)
    drawn, diags = load_link_meshes(load_robot(urdf), ["arm"], "visual")
    return drawn, [f"{d.rule} {d.message}" for d in diags]


def test_a_mesh_past_the_threshold_is_drawn_simplified_and_said_so(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(meshes, "DRAWN_TRIANGLES", 300)
    drawn, notes = _drawn(tmp_path)
    (part,) = drawn["arm"]
    assert 100 < part.n_triangles <= 300
    assert np.allclose(part.vertices.min(0), -0.1, atol=0.02)
    assert np.allclose(part.vertices.max(0), 0.1, atol=0.02)
    (note,) = notes
    assert note.startswith("mesh-simplified link 'arm': visual mesh ")
    assert f"drawn with {part.n_triangles:,} of its 1,280 triangles" in note
    again, _ = _drawn(tmp_path)
    assert np.array_equal(again["arm"][0].vertices, part.vertices)
    assert np.array_equal(again["arm"][0].faces, part.faces)


def test_an_ordinary_mesh_is_drawn_as_it_is(tmp_path: Path) -> None:
    drawn, notes = _drawn(tmp_path)
    assert drawn["arm"][0].n_triangles == 1280 and notes == []


def test_simplified_keeps_each_triangle_once_and_only_real_ones() -> None:
    mesh = trimesh.creation.icosphere(subdivisions=4, radius=1.0)
    v, f = simplified(mesh.vertices, mesh.faces, 500)
    assert len(f) <= 500 and f.max() < len(v)
    assert len(np.unique(np.sort(f, axis=1), axis=0)) == len(f)
    assert np.all((f[:, 0] != f[:, 1]) & (f[:, 1] != f[:, 2]) & (f[:, 0] != f[:, 2]))
