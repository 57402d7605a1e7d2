"""Sphere fitting on hard links (thin shells, parts without volume, placeholders, fingers),
clip planes, shared meshes, counts by coverage target, and the metrics in the CLI."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import trimesh
from typer.testing import CliRunner

from tests.robots import robot_urdf, robots_dir
from xrdf_tools.cli import app
from xrdf_tools.spheres import fit_link_spheres, sphere_metrics
from xrdf_tools.spheres.fit import parse_clip
from xrdf_tools.spheres.geometry import load_link_geometry
from xrdf_tools.spheres.inside import grid_inside, points_inside
from xrdf_tools.spheres.robot_fit import fit_robot
from xrdf_tools.util.errors import XrdfToolsError
from xrdf_tools.util.fixed_order import QUANTUM


def _robot(rel: str) -> Path:
    root = robots_dir()
    if root is None or not (root / rel).is_file():
        pytest.skip(f"{rel} not installed")
    return root / rel


# --------------------------------------------------------------------------------------------
# The grid inside test is the point inside test, column by column
# --------------------------------------------------------------------------------------------
def test_grid_inside_equals_the_point_test_on_every_node() -> None:
    geoms, _ = load_link_geometry(robot_urdf("panda"), links=["panda_link4", "panda_hand"])
    for g in geoms.values():
        lo, hi = g.solid.bounds
        axes = tuple(np.linspace(lo[i] - 0.01, hi[i] + 0.01, 17 + 3 * i) for i in range(3))
        grid = grid_inside(g.solid, axes)
        nodes = np.stack(np.meshgrid(*axes, indexing="ij"), -1).reshape(-1, 3)
        assert np.array_equal(grid.reshape(-1), points_inside(g.solid, nodes))
        assert 0.05 < grid.mean() < 0.9


# --------------------------------------------------------------------------------------------
# Hard links on real meshes
# --------------------------------------------------------------------------------------------
def test_part_without_volume_is_fitted_to_its_hull_and_said_so() -> None:
    """Unitree Z1's gripperStator (156 x 82 x 69 mm) is an open mesh whose trimesh hull is
    not watertight either: its hull rebuilt from qhull's facets gets the spheres."""
    urdf = _robot("z1_description/urdf/z1.urdf")
    result = fit_robot(urdf, links=["gripperStator"])
    spheres = result.spheres["gripperStator"]
    assert result.kinds["gripperStator"] == "convex_hull"
    assert any(
        d.rule == "spheres-convex-hull" and "gripperStator" in d.message for d in result.diagnostics
    )
    solid = result.geometry["gripperStator"].solid
    assert solid.is_volume and np.allclose(solid.extents, [0.156, 0.082, 0.06885], atol=1e-3)
    m = sphere_metrics(solid, spheres, samples=5000)
    assert 2 <= len(spheres) <= 16
    assert m.coverage >= 0.85 and m.protrusion_p95 <= 0.008


def test_thin_shell_base_is_fitted_to_its_hull_across_its_whole_span() -> None:
    """TIAGo's base_link is a closed shell with a tenth of its hull's volume."""
    urdf = _robot("tiago_description/robots/tiago.urdf")
    result = fit_robot(urdf, links=["base_link"])
    spheres = result.spheres["base_link"]
    assert result.kinds["base_link"] == "convex_hull"
    assert any(d.rule == "spheres-thin-shell" for d in result.diagnostics)
    centers = np.array([s.center for s in spheres])
    assert centers[:, 0].min() < -0.1 and centers[:, 0].max() > 0.1  # the mesh spans +-0.25
    m = sphere_metrics(result.geometry["base_link"].solid, spheres, samples=5000)
    assert m.coverage >= 0.85 and m.protrusion_p95 <= 0.025


def test_a_placeholder_gets_one_sphere() -> None:
    urdf = _robot("ur_description/urdf/ur5_robot.urdf")
    result = fit_robot(urdf, links=["ee_link", "wrist_3_link"], visual_check="off")
    assert len(result.spheres["ee_link"]) == 1
    assert len(result.spheres["wrist_3_link"]) > 1
    assert [d.rule for d in result.diagnostics] == ["spheres-placeholder"]


