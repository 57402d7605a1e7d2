"""Sheets (marker plates, stickers, flat parts boxed 2 mm thick): by default a few spheres that
hold the whole sheet, said once per link; explicit counts and bounds keep their meaning; a
solid that is not a sheet is not touched."""

from __future__ import annotations

import math
import re
import warnings
from pathlib import Path

import numpy as np
import pytest
import trimesh

from tests.robots import robot_urdf
from xrdf_tools.convert.spheres_job import fit_metrics, metrics_table
from xrdf_tools.spheres import sphere_metrics
from xrdf_tools.spheres.count_policy import CountPolicy
from xrdf_tools.spheres.fit import default_max_protrusion
from xrdf_tools.spheres.geometry import load_link_geometry
from xrdf_tools.spheres.robot_fit import FitResult, fit_robot
from xrdf_tools.spheres.sheet import (
    SHEET_MAX_CELLS,
    SHEET_MAX_CELLS_BOUND,
    SHEET_MAX_REACH,
    SHEET_MAX_SPHERES,
    as_plate,
    as_sheet,
    sheet_spheres,
)
from xrdf_tools.util.fixed_order import QUANTUM

#: a marker plate: 50 x 30 x 0.3 mm
PLATE = (0.05, 0.03, 0.0003)
#: a turn that puts the plate's axes off the link's axes
TURN = trimesh.transformations.euler_matrix(0.3, -0.7, 1.1)


def _urdf(tmp_path: Path, mesh: trimesh.Trimesh, name: str = "plate") -> Path:
    mesh.export(tmp_path / f"{name}.stl")
    urdf = tmp_path / f"{name}.urdf"
    urdf.write_text(
        f'<robot name="{name}"><link name="{name}"><collision><origin xyz="0.1 0 0.2"/>'
        f'<geometry><mesh filename="{name}.stl"/></geometry></collision></link></robot>'
    )
    return urdf


def _plate(extents: tuple[float, float, float] = PLATE) -> trimesh.Trimesh:
    plate = trimesh.creation.box(extents=extents)
    plate.apply_transform(TURN)
    return plate


def _mid_plane_grid(extents: tuple[float, float, float], n: int = 41) -> np.ndarray:
    """Points of the plate's mid-plane (edges and corners included) in the link frame."""
    u = np.linspace(-extents[0] / 2, extents[0] / 2, n)
    v = np.linspace(-extents[1] / 2, extents[1] / 2, n)
    uu, vv = np.meshgrid(u, v)
    local = np.stack([uu.ravel(), vv.ravel(), np.zeros(uu.size), np.ones(uu.size)], 1)
    moved = local @ TURN.T
    return np.asarray(moved[:, :3] + np.array([0.1, 0.0, 0.2]))


def _inside_some(points: np.ndarray, fit: FitResult, link: str) -> np.ndarray:
    centres = np.array([s.center for s in fit.spheres[link]])
    radii = np.array([s.radius for s in fit.spheres[link]])
    d = np.linalg.norm(points[:, None, :] - centres[None, :, :], axis=2)
    return np.asarray((d <= radii[None, :]).any(axis=1))


