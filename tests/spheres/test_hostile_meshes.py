"""Meshes as vendor CAD exports and hostile files bring them: parts far from their origin,
triangles listed twice, wires and cables. Each test builds its mesh here (small, fast)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
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


def test_many_bodies_are_compared_for_overlap_in_little_memory() -> None:
    """A screw bag: 3,000 separate boxes in one file. Whether any two overlap was one
    3,000 x 3,000 x 3 comparison (54 MB here, 1.2 GB at 10,000 bodies); now only the pairs
    that overlap along x are compared, a bounded number at a time. The answer is the same:
    none overlap, then two that do."""
    import tracemalloc

    from xrdf_tools.spheres import mesh_solids

    grid = np.stack(np.meshgrid(*[np.arange(15)] * 3, indexing="ij"), -1).reshape(-1, 3)
    lo = grid[:3000] * 0.01
    hi = lo + 0.004
    tracemalloc.start()
    try:
        apart = mesh_solids._boxes_overlap(lo, hi)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert not apart
    assert peak < 20e6, peak
    lo[-1], hi[-1] = lo[7] + 0.001, lo[7] + 0.005
    assert mesh_solids._boxes_overlap(lo, hi)


@pytest.mark.parametrize("second", ["same", "reversed"])
def test_a_part_with_every_face_listed_twice_is_fitted_as_itself(
    tmp_path: Path, second: str
) -> None:
    """A double-sided export lists each triangle twice (again, or with its winding reversed):
    every edge has four faces and the part read as open, so a ring was fitted to its convex
    hull, a disc with the hole filled. The repeats are dropped and the ring is the solid."""
    ring = trimesh.creation.annulus(r_min=0.02, r_max=0.05, height=0.03)
    again = ring.faces if second == "same" else ring.faces[:, ::-1]
    doubled = trimesh.Trimesh(ring.vertices, np.concatenate([ring.faces, again]), process=False)
    geoms, diags = load_link_geometry(_urdf(tmp_path, _write(tmp_path, doubled)))
    assert geoms["part"].kind == "mesh"
    assert not [d for d in diags if d.rule == "spheres-convex-hull"], diags
    assert geoms["part"].solid.volume == pytest.approx(ring.volume, rel=1e-4)