def test_a_zero_size_primitive_is_a_placeholder_not_a_traceback(tmp_path: Path) -> None:
    """Reachy's antenna and neck links collide as <cylinder length="0.0" radius="0.0"/>:
    trimesh gives vertices that no face uses (no bounds), and the bounding-box fallback
    raised a TypeError. Each gets one sphere at its origin, as a placeholder."""
    (tmp_path / "r.urdf").write_text(
        '<robot name="r"><link name="base"><collision><geometry><box size="0.1 0.1 0.1"/>'
        "</geometry></collision></link>"
        '<link name="antenna"><collision><origin xyz="0 0 0.2"/><geometry>'
        '<cylinder length="0.0" radius="0.0"/></geometry></collision></link>'
        '<joint name="j" type="fixed"><parent link="base"/><child link="antenna"/></joint>'
        "</robot>"
    )
    result = fit_robot(tmp_path / "r.urdf")
    (sphere,) = result.spheres["antenna"]
    assert np.allclose(sphere.center, [0, 0, 0.2], atol=1e-3) and sphere.radius <= 0.003
    assert any(
        d.rule == "spheres-placeholder" and "antenna" in d.message for d in result.diagnostics
    )
    assert len(result.spheres["base"]) > 1


def test_open_box_without_volume_falls_back_to_its_bounding_box(tmp_path: Path) -> None:
    """A flat part (a square sheet) has no hull volume: its bounding box, 2 mm thick."""
    sheet = trimesh.Trimesh(
        vertices=[[0, 0, 0], [0.1, 0, 0], [0.1, 0.1, 0], [0, 0.1, 0]], faces=[[0, 1, 2], [0, 2, 3]]
    )
    sheet.export(tmp_path / "sheet.stl")
    (tmp_path / "r.urdf").write_text(
        '<robot name="r"><link name="plate"><collision><geometry>'
        '<mesh filename="sheet.stl"/></geometry></collision></link></robot>'
    )
    result = fit_robot(tmp_path / "r.urdf")
    assert result.kinds["plate"] == "bounding_box"
    assert any(d.rule == "spheres-bounding-box" for d in result.diagnostics)
    assert np.allclose(
        sorted(result.geometry["plate"].solid.extents), [0.002, 0.1, 0.1], atol=QUANTUM
    )
    assert result.spheres["plate"]


# --------------------------------------------------------------------------------------------
# Counts, shared meshes, clip planes
# --------------------------------------------------------------------------------------------
def test_default_count_is_the_fewest_reaching_the_target() -> None:
    urdf = robot_urdf("panda")
    low = fit_robot(urdf, links=["panda_link3"], counts=_policy(0.8))
    high = fit_robot(urdf, links=["panda_link3"], counts=_policy(0.95))
    n_low, n_high = len(low.spheres["panda_link3"]), len(high.spheres["panda_link3"])
    assert n_low < n_high
    solid = low.geometry["panda_link3"].solid
    # one sphere fewer, within the same bound (not refined past it), falls short
    fewer = fit_robot(urdf, links=["panda_link3"], counts=_policy(0.8, n_low - 1)).spheres
    assert sphere_metrics(solid, low.spheres["panda_link3"], samples=8000).coverage >= 0.78
    assert sphere_metrics(solid, fewer["panda_link3"], samples=8000).coverage < 0.82


def _policy(target: float, per_link: int | None = None) -> object:
    from xrdf_tools.spheres.count_policy import CountPolicy

    return CountPolicy(per_link=per_link, target_coverage=target, refine=False)


def test_links_that_share_a_mesh_are_fitted_once(tmp_path: Path) -> None:
    mesh = trimesh.creation.box(extents=[0.1, 0.04, 0.04])
    mesh.export(tmp_path / "part.stl")
    link = (
        '<link name="{}"><collision><geometry><mesh filename="part.stl"/></geometry>'
        "</collision></link>"
    )
    (tmp_path / "r.urdf").write_text(
        '<robot name="r">'
        + "".join(link.format(n) for n in ("a", "b", "c"))
        + '<joint name="j1" type="fixed"><parent link="a"/><child link="b"/></joint>'
        + '<joint name="j2" type="fixed"><parent link="b"/><child link="c"/></joint></robot>'
    )
    result = fit_robot(tmp_path / "r.urdf", counts=_per_link(3))
    assert result.spheres["a"] == result.spheres["b"] == result.spheres["c"]
    assert result.seconds["b"] == 0.0 and result.seconds["c"] == 0.0
    shared = [d for d in result.diagnostics if d.rule == "spheres-shared-mesh"]
    assert len(shared) == 1 and "b, c" in shared[0].message


