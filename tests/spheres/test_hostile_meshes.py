"""Meshes as vendor CAD exports and hostile files bring them: parts far from their origin,
triangles listed twice, wires and cables. Each test builds its mesh here (small, fast)."""

from __future__ import annotations

from pathlib import Path

import trimesh

from xrdf_tools.spheres.geometry import load_link_geometry


def _urdf(tmp_path: Path, mesh: str, scale: str = "1 1 1") -> Path:
    (tmp_path / "r.urdf").write_text(
        f'<robot name="r"><link name="part"><collision><geometry><mesh filename="{mesh}" '
        f'scale="{scale}"/></geometry></collision></link></robot>'
    )
    return tmp_path / "r.urdf"


def _write(tmp_path: Path, mesh: trimesh.Trimesh, name: str = "part.stl") -> str:
    (tmp_path / name).write_bytes(mesh.export(file_type="stl"))
    return name


def test_a_millimetre_part_a_kilometre_away_is_read_in_metres(tmp_path: Path) -> None:
    """A part modelled in millimetres and exported in world coordinates 1 km away: its file
    says 1e6, its link frame 1,000 m. It was refused as "beyond ±1e+06 m" (the bound was
    checked on the file's numbers, before the scale), which it is not."""
    ball = trimesh.creation.icosphere(subdivisions=2, radius=50.0)  # mm
    ball.apply_translation([1e6, 0.0, 0.0])
    name = _write(tmp_path, ball)
    geoms, diags = load_link_geometry(_urdf(tmp_path, name, "0.001 0.001 0.001"))
    assert not [d for d in diags if d.rule == "spheres-mesh-unreadable"], diags
    assert geoms["part"].solid.bounds[0][0] > 999.9


def test_a_part_past_the_bound_says_how_far_and_what_to_do(tmp_path: Path) -> None:
    ball = trimesh.creation.icosphere(subdivisions=1, radius=0.05)
    ball.apply_translation([2e6, 0.0, 0.0])
    _, diags = load_link_geometry(_urdf(tmp_path, _write(tmp_path, ball)))
    (message,) = [d.message for d in diags if d.rule == "spheres-mesh-unreadable"]
    assert "a vertex is 2,000,000 m from the link frame, beyond ±1e+06 m" in message
    assert "re-export it about its own origin" in message
