"""One loader of URDF link geometry (:mod:`xrdf_tools.robot.link_geometry`) for viz, spheres and
lint.

On the bundled demo arm and a real robot of example-robot-data: viz draws exactly the parts
sphere fitting solidifies, both read from the loaded :class:`~xrdf_tools.robot.core.Robot` without
parsing the URDF again; ``<capsule>`` (not standard URDF, unknown to yourdfpy) is loaded by
every command.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from typer.testing import CliRunner

from tests.paths import FIXTURES
from tests.robots import robot_urdf
from xrdf_tools.cli import app
from xrdf_tools.robot import link_geometry as lg
from xrdf_tools.robot.core import Robot
from xrdf_tools.robot.xacro_source import load_robot
from xrdf_tools.spheres import fit_link_spheres
from xrdf_tools.spheres.geometry import load_link_geometry
from xrdf_tools.viz.meshes import load_link_meshes

DEMO = FIXTURES / "demo_arm" / "demo_arm.urdf"

CAPSULE_URDF = """<robot name="caps">
  <link name="base">
    <collision><geometry><box size="0.2 0.2 0.1"/></geometry></collision>
  </link>
  <link name="arm">
    <visual><origin xyz="0 0 0.15"/><geometry><capsule radius="0.04" length="0.2"/></geometry>
      <material name="blue"><color rgba="0 0 1 1"/></material></visual>
    <collision><origin xyz="0 0 0.15"/><geometry><capsule radius="0.04" length="0.2"/></geometry>
    </collision>
    <collision><origin xyz="0 0 0.15"/><geometry><cylinder radius="0.03" length="0.1"/>
    </geometry></collision>
  </link>
  <joint name="j" type="revolute"><parent link="base"/><child link="arm"/>
    <origin xyz="0 0 0.05"/><axis xyz="0 1 0"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>