def test_a_shared_mesh_of_macro_made_links_is_located_in_the_macro(
    runner: CliRunner, tmp_path: Path
) -> None:
    """Robotiq 2F-85's fingers are made by a macro (``${prefix}${fingerprefix}_inner_finger``):
    every note about one of them was placed at that template in the macro file, but the
    shared-mesh note ("links right_… share the geometry of 'left_…'") had no line."""
    (tmp_path / "finger.xacro").write_text(
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:macro name="finger" params="side">\n'
        '    <link name="${side}_finger"><collision><geometry><box size="0.06 0.02 0.02"/>'
        "</geometry></collision></link>\n"
        '    <joint name="${side}_joint" type="fixed"><parent link="palm"/>'
        '<child link="${side}_finger"/></joint>\n'
        "  </xacro:macro>\n</robot>\n"
    )
    top = tmp_path / "hand.urdf.xacro"
    top.write_text(
        '<robot name="hand" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:include filename="finger.xacro"/>\n  <link name="palm"/>\n'
        '  <xacro:finger side="left"/>\n  <xacro:finger side="right"/>\n</robot>\n'
    )
    out = str(tmp_path / "hand.xrdf")
    r = runner.invoke(app, ["spheres", str(top), "--per-link", "2", "--format", "json", "-o", out])
    assert r.exit_code == 0, r.output
    diags = json.loads(r.stderr)["diagnostics"]
    shared = [d for d in diags if d["rule"] == "spheres-shared-mesh"]
    assert len(shared) == 1, diags
    assert shared[0]["path"].endswith("finger.xacro") and shared[0]["line"] == 3, shared
    assert "'left_finger'" in shared[0]["message"] and "right_finger" in shared[0]["message"]


def _per_link(n: int) -> object:
    from xrdf_tools.spheres.count_policy import CountPolicy

    return CountPolicy(per_link=n)


def test_clip_plane_keeps_every_sphere_on_its_side() -> None:
    urdf = robot_urdf("panda")
    link, plane = parse_clip("panda_link0:0,0,2,0.04")  # normal normalised, d with it
    assert plane == ((0.0, 0.0, 1.0), 0.02)
    clipped, _ = fit_link_spheres(urdf, links=[link], per_link=6, clips={link: [plane]})
    free, _ = fit_link_spheres(urdf, links=[link], per_link=6)
    assert min(s.center[2] - s.radius for s in free[link]) < 0.02
    assert all(s.center[2] - s.radius >= 0.02 - 1e-9 for s in clipped[link])
    with pytest.raises(XrdfToolsError, match="without geometry"):
        fit_link_spheres(urdf, links=[link], clips={"world": [plane]})
    for bad in ("panda_link0", "panda_link0:0,0,0,1", "panda_link0:a,b,c,d", ":0,0,1,0"):
        with pytest.raises(XrdfToolsError):
            parse_clip(bad)


