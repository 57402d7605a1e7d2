"""`xrdf export curobo` writes a URDF whose joint axes cuRobo can take, as the same robot.

cuRobo turns joints about ±x, ±y, ±z only and its loader raises on any other axis; iCub's
creo2urdf model has shoulder and wrist axes tilted 15° and others a rounding error off z
(``1.0000000000000004``). The export stopped on them; it now writes a URDF in which every
link frame is where it was at every configuration (checked by our FK and yourdfpy's)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import yaml
from typer.testing import CliRunner

from xrdf_tools.cli import app
from xrdf_tools.export.curobo_axes import axes_to_rewrite, straighten_axes
from xrdf_tools.robot.axes import is_coordinate_axis
from xrdf_tools.robot.kinematics import build_kinematic_model, fk
from xrdf_tools.robot.urdf_source import parse_robot
from xrdf_tools.util.rotations import matrix_from_rpy, rpy_from_matrix

LIMIT = '<limit lower="-1.2" upper="1.2" effort="10" velocity="1"/>'
#: Tilted revolute (j1), prismatic without <origin> (j2), an axis off x by rounding (j3), a
#: continuous axis near -z (j4), a mimic follower with a tilted axis (finger), and a link and a
#: joint already named as the rewrite of j1 would name its new ones.
URDF = f"""<?xml version="1.0"?>
<!-- a comment kept -->
<robot name="tilted">
  <link name="base"/>
  <link name="l1"><collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision></link>
  <link name="l1__axis"/>
  <link name="l2"/>
  <link name="l3"/>
  <link name="l4"/>
  <link name="finger"/>
  <link name="ee"/>
  <joint name="j1" type="revolute">
    <parent link="base"/>
    <child link="l1"/>
    <origin xyz="0.1 0 0.2" rpy="0.3 -0.2 0.5"/>
    <axis xyz="0 0.6 0.8"/>
    {LIMIT}
  </joint>
  <joint name="j1__axis" type="fixed">
    <parent link="base"/>
    <child link="l1__axis"/>
  </joint>
  <joint name="j2" type="prismatic">
    <parent link="l1"/>
    <child link="l2"/>
    <axis xyz="0.48 0.6 0.64"/>
    {LIMIT}
  </joint>
  <joint name="j3" type="revolute">
    <parent link="l2"/>
    <child link="l3"/>
    <origin xyz="0 0.3 0" rpy="0 1.5707963267948966 0"/>
    <axis xyz="1.0000000000000004 2e-16 0"/>
    {LIMIT}
  </joint>
  <joint name="j4" type="continuous">
    <parent link="l3"/>
    <child link="l4"/>
    <origin xyz="0.2 0 0" rpy="0 0 0"/>
    <axis xyz="0.6 0 -0.8"/>
  </joint>
  <joint name="finger_joint" type="revolute">
    <parent link="l1"/>
    <child link="finger"/>
    <origin xyz="0 0.05 0.1" rpy="0 0 0.4"/>
    <axis xyz="-0.8 0 0.6"/>
    {LIMIT}
    <mimic joint="j1" multiplier="0.5" offset="0.1"/>
  </joint>
  <joint name="tool" type="fixed">
    <parent link="l4"/>
    <child link="ee"/>
    <origin xyz="0 0 0.1"/>
  </joint>
</robot>
"""

XRDF = """format: xrdf
format_version: 1.0
modifiers: []
default_joint_positions: {j1: 0.0, j2: 0.0, j3: 0.0, j4: 0.0}
cspace:
  joint_names: [j1, j2, j3]
  acceleration_limits: [10.0, 10.0, 10.0]
  jerk_limits: [1000.0, 1000.0, 1000.0]
tool_frames: [ee]
collision:
  geometry: spheres
self_collision:
  geometry: spheres
  ignore: {l1: [l2, finger], l2: [l3]}
geometry:
  spheres:
    spheres:
      l1: [{center: [0.0, 0.0, 0.0], radius: 0.05}]
      l2: [{center: [0.0, 0.0, 0.0], radius: 0.03}]
      l3: [{center: [0.0, 0.0, 0.0], radius: 0.03}]
      finger: [{center: [0.0, 0.0, 0.0], radius: 0.01}]