"""


def _link_vertices(parts: Any) -> np.ndarray[Any, Any]:
    return np.vstack([p.vertices for p in parts])


def _same_parts_for_viz_and_spheres(robot: Robot, kind: lg.GeometrySource) -> int:
    """Viz's meshes of every link equal the loader's parts in the link frame, which are what
    sphere fitting solidifies; returns the number of links compared."""
    loaded = lg.link_geometry(robot, kind)
    drawn, _ = load_link_meshes(robot, robot.links, kind)
    solids, _ = load_link_geometry(robot, source=kind)
    compared = 0
    for name, link in loaded.items():
        if not link.parts:
            assert name not in drawn and name not in solids
            continue
        assert link.source == kind
        in_link = [p.in_link_frame() for p in link.parts]
        assert np.allclose(_link_vertices(drawn[name]), _link_vertices(in_link), atol=1e-12)
        assert sum(len(p.faces) for p in drawn[name]) == sum(len(m.faces) for m in in_link)
        if name in solids:
            assert solids[name].parts == len(link.parts) and solids[name].source == kind
            if solids[name].kind == "mesh":  # one closed part: the solid is that part
                assert np.array_equal(solids[name].solid.vertices, in_link[0].vertices)
        compared += 1
    return compared


def test_demo_arm_viz_and_spheres_get_the_same_parts() -> None:
    robot = load_robot(DEMO)
    assert _same_parts_for_viz_and_spheres(robot, "collision") == 7
    assert _same_parts_for_viz_and_spheres(robot, "visual") == 8  # and the camera's box
    camera = lg.link_geometry(robot, "auto", links=["camera_link"])["camera_link"]
    assert camera.source == "visual" and camera.line == robot.link_lines["camera_link"]
    (box,) = camera.parts
    assert box.shape == "box" and box.origin[2, 3] == pytest.approx(0.03)
    assert box.mesh.extents == pytest.approx([0.04, 0.09, 0.03])


def test_real_robot_viz_and_spheres_get_the_same_parts() -> None:
    robot = load_robot(robot_urdf("panda"))
    assert _same_parts_for_viz_and_spheres(robot, "collision") == 11
    # visual COLLADA files hold several sub-meshes (one per material): viz draws each with its
    # colour, sphere fitting takes them together; both are the same triangles
    link0 = lg.link_geometry(robot, "visual", links=["panda_link0"])["panda_link0"]
    (part,) = link0.parts
    assert part.shape == "mesh" and part.file is not None and part.file.endswith("link0.dae")
    assert len(part.pieces) > 1
    drawn, _ = load_link_meshes(robot, ["panda_link0"], "visual")
    assert len(drawn["panda_link0"]) == len(part.pieces)
    assert len({m.color for m in drawn["panda_link0"]}) > 1
    assert np.allclose(_link_vertices(drawn["panda_link0"]), part.in_link_frame().vertices)


def test_fitting_a_loaded_robot_does_not_parse_the_urdf_again(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    from lxml import etree

    import xrdf_tools.robot.urdf_source as urdf_source

    robot = load_robot(DEMO)
    calls: list[str] = []

    def spy(name: str, real: Any) -> Any:
        def wrapper(*args: Any, **kwargs: Any) -> Any:
            calls.append(name)
            return real(*args, **kwargs)

        return wrapper

    for module, name in (
        (etree, "fromstring"),
        (etree, "parse"),
        (urdf_source, "_parse_bytes"),
        (urdf_source, "read_urdf_bytes"),
    ):
        monkeypatch.setattr(module, name, spy(name, getattr(module, name)))
    fitted, diags = fit_link_spheres(robot, per_link=2, seed=0)
    assert len(fitted) == 8 and calls == []
    assert [d.rule for d in diags] == ["spheres-visual-fallback"]  # the camera
    # a path is loaded once, through the robot loader
    by_path, _ = fit_link_spheres(DEMO, per_link=2, seed=0)
    assert by_path == fitted and calls.count("_parse_bytes") == 1
    assert "fromstring" in calls  # the loader's one parse


def test_capsules_load_everywhere(runner: CliRunner, tmp_path: Path) -> None:
    path = tmp_path / "caps.urdf"
    path.write_text(CAPSULE_URDF)
    robot = load_robot(path)  # yourdfpy itself knows no <capsule>
    assert robot.capsules == {("arm", "visual", 0), ("arm", "collision", 0)}
    arm = lg.link_geometry(robot, "collision", links=["arm"])["arm"]
    capsule, cylinder = arm.parts
    assert (capsule.shape, cylinder.shape) == ("capsule", "cylinder")
    assert capsule.mesh.extents == pytest.approx([0.08, 0.08, 0.28], rel=0.01)
    assert capsule.in_link_frame().bounds[1][2] == pytest.approx(0.29, rel=0.01)
    # viz draws the capsule in its material colour
    drawn, diags = load_link_meshes(robot, ["arm"], "visual")
    (part,) = drawn["arm"]
    assert diags == [] and part.source == "capsule" and part.color == (0.0, 0.0, 1.0, 1.0)
    assert part.vertices[:, 2].max() == pytest.approx(0.29, rel=0.01)
    solids, _ = load_link_geometry(robot, links=["arm"])
    volume = math.pi * 0.04**2 * 0.2 + 4 / 3 * math.pi * 0.04**3
    assert solids["arm"].solid.volume == pytest.approx(volume, rel=0.02)  # cylinder inside
    # the command line fits and lints it (yourdfpy alone refused the file)
    out = tmp_path / "caps.xrdf"
    r = runner.invoke(app, ["spheres", str(path), "--per-link", "2", "-o", str(out)])
    assert r.exit_code == 0, r.output
    lint = runner.invoke(app, ["lint", str(out), "--urdf", str(path)])
    assert lint.exit_code == 0, lint.output


def test_unreadable_parts_are_failures_worded_once(tmp_path: Path) -> None:
    path = tmp_path / "m.urdf"
    path.write_text(
        '<robot name="m"><link name="a"><visual><geometry><mesh filename="nope.stl"/>'
        "</geometry></visual><collision><geometry><mesh filename="
        f'"file://{FIXTURES}/demo_arm/demo_arm.srdf"/></geometry></collision>'
        '<collision><geometry><sphere radius="0.1"/></geometry></collision></link></robot>'
    )
    robot = load_robot(path)
    a = lg.link_geometry(robot, "collision")["a"]
    assert a.elements == 2 and [p.shape for p in a.parts] == ["sphere"]
    (failure,) = a.failures
    assert failure.index == 0 and "cannot read mesh" in failure.reason
    _, vdiags = load_link_meshes(robot, ["a"], "visual")
    _, sdiags = load_link_geometry(robot, source="visual")
    missing = f"nope.stl: mesh file not found ({tmp_path / 'nope.stl'})"
    assert [d.message for d in vdiags] == [f"link 'a': visual mesh not drawn: {missing}"]
    assert [d.message for d in sdiags] == [f"link 'a' visual: {missing}; this part is ignored"]
    assert {d.line for d in [*vdiags, *sdiags]} == {None, robot.link_lines["a"]}


def test_report_coverage_measures_the_loaded_xacro(runner: CliRunner, tmp_path: Path) -> None:
    from tests.convert.test_one_command import XACRO

    robot = tmp_path / "r.urdf.xacro"
    robot.write_text(XACRO)
    out = tmp_path / "r.xrdf"
    args = ["--xacro-arg", "prefix:=z_"]
    r = runner.invoke(
        app, ["convert", str(robot), *args, "--fit-spheres", "-n", "200", "-o", str(out)]
    )
    assert r.exit_code == 0, r.output
    rep = runner.invoke(
        app, ["report", str(out), "--urdf", str(robot), *args, "-n", "200", "--coverage"]
    )
    assert rep.exit_code == 0, rep.output
    # the links of the expansion with its argument, not of the xacro's defaults (a_)
    assert "z_base: sphere_count" in rep.output and "a_base" not in rep.output
    assert "not measured" not in rep.output


def test_a_shape_yourdfpy_does_not_hold_is_unsupported(tmp_path: Path) -> None:
    import yourdfpy

    path = tmp_path / "caps.urdf"
    path.write_text(CAPSULE_URDF)
    robot = load_robot(path)  # a yourdfpy object changed in code: a geometry without a shape
    robot.urdf.link_map["base"].collisions.append(
        yourdfpy.Collision("odd", None, yourdfpy.Geometry())
    )
    base = lg.link_geometry(robot, "collision", links=["base"])["base"]
    assert base.elements == 2 and len(base.parts) == 1 and base.failures[0].unsupported
    _, diags = load_link_geometry(robot, links=["base"])
    assert [d.rule for d in diags] == ["spheres-unsupported-geometry"]


def test_a_package_uri_without_a_name_is_a_path_below_a_search_directory(tmp_path: Path) -> None:
    """``package:///pkg/meshes/a.stl`` (as Pinocchio's robots write it): found below the
    URDF's folder or a parent of it, or below a --package-path directory; else an error naming
    what was searched."""
    from xrdf_tools.robot.packages import PackageResolver
    from xrdf_tools.util.errors import XrdfToolsError

    mesh = tmp_path / "share" / "pkg" / "meshes" / "a.stl"
    mesh.parent.mkdir(parents=True)
    mesh.write_text("solid a\nendsolid a\n")
    urdf = tmp_path / "share" / "pkg" / "robots" / "r.urdf"
    urdf.parent.mkdir(parents=True)
    urdf.write_text("<robot name='r'/>")
    uri = "package:///pkg/meshes/a.stl"
    assert PackageResolver(urdf).resolve_uri(uri) == mesh
    elsewhere = tmp_path / "elsewhere" / "r.urdf"
    elsewhere.parent.mkdir()
    given = PackageResolver(elsewhere, {"anything": str(tmp_path / "share")})
    assert given.resolve_uri(uri) == mesh
    with pytest.raises(XrdfToolsError, match="package:/// URI"):
        PackageResolver(elsewhere).resolve_uri("package:///nope/a.stl")


def test_a_package_split_over_two_folders_finds_each_file(tmp_path: Path) -> None:
    """iCub's manual models sit in a folder whose package.xml names 'iCub' and hold some of
    the meshes; the others are in the sibling folder 'iCub' (both install into one package).
    A file the nearest folder lacks is found in the farther one; a --package-path directory
    is taken alone, as given: a file it lacks is an error naming it."""
    import trimesh

    from xrdf_tools.robot.packages import PackageResolver
    from xrdf_tools.util.errors import XrdfToolsError

    manual, generated = tmp_path / "models" / "manual", tmp_path / "models" / "robo"
    for mesh in (manual / "meshes" / "hand.stl", generated / "meshes" / "torso.stl"):
        mesh.parent.mkdir(parents=True)
        trimesh.creation.box((0.1, 0.1, 0.1)).export(mesh)
    (manual / "package.xml").write_text("<package><name>robo</name></package>")
    urdf = manual / "robots" / "r.urdf"
    urdf.parent.mkdir()
    links = "".join(
        f'<link name="{n}"><collision><geometry><mesh filename="package://robo/meshes/{n}.stl"/>'
        "</geometry></collision></link>"
        for n in ("hand", "torso")
    )
    joint = '<joint name="j" type="fixed"><parent link="torso"/><child link="hand"/></joint>'
    urdf.write_text(f'<robot name="r">{links}{joint}</robot>')
    found = PackageResolver(urdf)
    assert found.resolve_uri("package://robo/meshes/hand.stl") == manual / "meshes" / "hand.stl"
    assert found.resolve_uri("package://robo/meshes/torso.stl") == generated / "meshes/torso.stl"
    assert found.resolve_uri("package://robo/meshes/none.stl") == manual / "meshes" / "none.stl"
    given = PackageResolver(urdf, {"robo": str(manual)})
    with pytest.raises(XrdfToolsError, match="--package-path directory of 'robo'"):
        given.resolve_uri("package://robo/meshes/torso.stl")
    geometry = lg.link_geometry(load_robot(urdf), "collision")
    assert {n: (len(g.parts), g.failures) for n, g in geometry.items()} == {
        "hand": (1, ()),
        "torso": (1, ()),
    }


def test_a_zero_radius_sphere_is_a_point_like_a_zero_box(runner: CliRunner, tmp_path: Path) -> None:
    """A URDF ``<sphere radius="0">`` (the check allows zero sizes) loads as the point a
    ``<box size="0 0 0">`` is: finite vertices, and no numpy warning printed by every command
    that reads geometry (a RuntimeWarning is an error in this suite)."""
    parts = {}
    for shape in ('<sphere radius="0"/>', '<box size="0 0 0"/>'):
        path = tmp_path / "z.urdf"
        path.write_text(
            f'<robot name="z"><link name="a"><collision><geometry>{shape}</geometry>'
            "</collision></link></robot>"
        )
        (part,) = lg.link_geometry(load_robot(path), "collision")["a"].parts
        parts[part.shape] = part
        vertices = np.asarray(part.mesh.vertices)
        assert len(vertices) and np.isfinite(vertices).all() and not vertices.any()
    assert parts["sphere"].radius == 0.0
    xrdf = tmp_path / "z.xrdf"
    xrdf.write_text(
        "format: xrdf\nformat_version: 1.0\ncspace:\n  joint_names: []\n"
        "  acceleration_limits: []\n  jerk_limits: []\ncollision:\n  geometry: g\n"
        "geometry:\n  g:\n    spheres:\n      a:\n        - center: [0.0, 0.0, 0.0]\n"
        "          radius: 0.01\n"
    )
    lint = runner.invoke(app, ["lint", str(xrdf), "--urdf", str(tmp_path / "z.urdf")])
    assert lint.exit_code == 0 and "Warning" not in lint.output, lint.output