# --------------------------------------------------------------------------------------------
# CLI
# --------------------------------------------------------------------------------------------
def test_cli_metrics_as_json_with_every_field(runner: CliRunner, tmp_path: Path) -> None:
    out = tmp_path / "p.xrdf"
    args = ["spheres", str(robot_urdf("panda")), "--links", "panda_link1,panda_link2"]
    args += ["--per-link", "3", "--format", "json", "-o", str(out)]
    res = runner.invoke(app, [*args, "--timings"])
    assert res.exit_code == 0, res.output
    doc = json.loads(res.stdout)
    assert list(doc["links"]) == ["panda_link1", "panda_link2"]
    fields = {
        "coverage",
        "protrusion_share",
        "protrusion_mean",
        "protrusion_p95",
        "surface_gap_mean",
        "surface_gap_p95",
        "max_uncovered_gap",
        "volume_ratio",
        "sphere_count",
        "fit_seconds",
    }
    assert fields <= set(doc["overall"])
    assert doc["overall"]["sphere_count"] == 6
    assert {m["solid"] for m in doc["links"].values()} == {"mesh"}
    assert all(m["fit_seconds"] > 0 for m in doc["links"].values())
    # without --timings: the same metrics, no wall time (the same bytes on every run)
    plain = runner.invoke(app, args)
    assert plain.exit_code == 0, plain.output
    assert json.loads(plain.stdout) == {
        part: (
            {k: {f: v for f, v in m.items() if f != "fit_seconds"} for k, m in doc[part].items()}
            if part == "links"
            else {f: v for f, v in doc[part].items() if f != "fit_seconds"}
        )
        for part in doc
    }


def test_cli_names_the_solid_a_thin_shell_was_measured_against(runner: CliRunner) -> None:
    urdf = _robot("tiago_description/robots/tiago.urdf")
    res = runner.invoke(app, ["spheres", str(urdf), "--links", "base_link", "--per-link", "4"])
    assert res.exit_code == 0, res.output
    assert "base_link: convex_hull" in res.output


def test_cli_clip_and_bad_clip(runner: CliRunner, tmp_path: Path) -> None:
    urdf = str(robot_urdf("panda"))
    out = tmp_path / "p.xrdf"
    args = ["spheres", urdf, "--links", "panda_link0", "--clip", "panda_link0:0,0,1,0.05"]
    res = runner.invoke(app, [*args, "-o", str(out)])
    assert res.exit_code == 0, res.output
    from xrdf_tools.xrdf.io import load_xrdf

    spheres = load_xrdf(out).world_collision_spheres()["panda_link0"]
    assert spheres and all(s.center[2] - s.radius >= 0.05 - 1e-9 for s in spheres)
    res = runner.invoke(app, ["spheres", urdf, "--clip", "panda_link0:0,0,1"])
    assert res.exit_code == 2 and "LINK:nx,ny,nz,d" in res.output


def test_clip_plane_beyond_the_whole_link_is_reported() -> None:
    urdf = robot_urdf("panda")
    clips = {"panda_link1": [((0.0, 0.0, 1.0), 5.0)]}  # everything lies below z = 5 m
    fitted, diags = fit_link_spheres(
        urdf, links=["panda_link1"], per_link=2, clips=clips, visual_check="off"
    )
    assert fitted == {}
    assert [d.rule for d in diags] == ["spheres-target-missed"]
    assert "clip planes" in diags[0].message


def test_hull_faces_are_turned_outward_as_trimesh_fix_normals_turns_them() -> None:
    """The vectorised orientation of a convex hull's faces gives the faces, in the same vertex
    order, that trimesh's face-by-face ``fix_normals`` gives, on real open and closed meshes."""
    from scipy.spatial import ConvexHull

    from xrdf_tools.robot.link_geometry import link_geometry
    from xrdf_tools.robot.xacro_source import load_robot
    from xrdf_tools.spheres.mesh_solids import _turn_outward

    robot = load_robot(_robot("so_arm_description/urdf/so101.urdf"))
    meshes = [
        p.in_link_frame() for lk in link_geometry(robot, "collision").values() for p in lk.parts
    ]
    assert len(meshes) >= 5
    for mesh in meshes:
        ch = ConvexHull(np.asarray(mesh.vertices, dtype=np.float64), qhull_options="Qt")
        ours = trimesh.Trimesh(mesh.vertices, ch.simplices, process=True)
        ours.remove_unreferenced_vertices()
        theirs = ours.copy()
        _turn_outward(ours)
        theirs.fix_normals()
        np.testing.assert_array_equal(ours.faces, theirs.faces)
        assert ours.is_volume and ours.volume > 0