"""

ORIGINAL_LINKS = ("base", "l1", "l1__axis", "l2", "l3", "l4", "finger", "ee")


def rewritten(text: str = URDF) -> str:
    robot = parse_robot(text, "tilted.urdf")
    return straighten_axes(text, robot.path, axes_to_rewrite(robot))


def test_which_axes_are_rewritten_and_how() -> None:
    found = {r.joint: r for r in axes_to_rewrite(parse_robot(URDF, "tilted.urdf"))}
    assert list(found) == ["j1", "j2", "j3", "j4", "finger_joint"]
    assert found["j3"].exact == (1.0, 0.0, 0.0)
    assert all(found[j].exact is None for j in ("j1", "j2", "j4", "finger_joint"))
    assert found["j1"].degrees == pytest.approx(math.degrees(math.acos(0.8)))
    scaled = URDF.replace('<axis xyz="0.6 0 -0.8"/>', '<axis xyz="0 0 -2.5"/>')
    assert axes_to_rewrite(parse_robot(scaled, "t.urdf"))[3].exact == (0.0, 0.0, -1.0)


def test_every_moving_joint_gets_an_exact_axis_and_keeps_its_name() -> None:
    robot = parse_robot(rewritten(), "out.urdf")
    for j in robot.joints.values():
        assert not j.is_movable or is_coordinate_axis(j.axis), (j.name, j.axis)
    j1 = robot.joints["j1"]
    assert (j1.type, j1.parent, j1.child, j1.axis) == ("revolute", "base", "l1__axis_2", (0, 0, 1))
    back = robot.joints["j1__axis_2"]  # j1__axis and l1__axis are the robot's own
    assert (back.type, back.parent, back.child) == ("fixed", "l1__axis_2", "l1")
    assert robot.joints["j3"].child == "l3" and robot.joints["j3"].axis == (1.0, 0.0, 0.0)
    finger = robot.joints["finger_joint"]
    assert (finger.mimic_joint, finger.mimic_multiplier, finger.mimic_offset) == ("j1", 0.5, 0.1)
    assert (j1.lower, j1.upper, j1.velocity) == (-1.2, 1.2, 1.0)
    assert set(robot.links) >= set(ORIGINAL_LINKS)


def test_the_rest_of_the_file_is_kept() -> None:
    text = rewritten()
    assert text.startswith('<?xml version="1.0"?>\n<!-- a comment kept -->\n<robot name="tilted">')
    assert '<origin xyz="0.1 0 0.2" rpy="0.3 -0.2 0.5"/>' not in text  # j1's origin turned
    assert '<origin xyz="0.2 0 0" rpy="0 0 0"/>' not in text  # j4's
    assert '<link name="l1"><collision><geometry><box size="0.1 0.1 0.1"/>' in text
    assert '    <child link="l1__axis"/>\n  </joint>' in text  # the robot's own fixed joint


def random_configurations(model, n: int = 25) -> np.ndarray:
    rng = np.random.default_rng(7)
    low = np.where(np.isfinite(model.lower), model.lower, -math.pi)
    high = np.where(np.isfinite(model.upper), model.upper, math.pi)
    return rng.uniform(low, high, size=(n, model.n_actuated))


def test_every_link_has_its_pose_at_every_configuration_by_our_fk() -> None:
    before, _ = build_kinematic_model(parse_robot(URDF, "tilted.urdf"))
    after, _ = build_kinematic_model(parse_robot(rewritten(), "out.urdf"))
    assert after.actuated_joints == before.actuated_joints == ("j1", "j2", "j3", "j4")
    q = random_configurations(before)
    poses = fk(before, q, list(ORIGINAL_LINKS))
    np.testing.assert_allclose(fk(after, q, list(ORIGINAL_LINKS)), poses, atol=1e-12)
    assert np.ptp(poses[:, ORIGINAL_LINKS.index("finger")], axis=0).max() > 0.1  # it moves


def test_every_link_has_its_pose_at_every_configuration_by_yourdfpy(tmp_path: Path) -> None:
    yourdfpy = pytest.importorskip("yourdfpy")
    (tmp_path / "a.urdf").write_text(URDF)
    (tmp_path / "b.urdf").write_text(rewritten())
    before, after = (
        yourdfpy.URDF.load(str(tmp_path / n), load_meshes=False, build_collision_scene_graph=False)
        for n in ("a.urdf", "b.urdf")
    )
    for q in random_configurations(build_kinematic_model(parse_robot(URDF, "t.urdf"))[0], 8):
        cfg = dict(zip(("j1", "j2", "j3", "j4"), map(float, q), strict=True))
        before.update_cfg(cfg)
        after.update_cfg(cfg)
        for link in ORIGINAL_LINKS:
            want = before.get_transform(link, "base")
            np.testing.assert_allclose(after.get_transform(link, "base"), want, atol=1e-12)


def test_rpy_from_matrix_gives_the_matrix_back_also_at_pitch_a_quarter_turn() -> None:
    rng = np.random.default_rng(3)
    for k in range(2000):
        r, p, y = rng.uniform(-math.pi, math.pi, 3)
        if k % 2:
            p = math.copysign(math.pi / 2, p) + rng.normal() * 10.0 ** rng.uniform(-17, -4)
        m = np.array(matrix_from_rpy(r, p, y))
        np.testing.assert_allclose(np.array(matrix_from_rpy(*rpy_from_matrix(m))), m, atol=1e-15)


# --------------------------------------------------------------------------------------------
# the command
# --------------------------------------------------------------------------------------------
@pytest.fixture
def inputs(tmp_path: Path) -> tuple[Path, Path]:
    urdf, xrdf = tmp_path / "tilted.urdf", tmp_path / "tilted.xrdf"
    urdf.write_text(URDF)
    xrdf.write_text(XRDF)
    return urdf, xrdf


def export(runner: CliRunner, xrdf: Path, urdf: Path, *args: str) -> tuple[int, str]:
    r = runner.invoke(app, ["export", "curobo", str(xrdf), "--urdf", str(urdf), *args])
    return r.exit_code, r.output


def test_export_writes_the_urdf_beside_the_config_and_says_so(
    runner: CliRunner, inputs: tuple[Path, Path], tmp_path: Path
) -> None:
    urdf, xrdf = inputs
    out = tmp_path / "cfg" / "tilted.yml"
    out.parent.mkdir()
    code, output = export(runner, xrdf, urdf, "-o", str(out))
    assert code == 0, output
    assert urdf.read_text() == URDF  # the user's file untouched
    written = out.with_suffix(".urdf")
    cfg = yaml.safe_load(out.read_text())["robot_cfg"]["kinematics"]
    assert cfg["urdf_path"] == "tilted.urdf"  # relative to cfg/: the one written there
    assert written.read_text() == rewritten()
    assert cfg["cspace"]["joint_names"] == ["j1", "j2", "j3", "j4"]
    assert "export-joint-axes" in output and str(written) in output
    assert "j1 (36.87° off)" in output and "j3 (x)" in output and "finger_joint" in output
    lint = runner.invoke(app, ["lint", str(xrdf), "--urdf", str(written), "--target", "curobo"])
    assert "curobo-joint-axis" not in lint.output


def test_keep_axes_stops_as_before(
    runner: CliRunner, inputs: tuple[Path, Path], tmp_path: Path
) -> None:
    urdf, xrdf = inputs
    out = tmp_path / "tilted.yml"
    code, output = export(runner, xrdf, urdf, "--keep-axes", "-o", str(out))
    assert code == 1 and "curobo-joint-axis" in output and "nothing written" in output
    assert not out.exists() and not (tmp_path / "tilted.urdf.yml").exists()


def test_no_place_for_the_urdf_is_a_usage_error(
    runner: CliRunner, inputs: tuple[Path, Path]
) -> None:
    urdf, xrdf = inputs
    code, output = export(runner, xrdf, urdf)  # the config to stdout
    assert code == 2 and "5 joint axis(es) cuRobo cannot take" in output, output
    assert "--expanded-urdf" in output


def test_the_urdf_never_replaces_the_input(
    runner: CliRunner, inputs: tuple[Path, Path], tmp_path: Path
) -> None:
    urdf, xrdf = inputs
    code, _ = export(runner, xrdf, urdf, "-o", str(tmp_path / "tilted.yml"))  # → tilted.urdf
    assert code == 2 and urdf.read_text() == URDF
    code, output = export(
        runner,
        xrdf,
        urdf,
        "-o",
        str(tmp_path / "t.yml"),
        "--expanded-urdf",
        str(tmp_path / "s.urdf"),
    )
    assert code == 0, output
    assert (
        yaml.safe_load((tmp_path / "t.yml").read_text())["robot_cfg"]["kinematics"]["urdf_path"]
        == "s.urdf"
    )


def test_a_gazebo_prefix_without_its_declaration_is_kept() -> None:
    text = URDF.replace('<robot name="tilted">', '<robot name="tilted">\n  <x:camera name="c"/>')
    out = rewritten(text)
    assert '<x:camera name="c"/>' in out and '<child link="l1__axis_2"/>' in out


def test_a_xacro_gets_one_urdf_expanded_and_rewritten(
    runner: CliRunner, inputs: tuple[Path, Path], tmp_path: Path
) -> None:
    _, xrdf = inputs
    xacro = tmp_path / "tilted.urdf.xacro"
    xacro.write_text(
        URDF.replace(
            '<robot name="tilted">',
            '<robot xmlns:xacro="http://wiki.ros.org/xacro" '
            'name="tilted">\n  <xacro:property name="z" value="0.8"/>',
        ).replace('<axis xyz="0 0.6 0.8"/>', '<axis xyz="0 0.6 ${z}"/>')
    )
    out = tmp_path / "x.yml"
    code, output = export(runner, xrdf, xacro, "-o", str(out))
    assert code == 0, output
    assert "export-expanded-urdf" in output and "export-joint-axes" in output
    robot = parse_robot((tmp_path / "x.urdf").read_text(), "x.urdf")
    assert robot.joints["j1"].child == "l1__axis_2"


def test_an_axis_too_small_to_turn_onto_stops_before_anything_is_written(
    runner: CliRunner, inputs: tuple[Path, Path], tmp_path: Path
) -> None:
    urdf, xrdf = inputs
    urdf.write_text(URDF.replace("0.48 0.6 0.64", "1e-200 1e-200 0"))
    out = tmp_path / "cfg" / "t.yml"
    out.parent.mkdir()
    code, output = export(runner, xrdf, urdf, "-o", str(out))
    assert code == 2 and "'j2' has a zero or invalid axis" in output, output
    assert list(out.parent.iterdir()) == []


ADDS_L1_AXIS_2 = XRDF.replace(
    "modifiers: []",
    """modifiers:
  - add_frame:
      frame_name: l1__axis_2
      parent_frame_name: l1
      joint_name: j1__axis_2
      joint_type: FIXED
      fixed_transform:
        position: [0.0, 0.0, 0.05]
        orientation: {w: 1.0, xyz: [0.0, 0.0, 0.0]}""",
).replace("tool_frames: [ee]", "tool_frames: [l1__axis_2]")


def test_the_new_links_and_joints_are_named_unlike_the_frames_the_xrdf_adds(
    runner: CliRunner, inputs: tuple[Path, Path], tmp_path: Path
) -> None:
    """cuRobo adds an add_frame to the URDF's links (extra_links): a new link of the same name
    was two frames of one name, which lint of the XRDF against the written URDF refused."""
    urdf, xrdf = inputs
    xrdf.write_text(ADDS_L1_AXIS_2)
    out = tmp_path / "t.yml"
    code, output = export(runner, xrdf, urdf, "-o", str(out))
    assert code == 0, output
    robot = parse_robot(out.with_suffix(".urdf").read_text(), "t.urdf")
    assert robot.joints["j1"].child == "l1__axis_3" and "j1__axis_3" in robot.joints
    assert "l1__axis_2" not in robot.links and "j1__axis_2" not in robot.joints
    lint = runner.invoke(app, ["lint", str(xrdf), "--urdf", str(out.with_suffix(".urdf"))])
    assert lint.exit_code == 0, lint.output


def test_the_urdf_for_curobo_is_never_standard_output_nor_the_config(
    runner: CliRunner, inputs: tuple[Path, Path], tmp_path: Path
) -> None:
    """``--expanded-urdf -`` printed the URDF and wrote urdf_path: "../-"; ``-o t.urdf`` was
    'refusing to overwrite an input file'."""
    urdf, xrdf = inputs
    out = tmp_path / "cfg" / "t.yml"
    out.parent.mkdir()
    code, output = export(runner, xrdf, urdf, "--expanded-urdf", "-", "-o", str(out))
    assert code == 2 and "--expanded-urdf -: urdf_path must name" in output, output
    code, output = export(runner, xrdf, urdf, "-o", str(out.with_suffix(".urdf")))
    assert code == 2 and "is named after the output (t.urdf)" in output, output
    code, output = export(runner, xrdf, urdf, "--expanded-urdf", str(out), "-o", str(out))
    assert code == 2 and "given for both -o and --expanded-urdf" in output, output
    assert list(out.parent.iterdir()) == []
