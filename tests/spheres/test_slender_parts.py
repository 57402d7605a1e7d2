"""Long thin parts (rods, fingers, masts, cables), coiled wires and screw bags in the fit."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest
import trimesh

from tests.odd_meshes import one_link_urdf, screw_bag
from xrdf_tools.spheres import mesh_solids, sphere_metrics
from xrdf_tools.spheres.count_policy import CountPolicy
from xrdf_tools.spheres.fewest import SLENDER_MAX_PER_LINK, slender
from xrdf_tools.spheres.metrics import sample_volume
from xrdf_tools.spheres.robot_fit import fit_robot


def test_a_finger_gets_a_chain_of_spheres_of_its_thickness(tmp_path: Path) -> None:
    """A 30 cm finger 8 mm thick: the default count stopped at 16 spheres, which cover 57 %
    within the 2 mm bound, and refined them past it (protrusion p95 5.8 mm, 4.2 times its
    volume). It is slender (39 times as long as thick): it may get up to 40 spheres, and
    28 cover the target within the bound: its protrusion p95 is within the bound too (2.6 mm
    on the 48-cell grid, whose 7 mm cells were close to its thickness)."""
    finger = trimesh.creation.cylinder(radius=0.004, height=0.3, sections=32)
    result = fit_robot(one_link_urdf(tmp_path, finger))
    spheres = result.spheres["part"]
    assert 20 <= len(spheres) <= 40
    assert not [d for d in result.diagnostics if d.rule == "spheres-past-bound"]
    metrics = sphere_metrics(finger, spheres)
    assert metrics.coverage >= 0.9 and metrics.protrusion_p95 < 0.0021
    assert max(s.radius for s in spheres) < 0.008


@pytest.mark.slow
def test_a_rod_past_its_most_spheres_says_how_far_they_reach(tmp_path: Path) -> None:
    """A 1 m rod 2 mm thick (16 flat sides) would take 518 spheres of its thickness: it gets
    the most a slender part gets by default, refined past the bound, and a warning says how
    far they reach and what gives more (it said only the coverage, as an info). On a grid
    that follows its thickness its 48 spheres within the bound cover a quarter of it, and
    refined past it they stop short of the target (the warning is then
    spheres-target-missed), reaching less far than on the coarse grid (10.3 mm)."""
    rod = trimesh.creation.cylinder(radius=0.001, height=1.0, sections=16)
    # the volume's count alone (by default up to 16 more within the bound reach for its
    # surface, with a spheres-surface-gap warning at 64)
    result = fit_robot(one_link_urdf(tmp_path, rod), counts=CountPolicy(reach_surface=False))
    assert len(result.spheres["part"]) == SLENDER_MAX_PER_LINK
    (note,) = [
        d for d in result.diagnostics if d.rule in ("spheres-past-bound", "spheres-target-missed")
    ]
    assert note.severity.value == "warning"
    assert "a slender part (about 1015 mm long, 1.96 mm thick: 518 times as long" in note.message
    assert f"): {SLENDER_MAX_PER_LINK} spheres, the most it gets by default" in note.message
    reach = float(note.message.split("reaching ")[1].split(" mm past it (protrusion p95)")[0])
    p95 = sphere_metrics(rod, result.spheres["part"]).protrusion_p95 * 1000
    assert reach == pytest.approx(p95, rel=0.25) and p95 < 10.0
    assert "give --per-link (up to 64) for more, thinner spheres" in note.message


def _as_fitter(solid: trimesh.Trimesh) -> Any:
    """What :func:`slender` reads of a fitter: its solid, volume and volume samples."""
    points = sample_volume(solid, 3000, np.random.default_rng(0))
    return SimpleNamespace(
        solid=solid, volume=float(solid.volume), points=points, n_volume=len(points)
    )


def _hollow_box() -> trimesh.Trimesh:
    """A closed box of 3 mm walls (an outer box, an inner one turned inward)."""
    outer = trimesh.creation.box((0.3, 0.2, 0.1))
    inner = trimesh.creation.box((0.294, 0.194, 0.094))
    faces = np.concatenate([outer.faces, inner.faces[:, ::-1] + len(outer.vertices)])
    return trimesh.Trimesh(np.concatenate([outer.vertices, inner.vertices]), faces)


def _coil(turns: float = 3.0, segments: int = 240, ring: int = 8) -> trimesh.Trimesh:
    """A closed tube 2 mm thick along a helix of radius 3 cm, 15 cm high (a coiled cable),
    59 cm long."""
    t = np.linspace(0.0, 1.0, segments + 1)
    angle = 2.0 * np.pi * turns * t
    path = np.stack([0.03 * np.cos(angle), 0.03 * np.sin(angle), 0.15 * t], axis=1)
    tangent = np.gradient(path, axis=0)
    tangent /= np.linalg.norm(tangent, axis=1, keepdims=True)
    side = np.cross(tangent, [0.0, 0.0, 1.0])
    side /= np.linalg.norm(side, axis=1, keepdims=True)
    up = np.cross(side, tangent)
    a = 2.0 * np.pi * np.arange(ring) / ring
    rings = path[:, None] + 0.001 * (
        np.cos(a)[None, :, None] * side[:, None] + np.sin(a)[None, :, None] * up[:, None]
    )
    i = (np.arange(segments)[:, None] * ring + np.arange(ring)[None]).reshape(-1)
    j = (np.arange(segments)[:, None] * ring + (np.arange(ring)[None] + 1) % ring).reshape(-1)
    tube = np.concatenate([np.stack([i, j, j + ring], 1), np.stack([i, j + ring, i + ring], 1)])
    ends = len(rings) * ring + np.arange(2)
    first = np.arange(ring)
    last = segments * ring + first
    caps = np.concatenate(
        [
            np.stack([np.full(ring, ends[0]), (first + 1) % ring, first], 1),
            np.stack([np.full(ring, ends[1]), last, segments * ring + (first + 1) % ring], 1),
        ]
    )
    vertices = np.concatenate([rings.reshape(-1, 3), path[[0, -1]]])
    coil = trimesh.Trimesh(vertices, np.concatenate([tube, caps]))
    if coil.volume < 0:
        coil.invert()
    return coil


def test_slender_reads_rods_and_coils_not_plates_shells_bags_or_blocks() -> None:
    """Read as a tube (length area²/(4π volume), thickness 4 volume/area) a plate, a hollow
    box and a screw bag are long and thin too; their volume samples spread over a surface
    or in blobs, not along a line, and they are not slender. Nor is a compact block."""
    rod = slender(_as_fitter(trimesh.creation.cylinder(radius=0.015, height=1.0)))
    assert rod is not None and rod.most == 36  # a 1 m mast 3 cm thick
    coil = slender(_as_fitter(_coil()))
    assert coil is not None and coil.length == pytest.approx(0.585, rel=0.1)
    assert coil.most == SLENDER_MAX_PER_LINK
    for part in (
        trimesh.creation.box((0.3, 0.3, 0.02)),
        _hollow_box(),
        screw_bag(500),
        trimesh.creation.box((0.1, 0.08, 0.06)),
    ):
        assert slender(_as_fitter(part)) is None


def test_a_closed_coiled_wire_is_a_solid_and_a_hollow_box_a_shell() -> None:
    """A coiled cable, closed and watertight, has 0.3 % of its hull's volume and walls far
    thinner than the hull: the thin-shell rule took it for a shell and fitted its hull, the
    whole coil's cylinder. Its surface is an eighth of its hull's, where a shell's wraps
    its hull (real ones: 47 % and more): it is fitted as the solid it is."""
    coil = _coil()
    hull = mesh_solids.convex_hull(coil)
    assert coil.is_volume and hull is not None
    assert coil.area < 0.15 * hull.area
    assert not mesh_solids.is_thin_shell(coil, hull)
    assert mesh_solids.closed_part(coil) == (coil, "mesh")
    box = _hollow_box()
    box_hull = mesh_solids.convex_hull(box)
    assert box.is_volume and box_hull is not None
    assert mesh_solids.is_thin_shell(box, box_hull)


def test_a_screw_bag_is_split_without_a_trimesh_check_per_body(monkeypatch: Any) -> None:
    """300 separate cubes in one mesh: each body was split off, checked with trimesh
    (is_volume) and hulled, twice over: 10-15 ms a body. Its bodies are measured at once:
    one hull (the whole part's), the same bodies out."""
    bag = screw_bag(300)
    calls = {"hull": 0, "volume": 0}
    hull, volume = mesh_solids.convex_hull, mesh_solids.is_volume

    def counted_hull(mesh: trimesh.Trimesh) -> Any:
        calls["hull"] += 1
        return hull(mesh)

    def counted_volume(mesh: trimesh.Trimesh) -> bool:
        calls["volume"] += 1
        return volume(mesh)

    monkeypatch.setattr(mesh_solids, "convex_hull", counted_hull)
    monkeypatch.setattr(mesh_solids, "is_volume", counted_volume)
    assert mesh_solids.overlapping_bodies(bag) == [bag]
    made = mesh_solids.closed_parts(bag)
    assert calls["hull"] <= 2 and calls["volume"] <= 4, calls
    assert [how for _, _, how in made] == ["mesh"] * 300
    for k, (body, solid, _) in enumerate(made):
        assert body is solid and len(body.faces) == 12
        assert np.array_equal(body.faces, bag.faces[12 * k : 12 * k + 12] - 8 * k)
        assert np.array_equal(body.vertices, bag.vertices[8 * k : 8 * k + 8])
    moved = bag.vertices.copy()
    moved[8:16] = bag.vertices[:8] + 0.001  # the second cube overlaps the first
    overlapping = trimesh.Trimesh(moved, bag.faces, process=False)
    assert len(mesh_solids.overlapping_bodies(overlapping)) == 300


def test_a_part_filling_little_of_its_box_gets_all_its_volume_samples() -> None:
    """A 2 m rod of 1 mm radius lying across its box's diagonal fills a millionth of it:
    rejection sampling in the box found about 50 of 1,000 points after its 64 rounds, so the
    fit and metrics of such a part saw almost nothing (and a coiled cable took minutes).
    Now its samples are drawn in the octree cells that hold it: all 1,000, all inside, spread
    along the whole rod, the same for the same seed; and every inside point a plain rejection
    sample finds lies in one of those cells."""
    import trimesh

    from xrdf_tools.spheres.metrics import contains, occupied_cells, sample_volume

    rod = trimesh.creation.cylinder(radius=0.001, height=2.0, sections=16)
    rod.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 4, [1, 0, 0]))
    rod.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 4, [0, 1, 0]))
    pts = sample_volume(rod, 1000, np.random.default_rng(3))
    assert len(pts) == 1000
    assert contains(rod, pts).all()
    axis = rod.vertices[rod.vertices[:, 2].argmax()] - rod.vertices[rod.vertices[:, 2].argmin()]
    along = (pts - rod.centroid) @ (axis / np.linalg.norm(axis))
    assert along.min() < -0.9 and along.max() > 0.9  # the whole 2 m, not one end
    np.testing.assert_array_equal(pts, sample_volume(rod, 1000, np.random.default_rng(3)))
    lo, hi = rod.bounds
    corners, size = occupied_cells(rod, lo, hi - lo, float(rod.volume))
    probe = np.random.default_rng(4).uniform(lo, hi, size=(2_000_000, 3))
    near_axis = np.linalg.norm(np.cross(probe - rod.centroid, axis / np.linalg.norm(axis)), axis=1)
    probe = probe[near_axis < 0.0011]
    inside = probe[contains(rod, probe)]
    assert len(inside) > 10
    cell = np.floor((inside - lo) / size)
    held = {tuple(c) for c in np.floor((corners - lo) / size + 0.5)}
    assert all(tuple(c) in held for c in cell)