def test_overlapping_shells_in_one_mesh_file_are_fitted_as_their_union() -> None:
    """The demo arm's shoulder is two intersecting cylinders in one STL (as CAD exports
    write links). Points inside both cross an even number of faces: fitted to the file as
    one mesh, they counted as outside, and 16 spheres covered half the link. The shells are
    unioned like the parts of a link."""
    import trimesh as tm

    from tests.paths import FIXTURES

    urdf = FIXTURES / "demo_arm" / "demo_arm.urdf"
    raw = tm.load(FIXTURES / "demo_arm" / "meshes" / "shoulder.stl")
    shells = raw.split(only_watertight=False)
    assert len(shells) == 2 and all(s.is_volume for s in shells)
    geoms, _ = load_link_geometry(urdf, links=["shoulder_link"])
    g = geoms["shoulder_link"]
    assert g.kind == "union" and g.solid.is_volume
    assert g.solid.volume < 0.95 * sum(s.volume for s in shells)  # the overlap counted once
    assert g.solid.volume > max(s.volume for s in shells)
    # an inside test of the union sees the overlap as inside
    both = np.array([[0.0, 0.0, 0.0]])  # the shells' common centre
    assert all(s.contains(both)[0] for s in shells) and g.solid.contains(both)[0]
    fitted, _ = fit_link_spheres(urdf, links=["shoulder_link"])
    spheres = fitted["shoulder_link"]
    m = sphere_metrics(g.solid, spheres, samples=4000, seed=0)
    assert m.coverage >= 0.85 and len(spheres) <= 12


def test_a_mesh_in_millimetres_without_its_scale_is_said(tmp_path: Path) -> None:
    """A CAD export in millimetres read as metres makes a 20 cm link 200 m long: the fit runs
    (spheres fitted as it is) and a located warning says what to set; with the scale, no
    warning."""
    trimesh.creation.box(extents=(60.0, 40.0, 200.0)).export(tmp_path / "link_mm.stl")
    text = (
        '<robot name="r">\n<link name="base"/>\n<link name="arm">\n'
        '<collision><geometry><mesh filename="link_mm.stl"{scale}/></geometry></collision>\n'
        '</link>\n<joint name="j" type="revolute"><parent link="base"/><child link="arm"/>'
        '<axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>\n'
        "</robot>\n"
    )
    urdf = tmp_path / "r.urdf"
    urdf.write_text(text.format(scale=""))
    _, diags = fit_link_spheres(urdf, links=["arm"], per_link=2)
    (said,) = [d for d in diags if d.rule == "spheres-mesh-scale"]
    assert said.path == str(urdf) and said.line == 3
    assert "spans 200 m" in said.message and 'scale="0.001 0.001 0.001"' in said.message
    urdf.write_text(text.format(scale=' scale="0.001 0.001 0.001"'))
    _, diags = fit_link_spheres(urdf, links=["arm"], per_link=2)
    assert not [d for d in diags if d.rule == "spheres-mesh-scale"]


def test_overlapping_thin_shells_in_one_file_are_hulled_unioned_and_said_once(
    tmp_path: Path,
) -> None:
    """Kinova Gen3's arm covers: one mesh file of several overlapping bodies, each a thin
    shell. Each body is replaced by its hull, the hulls are unioned, and one note says so
    (this crashed with an index error once bodies were split)."""
    arm_x = trimesh.creation.box(extents=(0.2, 0.003, 0.05))
    arm_x.apply_translation([0.1, 0.0015, 0.025])
    arm_y = trimesh.creation.box(extents=(0.003, 0.2, 0.05))
    arm_y.apply_translation([0.0015, 0.1, 0.025])
    a = trimesh.boolean.union([arm_x, arm_y], engine="manifold")  # an L of 3 mm walls
    assert a.is_volume and a.volume < 0.4 * a.convex_hull.volume
    b = a.copy()
    b.apply_translation([0.01, 0.01, 0.02])
    trimesh.util.concatenate([a, b]).export(tmp_path / "covers.stl")
    urdf = tmp_path / "r.urdf"
    urdf.write_text(
        '<robot name="r">\n<link name="base"/>\n<link name="arm">\n'
        '<collision><geometry><mesh filename="covers.stl"/></geometry></collision>\n'
        '</link>\n<joint name="j" type="revolute"><parent link="base"/><child link="arm"/>'
        '<axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>\n'
        "</robot>\n"
    )
    geoms, diags = load_link_geometry(urdf, links=["arm"])
    g = geoms["arm"]
    assert g.kind == "union" and g.solid.is_volume
    assert g.solid.volume > max(a.convex_hull.volume, b.convex_hull.volume)
    (note,) = [d for d in diags if d.rule == "spheres-thin-shell"]
    assert "link 'arm': of its 2 bodies, 2 thin shells" in note.message and note.line == 3
    # one shell beside a solid block: the note is about that body, not the whole link
    block = trimesh.creation.box(extents=(0.05, 0.05, 0.05))
    block.apply_translation([0.6, 0.6, 0.3])  # far: their hulls fill little of the whole
    trimesh.util.concatenate([a, block]).export(tmp_path / "covers.stl")
    _, diags = load_link_geometry(urdf, links=["arm"])
    (note,) = [d for d in diags if d.rule == "spheres-thin-shell"]
    assert note.message.startswith("link 'arm': of its 2 bodies, one thin shell (its volume")


