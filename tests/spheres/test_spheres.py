"""Sphere fitting and coverage metrics: analytic shapes, real robot meshes, the CLI."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import trimesh
from typer.testing import CliRunner

from tests.paths import FIXTURES
from tests.robots import panda_copy_with_mesh
from xrdf_tools.cli import app
from xrdf_tools.spheres import coverage_for_xrdf, fit_link_spheres, sphere_metrics
from xrdf_tools.spheres.fit import default_max_protrusion
from xrdf_tools.spheres.geometry import load_link_geometry
from xrdf_tools.util.errors import XrdfToolsError
from xrdf_tools.util.fixed_order import QUANTUM
from xrdf_tools.xrdf.io import load_xrdf
from xrdf_tools.xrdf.model import Sphere

#: Relative error of a volume whose vertices lie on the fitting grid (``util.fixed_order``).
ON_GRID = 1e-5

ROBOTS = (
    Path(trimesh.__file__).resolve().parents[1] / "cmeel.prefix/share/example-robot-data/robots"
)
PANDA = ROBOTS / "panda_description/urdf/panda.urdf"
UR5 = ROBOTS / "ur_description/urdf/ur5_robot.urdf"
PANDA_XRDF = FIXTURES / "panda" / "panda.xrdf"
PANDA_GEOMETRY_LINKS = [
    *(f"panda_link{i}" for i in range(8)),
    "panda_hand",
    "panda_leftfinger",
    "panda_rightfinger",
]
UR5_GEOMETRY_LINKS = [
    "base_link",
    "shoulder_link",
    "upper_arm_link",
    "forearm_link",
    "wrist_1_link",
    "wrist_2_link",
    "wrist_3_link",
    "ee_link",
]


def needs(path: Path) -> Path:
    if not path.exists():
        pytest.skip(f"{path} not installed")
    return path


# --------------------------------------------------------------------------------------------
# Metrics on analytic shapes
# --------------------------------------------------------------------------------------------
def test_small_sphere_in_unit_cube_covers_its_own_volume() -> None:
    cube = trimesh.creation.box(extents=[1.0, 1.0, 1.0])
    m = sphere_metrics(cube, [Sphere((0.0, 0.0, 0.0), 0.3)], samples=40_000)
    assert m.coverage == pytest.approx(4.0 / 3.0 * math.pi * 0.3**3, abs=0.008)
    assert m.surface_coverage == 0.0
    assert m.protrusion_mean == 0.0 and m.protrusion_p95 == 0.0 and m.protrusion_max == 0.0
    assert m.sphere_count == 1 and m.volume == pytest.approx(1.0)


def test_sphere_of_radius_0_6_on_unit_cube_matches_closed_forms() -> None:
    cube = trimesh.creation.box(extents=[1.0, 1.0, 1.0])
    m = sphere_metrics(cube, [Sphere((0.0, 0.0, 0.0), 0.6)], samples=40_000)
    r, h = 0.6, 0.1
    cap = math.pi * h * h * (3 * r - h) / 3
    assert m.coverage == pytest.approx(4 / 3 * math.pi * r**3 - 6 * cap, abs=0.01)
    # each face holds a disc of radius sqrt(0.6² - 0.5²)
    assert m.surface_coverage == pytest.approx(math.pi * (r * r - 0.25), abs=0.01)
    # half the sphere's area lies in six caps where protrusion is uniform on [0, 0.1]
    assert m.protrusion_mean == pytest.approx(0.025, abs=0.0015)
    assert m.protrusion_p95 == pytest.approx(0.09, abs=0.003)
    assert 0.097 <= m.protrusion_max <= 0.1 + 1e-6


def test_sphere_equal_to_a_sphere_mesh_covers_it_without_protrusion() -> None:
    ball = trimesh.creation.icosphere(subdivisions=4, radius=0.2)
    m = sphere_metrics(ball, [Sphere((0.0, 0.0, 0.0), 0.2)])
    assert m.coverage == 1.0 and m.surface_coverage == 1.0
    assert m.protrusion_p95 < 0.002 * 0.2


def test_overlapping_spheres_count_protrusion_on_the_union_boundary_only() -> None:
    cube = trimesh.creation.box(extents=[1.0, 1.0, 1.0])
    one = sphere_metrics(cube, [Sphere((0.0, 0.0, 0.0), 0.6)], samples=20_000)
    # a small sphere fully inside the big one changes nothing
    two = sphere_metrics(
        cube, [Sphere((0.0, 0.0, 0.0), 0.6), Sphere((0.0, 0.0, 0.0), 0.3)], samples=20_000
    )
    assert two.protrusion_p95 == pytest.approx(one.protrusion_p95, abs=0.003)
    assert two.coverage == pytest.approx(one.coverage, abs=0.01)


def test_metrics_are_deterministic_for_a_seed() -> None:
    cube = trimesh.creation.box(extents=[0.3, 0.2, 0.1])
    s = [Sphere((0.05, 0.0, 0.0), 0.08), Sphere((-0.08, 0.0, 0.0), 0.06)]
    assert sphere_metrics(cube, s, seed=3) == sphere_metrics(cube, s, seed=3)


# --------------------------------------------------------------------------------------------
# Geometry: primitives, origins, fallbacks
# --------------------------------------------------------------------------------------------
PRIMITIVES_URDF = """<?xml version="1.0"?>
<robot name="prims">
  <link name="base">
    <collision><origin xyz="0.5 0 0" rpy="0 0 0.3"/>
      <geometry><box size="0.2 0.1 0.05"/></geometry></collision>
  </link>
  <link name="cyl">
    <collision><origin xyz="0 0.4 0"/>
      <geometry><cylinder radius="0.05" length="0.3"/></geometry></collision>
  </link>
  <link name="cap">
    <collision><geometry><capsule radius="0.04" length="0.2"/></geometry></collision>
  </link>
  <link name="ball">
    <collision><origin xyz="0 0 1"/><geometry><sphere radius="0.1"/></geometry></collision>
  </link>
  <link name="empty"/>
  <joint name="j1" type="fixed"><parent link="base"/><child link="cyl"/></joint>
  <joint name="j2" type="revolute"><parent link="cyl"/><child link="cap"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="j3" type="fixed"><parent link="cap"/><child link="ball"/></joint>
  <joint name="j4" type="fixed"><parent link="ball"/><child link="empty"/></joint>