@pytest.fixture(scope="module")
def plate_urdf(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return _urdf(tmp_path_factory.mktemp("plate"), _plate())


@pytest.fixture(scope="module")
def plate_fit(plate_urdf: Path) -> FitResult:
    return fit_robot(plate_urdf)


def test_a_plate_gets_a_few_spheres_holding_its_whole_area(plate_fit: FitResult) -> None:
    spheres = plate_fit.spheres["plate"]
    assert 1 <= len(spheres) <= SHEET_MAX_SPHERES
    # every point of the mid-plane, and every corner of the plate itself, is inside a sphere
    assert _inside_some(_mid_plane_grid(PLATE), plate_fit, "plate").all()
    corners = trimesh.creation.box(extents=PLATE)
    corners.apply_transform(TURN)
    assert _inside_some(
        np.asarray(corners.vertices) + np.array([0.1, 0.0, 0.2]), plate_fit, "plate"
    ).all()
    # the spheres are no bigger than it takes: each holds a square cell half the plate wide
    # (two rows along its length), so each reaches about a third of its width, not more
    assert len(spheres) == 2 * math.ceil(2 * PLATE[0] / PLATE[1])
    for s in spheres:
        cell = 0.5 * PLATE[1]
        assert s.radius <= 0.5 * math.hypot(PLATE[0] / (len(spheres) // 2), cell, PLATE[2]) + 2e-4
        assert s.radius < 0.4 * PLATE[1]


def test_a_plate_is_said_once_as_a_sheet_not_as_a_missed_target(plate_fit: FitResult) -> None:
    rules = [d.rule for d in plate_fit.diagnostics]
    assert rules == ["spheres-sheet"]
    (note,) = plate_fit.diagnostics
    assert "50 × 30 × 0.3 mm" in note.message
    assert "--per-link" in note.message and "--max-protrusion" in note.message
    assert note.line == 1


def test_the_count_follows_the_aspect_ratio_up_to_a_few() -> None:
    """Two rows of square cells half the sheet wide: 4 for a square, 8 for 50 x 30, the cap
    for a strip (its cells then lengthen); every corner of the box is inside a sphere."""
    for extents, count in (
        ((0.06, 0.06, 0.00025), 4),
        ((0.06, 0.0598, 0.00025), 4),  # a CAD square a little off
        ((0.05, 0.03, 0.0003), 8),
        ((0.09, 0.03, 0.0003), 12),
        ((0.4, 0.02, 0.0005), SHEET_MAX_SPHERES),
    ):
        box = trimesh.creation.box(extents=extents)
        box.apply_transform(TURN)
        sheet = as_sheet(box, default_max_protrusion(box))
        assert sheet is not None, extents
        spheres = sheet_spheres(sheet)
        assert len(spheres) == count, extents
        c = np.array([s.center for s in spheres])
        r = np.array([s.radius for s in spheres])
        d = np.linalg.norm(np.asarray(box.vertices)[:, None] - c[None], axis=2)
        assert (d <= r[None]).any(axis=1).all(), extents


def test_solids_that_are_not_sheets() -> None:
    """Thick for their width (10 mm over 30 mm), thicker than the protrusion bound (5 mm
    over 10 cm: the bound is 2.2 mm), or a rod: the volume fit stays theirs."""
    for extents in ((0.05, 0.03, 0.01), (0.1, 0.1, 0.005), (0.2, 0.004, 0.004)):
        box = trimesh.creation.box(extents=extents)
        assert as_sheet(box, default_max_protrusion(box)) is None, extents


def test_a_flat_part_boxed_2_mm_thick_is_a_sheet(tmp_path: Path) -> None:
    """A square with no thickness at all (two triangles) encloses no volume even as a hull:
    it becomes its bounding box, 2 mm thick, as thick as the smallest bound: a sheet."""
    flat = trimesh.Trimesh(
        vertices=[[-0.03, -0.03, 0], [0.03, -0.03, 0], [0.03, 0.03, 0], [-0.03, 0.03, 0]],
        faces=[[0, 1, 2], [0, 2, 3]],
        process=False,
    )
    fit = fit_robot(_urdf(tmp_path, flat, "flat"))
    assert [d.rule for d in fit.diagnostics] == ["spheres-bounding-box", "spheres-sheet"]
    assert fit.kinds["flat"] == "bounding_box"
    spheres = fit.spheres["flat"]  # 2 x 2 square cells of 30 mm, one sphere around each
    assert len(spheres) == 4
    centres = np.array([s.center for s in spheres]) - np.array([0.1, 0.0, 0.2])
    np.testing.assert_allclose(np.sort(np.abs(centres[:, :2]), axis=0), 0.015, atol=1e-4)
    np.testing.assert_allclose(centres[:, 2], 0.0, atol=1e-4)
    r = math.hypot(0.015, 0.015, 0.001)
    assert all(r <= s.radius <= r + 2e-4 for s in spheres)


def test_explicit_counts_and_clips_keep_their_meaning(plate_urdf: Path) -> None:
    by_count = fit_robot(plate_urdf, counts=CountPolicy(per_link=3))
    assert len(by_count.spheres["plate"]) == 3
    assert "spheres-sheet" not in [d.rule for d in by_count.diagnostics]
    clipped = fit_robot(plate_urdf, clips={"plate": [((0.0, 0.0, 1.0), -1.0)]})
    assert "spheres-sheet" not in [d.rule for d in clipped.diagnostics]


def test_a_bound_given_for_a_sheet_is_kept_by_a_grid_covering_it(plate_urdf: Path) -> None:
    """Within 10 mm: square cells whose spheres reach at most 10 mm past the faces, as few as
    that takes, all of the plate inside them."""
    bound = 0.01
    fit = fit_robot(plate_urdf, max_protrusion=bound)
    assert [d.rule for d in fit.diagnostics] == ["spheres-sheet"]
    assert "given" in fit.diagnostics[0].message
    spheres = fit.spheres["plate"]
    assert 4 <= len(spheres) <= 16
    assert all(s.radius - PLATE[2] / 2 <= bound for s in spheres)
    assert _inside_some(_mid_plane_grid(PLATE), fit, "plate").all()


def test_a_tight_bound_given_for_a_sheet_is_still_a_grid_covering_it(plate_urdf: Path) -> None:
    """Within 2 mm the plate takes a grid of more than 16 cells: still a grid holding all of
    it within the bound, not the volume fit (which covered a quarter of such a plate)."""
    bound = 0.002
    fit = fit_robot(plate_urdf, max_protrusion=bound)
    assert [d.rule for d in fit.diagnostics] == ["spheres-sheet"]
    spheres = fit.spheres["plate"]
    assert 16 < len(spheres) <= SHEET_MAX_CELLS_BOUND
    assert all(s.radius - PLATE[2] / 2 <= bound for s in spheres)
    assert _inside_some(_mid_plane_grid(PLATE), fit, "plate").all()


def test_a_bound_no_grid_of_the_most_cells_keeps_is_a_warning(plate_urdf: Path) -> None:
    fit = fit_robot(plate_urdf, max_protrusion=0.0005)
    (d,) = fit.diagnostics
    assert (d.rule, d.severity.value) == ("spheres-sheet", "warning")
    assert "past the bound" in d.message and f"more than {SHEET_MAX_CELLS_BOUND}" in d.message
    assert len(fit.spheres["plate"]) <= SHEET_MAX_CELLS_BOUND
    assert _inside_some(_mid_plane_grid(PLATE), fit, "plate").all()


#: a mobile base's top plate: 932 x 790 x 6.35 mm
TOP_PLATE = (0.932, 0.79, 0.00635)


def test_a_big_plate_gets_finer_cells_reaching_no_further_than_the_cap(tmp_path: Path) -> None:
    """Two rows of cells over a 0.8 m plate would reach 0.25 m past its faces (further than
    an arm link sticks out): its cells are cut until the reach is within SHEET_MAX_REACH, or
    the finest grid of SHEET_MAX_CELLS, whichever reaches less far."""
    fit = fit_robot(_urdf(tmp_path, _plate(TOP_PLATE), "top"))
    spheres = fit.spheres["top"]
    assert SHEET_MAX_SPHERES < len(spheres) <= SHEET_MAX_CELLS
    a, b, t = TOP_PLATE
    # the least reach any grid of at most SHEET_MAX_CELLS cells has, by trying them all
    least = min(
        0.5 * math.sqrt((a / na) ** 2 + (b / nb) ** 2 + t**2) - t / 2
        for na in range(1, SHEET_MAX_CELLS + 1)
        for nb in range(1, SHEET_MAX_CELLS // na + 1)
    )
    reach = max(s.radius for s in spheres) - t / 2
    assert reach <= max(SHEET_MAX_REACH, 1.1 * least) + 2e-4
    assert _inside_some(_mid_plane_grid(TOP_PLATE), fit, "top").all()


def test_the_metrics_name_a_sheet_and_its_whole_area_is_covered(plate_fit: FitResult) -> None:
    per, overall = fit_metrics(plate_fit)
    m = per["plate"]
    assert m.sheet_thickness == pytest.approx(PLATE[2], abs=QUANTUM)
    assert m.coverage == 1.0 and m.surface_coverage == 1.0
    assert m.max_uncovered_gap == 0.0
    assert m.to_dict()["sheet_thickness"] == m.sheet_thickness
    assert "sheets (protr.share and vol.ratio only say how thin): plate 0.3 mm" in metrics_table(
        per, overall
    )


def test_panda_links_are_not_sheets_and_say_nothing_of_it() -> None:
    geoms, _ = load_link_geometry(robot_urdf("panda"))
    assert len(geoms) >= 10
    for g in geoms.values():
        assert as_sheet(g.solid, default_max_protrusion(g.solid)) is None, g.link
    fit = fit_robot(robot_urdf("panda"), links=["panda_leftfinger"])
    assert "spheres-sheet" not in [d.rule for d in fit.diagnostics]
    per, _ = fit_metrics(fit)
    assert per["panda_leftfinger"].sheet_thickness is None
    assert "sheet_thickness" not in per["panda_leftfinger"].to_dict()


def test_a_closed_flat_mesh_is_no_volume_without_a_numpy_warning() -> None:
    """Four coplanar points closed into a tetrahedron (a marker plate exported as a closed
    shell of no thickness): no volume, and trimesh's 0/0 centre of mass prints nothing."""
    from xrdf_tools.spheres.mesh_solids import is_volume

    flat = trimesh.Trimesh(
        vertices=[[0, 0, 0], [0.03, 0, 0], [0, 0.03, 0], [0.03, 0.03, 0]],
        faces=[[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]],
        process=False,
    )
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        assert not is_volume(flat)
    assert [str(w.message) for w in seen] == []


def test_a_disc_its_default_bound_cannot_cover_is_refined_past_it(tmp_path: Path) -> None:
    """Unitree H1's shoulder discs (80 mm across, 10 mm thick): thicker than a sheet, and
    under their 2.2 mm default bound 16 spheres covered 43 % of them. By default they are
    refined past the bound as --per-link is, and reach the target; a bound the user gives
    stays hard (and the target is missed, said as before)."""
    disc = trimesh.creation.cylinder(radius=0.04, height=0.01, sections=64)
    urdf = _urdf(tmp_path, disc, "disc")
    fit = fit_robot(urdf)
    assert [d.rule for d in fit.diagnostics] == ["spheres-past-bound"]
    # judged on samples held out of the fit (its own samples said 49 %)
    said = re.search(
        r"within its 2\.21 mm default bound cover (\d+)% of it", fit.diagnostics[0].message
    )
    assert said is not None and int(said.group(1)) < 50, fit.diagnostics[0].message
    solid = fit.geometry["disc"].solid
    m = sphere_metrics(solid, fit.spheres["disc"], samples=8000)
    assert m.coverage >= 0.9 and len(fit.spheres["disc"]) <= 16
    hard = fit_robot(urdf, max_protrusion=default_max_protrusion(solid))
    # its rim, 12.5 mm from the 16 spheres, gets 6 more within the bound (surface gap)
    assert [d.rule for d in hard.diagnostics] == ["spheres-target-missed", "spheres-surface-gap"]
    h = sphere_metrics(solid, hard.spheres["disc"], samples=8000)
    assert h.coverage < 0.6 and h.protrusion_max <= default_max_protrusion(solid) + 2e-4


def test_a_coverage_short_of_its_target_never_reads_as_the_target() -> None:
    """Staubli RX160's link_6: 16 spheres covered 89.96 % under the default bound, said as
    'cover 90% of it (target 90%)' and then refined past the bound. A coverage below the
    target is rounded down."""
    from xrdf_tools.spheres.fewest import short_of

    assert [short_of(s) for s in (0.8996, 0.9, 0.43, 0.0)] == ["89%", "90%", "43%", "0%"]


#: the table top of Trossen's Stationary AI, both arms stand on it: 1219 x 749 x 20 mm
TABLE = (1.219, 0.749, 0.02)


def test_a_plate_thicker_than_its_bound_is_covered_as_a_sheet_not_by_huge_spheres(
    tmp_path: Path,
) -> None:
    """Thicker (20 mm) than its 15.8 mm default bound, the table was no sheet; 16 spheres
    within the bound covered 4 % of it, so they were refined past the bound, to 0.14 m radii
    reaching 156 mm from its faces: every arm link near it collided with it. Its box is cut
    into cells as a sheet's is when they reach less far, and a warning says so."""
    from xrdf_tools.spheres.sheet import face_reach

    fit = fit_robot(_urdf(tmp_path, _plate(TABLE), "table"))
    spheres = fit.spheres["table"]
    (note,) = fit.diagnostics
    assert note.rule == "spheres-sheet" and note.severity.value == "warning", note
    assert "is a plate (1219 × 749 × 20 mm), thicker than its 15.8 mm default" in note.message
    said = re.search(r"16 spheres refined past the bound would reach (\d+) mm", note.message)
    assert said is not None and int(said.group(1)) > 100, note.message
    assert "world cuboid" in note.message
    assert SHEET_MAX_SPHERES < len(spheres) <= SHEET_MAX_CELLS
    assert _inside_some(_mid_plane_grid(TABLE), fit, "table").all()
    plate = as_plate(fit.geometry["table"].solid)
    assert plate is not None and face_reach(plate, spheres) < 0.08


def test_a_plate_a_joint_moves_is_not_sent_to_the_planner_as_a_world_cuboid(
    tmp_path: Path,
) -> None:
    """The car-seat cell of tesseract's support package carries its arm on a 1000 x 722 x
    50 mm carriage along a prismatic rail: the plate note told to give that carriage to the
    planner as a world cuboid, which would stay where it was while the rail moves the arm.
    A plate moved by a joint (through a fixed joint here) is said to move with it; a fixed
    one keeps the world-cuboid advice (the test above)."""
    _plate((1.0, 0.722, 0.05)).export(tmp_path / "carriage.stl")
    urdf = tmp_path / "rail.urdf"
    urdf.write_text(
        '<robot name="rail"><link name="base"/><link name="slider"/><link name="carriage">'
        '<collision><geometry><mesh filename="carriage.stl"/></geometry></collision></link>'
        '<joint name="rail_axis" type="prismatic"><parent link="base"/><child link="slider"/>'
        '<axis xyz="1 0 0"/><limit lower="0" upper="4" effort="1" velocity="1"/></joint>'
        '<joint name="mount" type="fixed"><parent link="slider"/><child link="carriage"/>'
        "</joint></robot>"
    )
    (note,) = fit_robot(urdf).diagnostics
    assert "link 'carriage' is a plate" in note.message, note
    assert "It moves with joint 'rail_axis', so it keeps these spheres" in note.message
    assert "world cuboid would not follow it" in note.message


def test_two_plates_far_apart_in_one_mesh_get_spheres_only_over_the_plates(
    tmp_path: Path,
) -> None:
    """Two 100 x 100 x 1 mm plates 5 m apart in one STL are one sheet's box, 5.1 m long: its
    51 cells' spheres stood in a row across the empty 5 m between them (protrusion mean 1.2
    m). Only the cells the plates reach keep a sphere, and every plate corner is covered."""
    first = trimesh.creation.box(extents=(0.1, 0.1, 0.001))
    second = first.copy()
    second.apply_translation((5.0, 0.0, 0.0))
    fit = fit_robot(_urdf(tmp_path, trimesh.util.concatenate([first, second])))
    spheres = fit.spheres["plate"]
    assert 2 <= len(spheres) <= 6
    for s in spheres:  # each sphere is over one of the plates, none in the gap
        assert min(abs(s.center[0] - 0.1), abs(s.center[0] - 5.1)) < 0.05 + s.radius
    corners = np.vstack([first.vertices, second.vertices]) + np.array([0.1, 0.0, 0.2])
    assert _inside_some(corners, fit, "plate").all()