def test_separate_plates_in_one_file_are_not_filled_in_as_one_shell(tmp_path: Path) -> None:
    """Two 3 mm plates 60 mm apart in one STL (a gripper's jaws): as a whole they are a small
    share of their common hull, with thin walls, but each plate is a solid. Each body is
    judged alone: the plates are kept, the gap between them stays empty (it was filled by the
    hull of both)."""
    plates = []
    for y in (-0.03, 0.03):
        plate = trimesh.creation.box(extents=(0.08, 0.003, 0.04))
        plate.apply_translation([0.0, y, 0.0])
        plates.append(plate)
    trimesh.util.concatenate(plates).export(tmp_path / "jaws.stl")
    urdf = tmp_path / "r.urdf"
    urdf.write_text(
        '<robot name="r">\n<link name="base"/>\n<link name="jaws">\n'
        '<collision><geometry><mesh filename="jaws.stl"/></geometry></collision>\n'
        '</link>\n<joint name="j" type="revolute"><parent link="base"/><child link="jaws"/>'
        '<axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>\n'
        "</robot>\n"
    )
    geoms, diags = load_link_geometry(urdf, links=["jaws"])
    g = geoms["jaws"]
    assert g.kind == "union"
    assert g.solid.volume == pytest.approx(2 * 0.08 * 0.003 * 0.04, rel=1e-3)
    assert not g.solid.contains([[0.0, 0.0, 0.0]])[0]  # the gap between the jaws is free
    assert not [d for d in diags if d.rule == "spheres-thin-shell"]


SPHERE_LINK_URDF = """<robot name="r">
  <link name="base"><collision><geometry><box size="0.2 0.2 0.1"/></geometry></collision></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="a"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <link name="a">
    <collision><origin xyz="0 0 0.1"/><geometry><sphere radius="0.0796"/></geometry></collision>
    <collision><origin xyz="0 0.01 0.25"/><geometry><sphere radius="0.05"/></geometry></collision>
  </link>
</robot>
"""


def test_a_link_made_of_urdf_spheres_keeps_them_exactly(tmp_path: Path) -> None:
    """Drake's iiwa14_spheres_collision models links as <sphere> elements: the fit had moved
    them (radius 0.0796 became 0.083, 2 mm off); they are taken as they are, and a link of
    other shapes beside them is still fitted. A clip plane on the link makes it a fit again."""
    from xrdf_tools.xrdf.model import Sphere

    urdf = tmp_path / "r.urdf"
    urdf.write_text(SPHERE_LINK_URDF)
    result = fit_robot(urdf)
    assert result.spheres["a"] == (
        Sphere(center=(0.0, 0.0, 0.1), radius=0.0796),
        Sphere(center=(0.0, 0.01, 0.25), radius=0.05),
    )
    assert len(result.spheres["base"]) > 1 and list(result.spheres) == ["base", "a"]
    said = [d for d in result.diagnostics if d.rule == "spheres-from-urdf"]
    assert [(d.line, d.message) for d in said] == [
        (6, "link 'a': its collision geometry is 2 <sphere> element(s), taken as they are")
    ]
    clipped = fit_robot(urdf, clips={"a": [parse_clip("a:0,0,1,0.05")[1]]})
    assert all(s.center[2] - s.radius >= 0.05 - 1e-9 for s in clipped.spheres["a"])