</robot>
"""


@pytest.fixture
def prims(tmp_path: Path) -> Path:
    p = tmp_path / "prims.urdf"
    p.write_text(PRIMITIVES_URDF)
    return p


def test_primitives_become_solids_in_the_link_frame(prims: Path) -> None:
    geoms, diags = load_link_geometry(prims)
    assert list(geoms) == ["base", "cyl", "cap", "ball"] and diags == []
    assert geoms["base"].solid.volume == pytest.approx(0.2 * 0.1 * 0.05, rel=ON_GRID)
    assert geoms["base"].solid.center_mass == pytest.approx([0.5, 0.0, 0.0], abs=QUANTUM)
    assert geoms["cyl"].solid.volume == pytest.approx(math.pi * 0.05**2 * 0.3, rel=0.01)
    cap = math.pi * 0.04**2 * 0.2 + 4 / 3 * math.pi * 0.04**3
    assert geoms["cap"].solid.volume == pytest.approx(cap, rel=0.01)
    assert geoms["cap"].solid.extents == pytest.approx([0.08, 0.08, 0.28], rel=0.01)
    assert geoms["ball"].solid.center_mass == pytest.approx([0.0, 0.0, 1.0], abs=1e-6)


def test_progress_announces_the_fit_of_each_link_not_only_its_preparation(prims: Path) -> None:
    """Preparing every link (measuring its solid) comes before fitting any: progress counts
    both, two steps a link, so it does not say n/n while the fitting (most of a big robot's
    time: 29 of 45 s on Unitree G1) has yet to start. The sphere primitive is taken as it
    is, without steps."""
    from xrdf_tools.spheres.count_policy import CountPolicy
    from xrdf_tools.spheres.robot_fit import fit_robot

    calls: list[tuple[str, int, int]] = []
    fitted = fit_robot(
        prims, counts=CountPolicy(per_link=2), progress=lambda *call: calls.append(call)
    )
    links = ["base", "cyl", "cap"]
    assert set(fitted.spheres) == {*links, "ball"}
    assert [i for _, i, _ in calls] == list(range(6)) and {n for *_, n in calls} == {6}
    assert [link for link, *_ in calls] == links + links  # prepared, then fitted


def test_one_sphere_for_a_sphere_primitive_is_centred_and_within_budget(prims: Path) -> None:
    fitted, _ = fit_link_spheres(prims, links=["ball"], per_link=1)
    (s,) = fitted["ball"]
    assert math.dist(s.center, (0.0, 0.0, 1.0)) < 0.01
    geoms, _ = load_link_geometry(prims, links=["ball"])
    budget = default_max_protrusion(geoms["ball"].solid)
    assert 0.1 <= s.radius <= 0.1 + budget + 0.002
    m = sphere_metrics(geoms["ball"].solid, fitted["ball"])
    assert m.coverage == 1.0 and m.protrusion_max <= budget + 0.002


def test_spheres_stay_within_the_requested_protrusion(prims: Path) -> None:
    geoms, _ = load_link_geometry(prims, links=["base", "cyl"])
    for link in ("base", "cyl"):
        cov = []
        for budget in (0.004, 0.02):
            fitted, _ = fit_link_spheres(prims, links=[link], per_link=3, max_protrusion=budget)
            m = sphere_metrics(geoms[link].solid, fitted[link])
            assert m.sphere_count == 3
            assert m.protrusion_p95 <= budget * 1.05 + 0.001
            cov.append(m.coverage)
        assert cov[1] > cov[0] + 0.1, link  # a larger budget buys coverage


def test_open_visual_mesh_falls_back_to_convex_hull_and_says_so(tmp_path: Path) -> None:
    dae = needs(ROBOTS / "panda_description/meshes/visual/hand.dae")
    urdf = tmp_path / "hand.urdf"
    urdf.write_text(
        f'<robot name="h"><link name="hand"><visual><geometry>'
        f'<mesh filename="file://{dae}"/></geometry></visual></link></robot>'
    )
    fitted, diags = fit_link_spheres(urdf, per_link=3)
    rules = {d.rule for d in diags}
    assert {"spheres-visual-fallback", "spheres-convex-hull"} <= rules
    assert len(fitted["hand"]) == 3
    geoms, _ = load_link_geometry(urdf)
    assert geoms["hand"].kind == "convex_hull" and geoms["hand"].source == "visual"


def test_missing_mesh_is_a_diagnostic_and_the_command_exits_2(
    runner: CliRunner, tmp_path: Path
) -> None:
    urdf = tmp_path / "m.urdf"
    urdf.write_text(
        '<robot name="m"><link name="a"><collision><geometry><mesh filename="nope.stl"/>'
        '</geometry></collision></link><link name="b"><collision><geometry>'
        '<box size="0.1 0.1 0.1"/></geometry></collision></link>'
        '<joint name="j" type="fixed"><parent link="a"/><child link="b"/></joint></robot>'
    )
    fitted, diags = fit_link_spheres(urdf, per_link=1)
    assert list(fitted) == ["b"]
    assert [d.rule for d in diags] == ["spheres-mesh-unreadable"] and "nope.stl" in diags[0].message
    xr = tmp_path / "in.xrdf"
    xr.write_text(
        "format: xrdf\nformat_version: 2.0\ncspace:\n  joint_names: []\n"
        "  acceleration_limits: []\n  jerk_limits: []\n"
    )
    args = ["spheres", str(urdf), "--xrdf", str(xr), "-o", str(tmp_path / "o")]
    res = runner.invoke(app, args)
    assert res.exit_code == 2 and "nope.stl" in res.output and "mesh file not found" in res.output
    assert not (tmp_path / "o").exists()
    res = runner.invoke(app, [*args, "--allow-missing-meshes"])
    assert res.exit_code == 0, res.output
    assert "nope.stl" in res.output  # the warning for the mesh left out
    assert load_xrdf(tmp_path / "o").resolved_spheres("collision_spheres")["b"]


def test_xacro_input_is_expanded(tmp_path: Path) -> None:
    x = tmp_path / "r.urdf.xacro"
    x.write_text(
        '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">'
        '<xacro:macro name="blk" params="n s"><link name="${n}"><collision><geometry>'
        '<box size="${s} ${s} ${s}"/></geometry></collision></link></xacro:macro>'
        '<xacro:blk n="a" s="0.1"/><xacro:blk n="b" s="0.2"/>'
        '<joint name="j" type="fixed"><parent link="a"/><child link="b"/></joint></robot>'
    )
    fitted, _ = fit_link_spheres(x, per_link=2)
    assert sorted(fitted) == ["a", "b"]
    assert max(s.radius for s in fitted["b"]) > max(s.radius for s in fitted["a"])


# --------------------------------------------------------------------------------------------
# Real robots
# --------------------------------------------------------------------------------------------
def test_panda_every_link_with_geometry_gets_spheres() -> None:
    fitted, diags = fit_link_spheres(needs(PANDA), per_link=2)
    assert list(fitted) == PANDA_GEOMETRY_LINKS
    # its visual meshes are COLLADA, read by the default visual check: nothing to say
    assert diags == []
    assert all(len(s) == 2 and all(q.radius > 0 for q in s) for s in fitted.values())
    geoms, _ = load_link_geometry(PANDA)
    for link in ("panda_link1", "panda_link4", "panda_hand"):
        m = sphere_metrics(geoms[link].solid, fitted[link], samples=5000)
        assert m.coverage > 0.35, link


def test_ur5_count_is_shared_over_every_link_with_geometry() -> None:
    fitted, _ = fit_link_spheres(needs(UR5), count=20)
    assert list(fitted) == UR5_GEOMETRY_LINKS
    assert sum(len(s) for s in fitted.values()) == 20
    assert all(len(s) >= 1 for s in fitted.values())
    # the long arm links get more spheres than the small wrist links
    assert len(fitted["upper_arm_link"]) > len(fitted["wrist_3_link"])


TWINS_URDF = """<robot name="twins">
  <link name="base"><collision><geometry><box size="0.3 0.2 0.1"/></geometry></collision></link>
  <link name="left"><collision><geometry><box size="0.05 0.05 0.3"/></geometry></collision></link>
  <link name="right"><collision><geometry><box size="0.05 0.05 0.3"/></geometry></collision>
  </link>
  <link name="foot"><collision><geometry><sphere radius="0.02"/></geometry></collision>
    <collision><origin xyz="0.05 0 0"/><geometry><sphere radius="0.02"/></geometry></collision>
  </link>
  <joint name="a" type="fixed"><parent link="base"/><child link="left"/></joint>
  <joint name="b" type="fixed"><parent link="base"/><child link="right"/></joint>
  <joint name="c" type="fixed"><parent link="base"/><child link="foot"/></joint>