FORK_URDF = """<robot name="r">
<link name="base"/>
<link name="fork"><collision><geometry><mesh filename="fork.stl"/></geometry></collision></link>
<joint name="j" type="revolute"><parent link="base"/><child link="fork"/>
<axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>
"""


def test_a_fork_is_a_concave_solid_not_a_thin_shell(tmp_path: Path) -> None:
    """A clevis (two 15 mm prongs 7 cm apart on a plate, the slot where the next link turns)
    has 36 % of its hull's volume, like a moulded cover, but walls a tenth of its size: it is
    fitted as the solid it is, and no sphere fills the slot (its hull's spheres did, and
    collided with the link turning in it)."""
    from xrdf_tools.spheres.mesh_solids import is_thin_shell, wall_thickness

    plate = trimesh.creation.box(extents=(0.1, 0.06, 0.015))
    plate.apply_translation([0.0, 0.0, 0.0075])
    prongs = []
    for x in (-0.0425, 0.0425):
        prong = trimesh.creation.box(extents=(0.015, 0.06, 0.16))
        prong.apply_translation([x, 0.0, 0.015 + 0.08])
        prongs.append(prong)
    fork = trimesh.boolean.union([plate, *prongs], engine="manifold")
    hull = fork.convex_hull
    assert fork.is_volume and fork.volume < 0.4 * hull.volume
    assert wall_thickness(fork) > 0.08 * np.cbrt(hull.volume) and not is_thin_shell(fork, hull)
    fork.export(tmp_path / "fork.stl")
    (tmp_path / "r.urdf").write_text(FORK_URDF)
    geoms, diags = load_link_geometry(tmp_path / "r.urdf", links=["fork"])
    assert geoms["fork"].kind == "mesh"
    assert not [d for d in diags if d.rule == "spheres-thin-shell"]
    spheres, _ = fit_link_spheres(tmp_path / "r.urdf", links=["fork"])
    slot = np.array([[0.0, 0.0, z] for z in (0.05, 0.1, 0.15)])  # the middle of the slot
    for s in spheres["fork"]:
        gap = np.linalg.norm(slot - np.asarray(s.center), axis=1) - s.radius
        assert (gap > 0.01).all(), (s, gap)


def test_a_thin_shell_note_gives_its_wall_thickness() -> None:
    """TIAGo's base cover: the note says how thin its walls are, the reason it is hulled."""
    _, diags = load_link_geometry(
        _robot("tiago_description/robots/tiago.urdf"), links=["base_link"]
    )
    (note,) = [d for d in diags if d.rule == "spheres-thin-shell"]
    assert "its walls about" in note.message and "mm thick" in note.message


@pytest.mark.parametrize(
    ("text", "plane"),
    [
        ("a:1e300,0,0,1e300", ((1.0, 0.0, 0.0), 1.0)),  # the squares overflow
        ("a:0,1e-200,0,0", ((0.0, 1.0, 0.0), 0.0)),  # the squares underflow
        ("a:0,0,2,0.04", ((0.0, 0.0, 1.0), 0.02)),
    ],
)
def test_a_clip_normal_of_any_finite_size_is_normalised(
    text: str, plane: tuple[tuple[float, float, float], float]
) -> None:
    """A normal whose squared length leaves float range was divided by inf (a zero normal,
    a plane no sphere can keep) or refused as zero."""
    assert parse_clip(text) == ("a", plane)


@pytest.mark.parametrize(
    ("text", "said"),
    [
        ("a:0,0,1,inf", "must be finite numbers"),
        ("a:nan,0,1,0", "must be finite numbers"),
        ("a:0,0,0,1", "the normal (nx, ny, nz) must be non-zero"),
    ],
)
def test_a_clip_that_is_no_plane_says_why(text: str, said: str) -> None:
    with pytest.raises(XrdfToolsError) as exc:
        parse_clip(text)
    assert said in str(exc.value)