</robot>
"""


def test_a_total_count_holds_shared_solids_and_the_urdfs_own_spheres(tmp_path: Path) -> None:
    """Unitree G1 with --sphere-budget 120 got 132 spheres: the total was split over the
    distinct solids only, while two links sharing a solid (left and right fingers) each carry
    its spheres and the URDF's own <sphere> collisions (the ankles' 4) come on top. The total
    holds them all; one too few for a sphere per link is an error."""
    urdf = tmp_path / "twins.urdf"
    urdf.write_text(TWINS_URDF)
    for total in (5, 9, 12):
        fitted, _ = fit_link_spheres(urdf, count=total)
        assert sum(len(s) for s in fitted.values()) == total
        assert len(fitted["foot"]) == 2 and fitted["left"] == fitted["right"]
    with pytest.raises(XrdfToolsError, match="one sphere per link to fit \\(3\\)"):
        fit_link_spheres(urdf, count=4)


def test_fitting_is_deterministic_for_a_seed() -> None:
    a, _ = fit_link_spheres(needs(PANDA), links=["panda_link3"], per_link=3, seed=7)
    b, _ = fit_link_spheres(PANDA, links=["panda_link3"], per_link=3, seed=7)
    c, _ = fit_link_spheres(PANDA, links=["panda_link3"], per_link=3, seed=8)
    assert a == b
    assert a != c


def test_counting_options_are_exclusive_and_checked() -> None:
    with pytest.raises(XrdfToolsError):
        fit_link_spheres(needs(PANDA), per_link=2, count=20)
    with pytest.raises(XrdfToolsError, match="less than the number of links"):
        fit_link_spheres(PANDA, count=3)
    with pytest.raises(XrdfToolsError, match="did you mean 'panda_link1'"):
        fit_link_spheres(PANDA, links=["panda_lnk1"])


def test_coverage_for_the_hand_tuned_panda_spheres() -> None:
    summary = coverage_for_xrdf(needs(PANDA), load_xrdf(PANDA_XRDF), samples=5000)
    assert summary.group == "panda_spheres"
    assert list(summary.links) == PANDA_GEOMETRY_LINKS
    assert summary.overall.sphere_count == 61
    covs = [m.coverage for m in summary.links.values()]
    assert min(covs) <= summary.overall.coverage <= max(covs)
    # cuRobo's base model is two 3 cm spheres: almost nothing of link0 is covered
    assert summary.links["panda_link0"].coverage < 0.15
    assert summary.unmeasured == ()


@pytest.mark.slow
def test_same_counts_as_the_anchor_cover_more_at_no_more_protrusion() -> None:
    anchor = coverage_for_xrdf(needs(PANDA), load_xrdf(PANDA_XRDF), samples=8000)
    budget = {k: m.protrusion_p95 for k, m in anchor.links.items()}
    counts = {k: m.sphere_count for k, m in anchor.links.items()}
    geoms, _ = load_link_geometry(PANDA)
    for link in ("panda_link1", "panda_link5", "panda_hand"):
        fitted, _ = fit_link_spheres(
            PANDA, links=[link], per_link=counts[link], max_protrusion=budget[link]
        )
        ours = sphere_metrics(geoms[link].solid, fitted[link], samples=8000)
        assert ours.coverage > anchor.links[link].coverage, link
        assert ours.protrusion_p95 <= budget[link] * 1.05 + 5e-4, link


# --------------------------------------------------------------------------------------------
# CLI
# --------------------------------------------------------------------------------------------
def test_cli_merge_replaces_only_the_chosen_links(runner: CliRunner, tmp_path: Path) -> None:
    out = tmp_path / "out.xrdf"
    args = ["spheres", str(needs(PANDA)), "--xrdf", str(PANDA_XRDF), "--links", "panda_link1"]
    res = runner.invoke(app, [*args, "--per-link", "3", "-o", str(out)])
    assert res.exit_code == 0, res.output
    assert "panda_link1" in res.output and "overall" in res.output
    before, after = load_xrdf(PANDA_XRDF), load_xrdf(out)
    old, new = before.resolved_spheres("panda_spheres"), after.resolved_spheres("panda_spheres")
    assert list(new) == list(old)
    assert len(new["panda_link1"]) == 3 and new["panda_link1"] != old["panda_link1"]
    assert all(new[k] == old[k] for k in old if k != "panda_link1")
    assert after.replace(geometry=None) == before.replace(geometry=None)


def test_cli_output_lints_clean(runner: CliRunner, tmp_path: Path) -> None:
    lint_mod = pytest.importorskip("xrdf_tools.lint")
    merged, fresh = tmp_path / "panda.xrdf", tmp_path / "ur5.xrdf"
    r1 = runner.invoke(
        app,
        [
            "spheres",
            str(needs(PANDA)),
            "--xrdf",
            str(PANDA_XRDF),
            "--links",
            "panda_hand",
            "--per-link",
            "4",
            "-o",
            str(merged),
        ],
    )
    r2 = runner.invoke(app, ["spheres", str(needs(UR5)), "--count", "12", "-o", str(fresh)])
    assert r1.exit_code == 0 and r2.exit_code == 0, r1.output + r2.output
    for out, urdf in ((merged, PANDA), (fresh, UR5)):
        diags = lint_mod.lint([out], urdf=urdf)
        errors = [d for d in diags if d.severity.value == "error"]
        assert errors == [], errors


def test_cli_refuses_to_overwrite_its_input_and_bad_options(
    runner: CliRunner, tmp_path: Path
) -> None:
    copy = tmp_path / "panda.xrdf"
    copy.write_text(PANDA_XRDF.read_text())
    res = runner.invoke(app, ["spheres", str(needs(PANDA)), "--xrdf", str(copy), "-o", str(copy)])
    assert res.exit_code == 2 and "overwrite" in res.output
    assert copy.read_text() == PANDA_XRDF.read_text()
    res = runner.invoke(app, ["spheres", str(PANDA), "--count", "30", "--density", "2"])
    assert res.exit_code == 2 and "only one of" in res.output
    res = runner.invoke(app, ["spheres", str(tmp_path / "none.urdf")])
    assert res.exit_code == 2 and "not found" in res.output


def test_a_loaded_robot_fits_like_its_file(tmp_path: Path) -> None:
    from xrdf_tools.robot.xacro_source import load_robot

    path = tmp_path / "prims.urdf"  # yourdfpy itself knows no <capsule>
    path.write_text(PRIMITIVES_URDF.replace("<capsule", "<cylinder"))
    robot = load_robot(path)
    by_robot, d1 = fit_link_spheres(robot, per_link=2, seed=3)
    by_path, d2 = fit_link_spheres(path, per_link=2, seed=3)
    assert by_robot == by_path and d1 == d2


def test_outside_distance_in_blocks_equals_one_block(monkeypatch: pytest.MonkeyPatch) -> None:
    """Far points are measured in blocks (memory grows with points x faces); the distances
    are those of one whole block and of the exact distance to a sphere."""
    from xrdf_tools.spheres import distance, metrics

    ball = trimesh.creation.icosphere(subdivisions=3, radius=0.1)
    rng = np.random.default_rng(0)
    pts = rng.normal(size=(500, 3))
    whole = metrics.outside_distance(ball, pts)
    monkeypatch.setattr(distance, "PAIR_BLOCK", 10 * len(ball.faces))
    blocked = metrics.outside_distance(ball, pts)
    assert np.array_equal(whole, blocked)
    exact = np.maximum(np.linalg.norm(pts, axis=1) - 0.1, 0.0)
    assert np.allclose(blocked, exact, atol=2e-3)


# --------------------------------------------------------------------------------------------
# cuRobo's metric set: protrusion share, surface gap, volume ratio (closed forms)
# --------------------------------------------------------------------------------------------
def test_union_volume_shares_and_ratio_match_closed_forms() -> None:
    cube = trimesh.creation.box(extents=[1.0, 1.0, 1.0])
    inner = sphere_metrics(cube, [Sphere((0.0, 0.0, 0.0), 0.3)], samples=40_000)
    assert inner.protrusion_share == 0.0
    assert inner.volume_ratio == pytest.approx(4 / 3 * math.pi * 0.3**3, rel=0.01)
    big = sphere_metrics(cube, [Sphere((0.0, 0.0, 0.0), 0.6)], samples=40_000)
    r, h = 0.6, 0.1
    ball = 4 / 3 * math.pi * r**3
    inside = ball - 6 * math.pi * h * h * (3 * r - h) / 3
    assert big.volume_ratio == pytest.approx(ball, rel=0.01)
    assert big.protrusion_share == pytest.approx(1 - inside / ball, abs=0.006)
    # two overlapping balls: the union is twice a ball minus the lens, pi(4r+d)(2r-d)^2/12
    two = [Sphere((-0.1, 0.0, 0.0), 0.3), Sphere((0.1, 0.0, 0.0), 0.3)]
    m = sphere_metrics(cube, two, samples=40_000)
    lens = math.pi * (4 * 0.3 + 0.2) * (0.6 - 0.2) ** 2 / 12
    assert m.volume_ratio == pytest.approx(2 * 4 / 3 * math.pi * 0.027 - lens, rel=0.01)


def test_surface_gap_of_a_concentric_smaller_sphere_is_the_difference_of_radii() -> None:
    ball = trimesh.creation.icosphere(subdivisions=4, radius=0.5)
    m = sphere_metrics(ball, [Sphere((0.0, 0.0, 0.0), 0.4)], samples=20_000)
    assert m.surface_gap_mean == pytest.approx(0.1, abs=0.002)
    assert m.surface_gap_p95 == pytest.approx(0.1, abs=0.002)
    assert m.max_uncovered_gap == pytest.approx(0.1, abs=0.002)
    assert m.coverage == pytest.approx(0.512, abs=0.012)
    assert m.volume_ratio == pytest.approx(0.4**3 / 0.5**3, rel=0.02)
    assert m.protrusion_share == 0.0 and m.surface_coverage == 0.0


def test_surface_gap_on_a_cube_face_matches_a_quadrature() -> None:
    """A ball of radius 0.6 in a unit cube: a face point at (u, v) from the face centre has
    gap max(0, sqrt(0.25 + u^2 + v^2) - 0.6); its mean over the face by a midpoint rule."""
    cube = trimesh.creation.box(extents=[1.0, 1.0, 1.0])
    m = sphere_metrics(cube, [Sphere((0.0, 0.0, 0.0), 0.6)], samples=40_000)
    u = (np.arange(400) + 0.5) / 400 - 0.5
    gap = np.maximum(np.sqrt(0.25 + u[:, None] ** 2 + u[None, :] ** 2) - 0.6, 0.0)
    assert m.surface_gap_mean == pytest.approx(float(gap.mean()), abs=0.0015)
    assert m.max_uncovered_gap == pytest.approx(math.sqrt(0.75) - 0.6, abs=0.003)
    assert m.surface_gap_p95 == pytest.approx(float(np.quantile(gap, 0.95)), abs=0.003)


def test_cli_refuses_to_overwrite_a_mesh_of_the_robot(runner: CliRunner, tmp_path: Path) -> None:
    """A mesh file the URDF names is an input too: ``-o`` on it is refused, the mesh kept."""
    needs(PANDA)
    urdf, mesh = panda_copy_with_mesh(tmp_path, "collision/link0.stl")
    before = mesh.read_bytes()
    pkg = ["--package-path", f"example-robot-data={tmp_path}", "--allow-missing-meshes"]
    res = runner.invoke(
        app, ["spheres", str(urdf), *pkg, "--links", "panda_link0", "-o", str(mesh)]
    )
    assert res.exit_code == 2, res.output
    assert f"{mesh}: refusing to overwrite an input" in res.output
    assert mesh.read_bytes() == before


def test_spheres_from_chooses_the_geometry_as_convert_does(
    runner: CliRunner, tmp_path: Path
) -> None:
    """`xrdf spheres` fell back to visual geometry on its own and had no --from, which
    `xrdf convert --fit-spheres` has: a link with a visual box only got spheres, and nothing
    could ask for collision geometry only or visual geometry only."""
    urdf = tmp_path / "two.urdf"
    urdf.write_text(
        '<robot name="two"><link name="a"><collision><geometry><box size="0.2 0.1 0.1"/>'
        '</geometry></collision><visual><geometry><box size="0.1 0.1 0.1"/></geometry></visual>'
        '</link><link name="b"><visual><geometry><box size="0.1 0.1 0.3"/></geometry>'
        '</visual></link><joint name="j" type="revolute"><parent link="a"/><child link="b"/>'
        '<axis xyz="0 0 1"/><limit lower="-1" upper="1" velocity="1" effort="1"/></joint>'
        "</robot>"
    )

    def fitted(*extra: str) -> dict[str, list[float]]:
        out = tmp_path / "o.xrdf"
        r = runner.invoke(app, ["spheres", str(urdf), "--per-link", "2", "-o", str(out), *extra])
        assert r.exit_code == 0, r.stderr
        spheres = load_xrdf(out).geometry["two_collision_spheres"].spheres
        return {k: [s.radius for s in v] for k, v in spheres.items()}

    assert set(fitted()) == {"a", "b"}  # auto, the default: collision, else visual
    assert set(fitted("--from", "collision")) == {"a"}
    by_visual = fitted("--from", "visual")
    assert set(by_visual) == {"a", "b"}
    assert max(by_visual["a"]) < max(fitted()["a"])  # a's visual box is half its collision box
