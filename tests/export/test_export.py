"""XRDF → cuRobo YAML / SRDF, the round trip back through convert, and the convert CLI contract."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
import yaml
from typer.testing import CliRunner

from tests.curobo_loader import from_config, from_xrdf
from tests.paths import FIXTURES, UR10E_URDF, UR10E_XRDF
from xrdf_tools.cli import app
from xrdf_tools.convert.core import ConvertOptions, convert_files
from xrdf_tools.convert.sources import RobotTree
from xrdf_tools.convert.sources.srdf import parse_srdf
from xrdf_tools.diff import diff_xrdf
from xrdf_tools.export.curobo import to_curobo, to_srdf
from xrdf_tools.robot.core import as_robot
from xrdf_tools.robot.urdf_source import load_urdf
from xrdf_tools.xrdf.io import dump_xrdf, load_xrdf, parse_xrdf

PANDA_XRDF = FIXTURES / "panda" / "panda.xrdf"


def _tree() -> RobotTree:
    return as_robot(load_urdf(UR10E_URDF)).tree


@pytest.mark.parametrize("layout", ["2.0", "classic"])
@pytest.mark.parametrize(
    "source", [UR10E_XRDF, FIXTURES / "curobo_classic" / "ur10e_classic.yml"], ids=["xrdf", "yml"]
)
def test_round_trip_xrdf_export_convert(layout: str, source: Path, tmp_path: Path) -> None:
    if source.suffix == ".xrdf":
        original = load_xrdf(source)
    else:
        original, _, _ = convert_files(UR10E_URDF, ConvertOptions(curobo=source))
    text, diags = to_curobo(original, _tree(), layout=layout, urdf_path=UR10E_URDF)
    assert diags == []
    cfg = tmp_path / "robot.yml"
    cfg.write_text(text)
    back, _, _ = convert_files(
        UR10E_URDF, ConvertOptions(curobo=cfg, format_version=original.format_version)
    )
    result = diff_xrdf(original, back)
    assert result.is_equal, [c.message for c in result.changes]


def test_curobo_yaml_is_what_curobos_loader_accepts() -> None:
    x, _, _ = convert_files(
        UR10E_URDF, ConvertOptions(curobo=FIXTURES / "curobo_classic" / "ur10e_inline.yml")
    )
    text, _ = to_curobo(x, _tree(), layout="classic")
    kin = yaml.safe_load(text)["robot_cfg"]["kinematics"]
    assert kin["ee_link"] == "tool0" and kin["link_names"] == ["tool0"]
    cs = kin["cspace"]
    # locked joints listed in joint_names and lock_joints; every number a float
    assert cs["joint_names"][-1] == "wrist_3_joint" and kin["lock_joints"] == {"wrist_3_joint": 0.5}
    for key in ("retract_config", "max_acceleration", "max_jerk"):
        assert all(type(v) is float for v in cs[key]), key
        assert len(cs[key]) == len(cs["joint_names"])
    assert cs["retract_config"][0] == 0.1  # looked up by name, in joint_names order
    for link, spheres in kin["collision_spheres"].items():
        for s in spheres:
            assert type(s["radius"]) is float and all(type(c) is float for c in s["center"]), link
    assert all(type(v) is float for v in kin["collision_sphere_buffer"].values())
    assert list(kin["collision_spheres"]) == sorted(kin["collision_spheres"])  # by name


def test_added_frames_export_fixed_and_w_first() -> None:
    x = load_xrdf(PANDA_XRDF)
    tree = as_robot(load_urdf(_panda_urdf())).tree
    text, _ = to_curobo(x, tree)
    kin = yaml.safe_load(text)["robot_cfg"]["kinematics"]
    for name, link in (kin["extra_links"] or {}).items():
        assert link["joint_type"] == "FIXED"
        assert len(link["fixed_transform"]) == 7, name
    assert kin["format_version"] == 2.0 and "tool_frames" in kin


def _panda_urdf() -> Path:
    from tests.robots import robot_urdf

    return robot_urdf("panda")


def test_srdf_export_new_and_merged() -> None:
    x, _, _ = convert_files(
        UR10E_URDF, ConvertOptions(curobo=FIXTURES / "curobo_classic" / "ur10e_classic.yml")
    )
    assert x.self_collision is not None
    added = {m.frame_name for m in x.added_frames()}
    assert added == {"gripper_center"}  # cuRobo extra_links: no URDF link, not for MoveIt
    pairs = {p for p in x.self_collision.ignore_pairs() if not p & added}
    assert pairs != x.self_collision.ignore_pairs()
    fresh = parse_srdf(to_srdf(x, "ur10e"))
    assert fresh.robot_name == "ur10e"
    assert {frozenset((a, b)) for a, b, _, _ in fresh.disable_collisions} == pairs
    assert {r for _, _, r, _ in fresh.disable_collisions} == {"User"}
    existing = """<?xml version="1.0"?>
<robot name="ur10e">
  <group name="arm"><chain base_link="base_link" tip_link="tool0"/></group>
  <!-- kept -->
  <disable_collisions link1="forearm_link" link2="upper_arm_link" reason="Adjacent"/>
</robot>
"""
    merged_text = to_srdf(x, "ignored", existing)
    merged = parse_srdf(merged_text)
    assert "arm" in merged.groups and "<!-- kept -->" in merged_text
    reasons = {frozenset((a, b)): r for a, b, r, _ in merged.disable_collisions}
    assert set(reasons) == pairs
    assert reasons[frozenset(("upper_arm_link", "forearm_link"))] == "Adjacent"  # not repeated
    assert len(merged.disable_collisions) == len(pairs)


def test_export_cli(runner: CliRunner, tmp_path: Path) -> None:
    out = tmp_path / "ur10e.yml"
    r = runner.invoke(
        app, ["export", "curobo", str(UR10E_XRDF), "--urdf", str(UR10E_URDF), "-o", str(out)]
    )
    assert r.exit_code == 0, r.output
    assert yaml.safe_load(out.read_text())["robot_cfg"]["kinematics"]["tool_frames"] == ["tool0"]
    r = runner.invoke(app, ["export", "srdf", str(UR10E_XRDF)])
    assert r.exit_code == 0 and 'reason="User"' in r.output
    r = runner.invoke(app, ["export", "srdf", str(UR10E_XRDF), "-o", str(UR10E_XRDF)])
    assert r.exit_code == 2 and "refusing to overwrite" in r.output
    r = runner.invoke(app, ["export", "curobo", str(UR10E_XRDF), "--urdf", "/nope.urdf"])
    assert r.exit_code == 2 and "Traceback" not in r.output


# --- the convert command's contract ------------------------------------------------------------

CLASSIC = FIXTURES / "curobo_classic" / "ur10e_classic.yml"


def test_convert_cli_stdout_output_check_strict(runner: CliRunner, tmp_path: Path) -> None:
    base = ["convert", str(UR10E_URDF), "--curobo", str(CLASSIC)]
    r = runner.invoke(app, base)
    assert r.exit_code == 0
    assert "convert-dropped-key" in r.stderr and "convert-dropped-key" not in r.stdout
    x = parse_xrdf(r.stdout)
    assert dump_xrdf(x) == r.stdout  # canonical
    out = tmp_path / "ur10e.xrdf"
    assert runner.invoke(app, [*base, "-o", str(out)]).exit_code == 0
    assert out.read_text() == r.stdout
    # --check: equal → 0; after a change → 1 with the semantic diff
    assert runner.invoke(app, [*base, "-o", str(out), "--check"]).exit_code == 0
    out.write_text(out.read_text().replace("jerk_limits: [500.0", "jerk_limits: [501.0"))
    r = runner.invoke(app, [*base, "-o", str(out), "--check"])
    assert r.exit_code == 1 and "jerk" in r.stdout and "out of date" in r.stderr
    # re-running writes the file anew: a user who edited it by hand is told the edit goes
    assert "replaces any edit made to the file by hand" in " ".join(r.stderr.split())
    # the two sides: the committed file and what the sources give now (was '<document>')
    assert r.stdout.startswith(
        f"--- {out} (XRDF 1.0)\n+++ (converted from the sources now) (XRDF 1.0)\n"
    )
    missing = runner.invoke(app, [*base, "-o", str(tmp_path / "nope.xrdf"), "--check"])
    assert missing.exit_code == 1 and "does not exist" in missing.stderr
    # --strict: the dropped keys are a failure, nothing is written
    strict_out = tmp_path / "strict.xrdf"
    r = runner.invoke(app, [*base, "--strict", "-o", str(strict_out)])
    assert r.exit_code == 1 and "--strict" in r.stderr and not strict_out.exists()
    # refusing to overwrite an input
    r = runner.invoke(app, [*base, "-o", str(CLASSIC)])
    assert r.exit_code == 2 and "refusing to overwrite" in r.stderr
    # 1.0 output
    r = runner.invoke(app, [*base, "--format-version", "1.0"])
    assert r.exit_code == 0 and parse_xrdf(r.stdout).format_version == "1.0"
    assert runner.invoke(app, [*base, "--format-version", "3.0"]).exit_code == 2


def test_convert_cli_input_errors(runner: CliRunner, tmp_path: Path) -> None:
    bad = tmp_path / "bad.srdf"
    bad.write_text("<robot><group name='x'>")
    r = runner.invoke(app, ["convert", str(UR10E_URDF), "--srdf", str(bad)])
    assert r.exit_code == 2 and "malformed SRDF XML" in r.stderr and "Traceback" not in r.output
    r = runner.invoke(
        app, ["convert", str(UR10E_URDF), "--srdf", str(bad), "--curobo", str(CLASSIC)]
    )
    assert r.exit_code == 2 and "not both" in r.stderr
    srdf = tmp_path / "ok.srdf"
    srdf.write_text('<robot name="r"><group name="arm"><joint name="elbow_joint"/></group></robot>')
    r = runner.invoke(app, ["convert", str(UR10E_URDF), "--srdf", str(srdf), "--group", "amr"])
    assert r.exit_code == 2 and "did you mean 'arm'" in r.stderr
    r = runner.invoke(
        app, ["convert", str(UR10E_URDF), "--srdf", str(srdf), "--tool-frame", "tool1"]
    )
    assert r.exit_code == 2 and "did you mean 'tool0'" in r.stderr


def test_joint_limits_yaml(tmp_path: Path) -> None:
    limits = tmp_path / "joint_limits.yaml"
    limits.write_text(
        """default_velocity_scaling_factor: 0.1
joint_limits:
  shoulder_pan_joint: {has_acceleration_limits: true, max_acceleration: -5, has_jerk_limits: true,
                       max_jerk: 300}
  shoulder_lift_joint: {has_acceleration_limits: false, max_acceleration: 7.0}
  elbow_joint: {max_acceleration: 2.5, max_jerk: 0}
  wrist_1_joint: {has_acceleration_limits: true, max_acceleration: 0}
  not_a_joint: {has_acceleration_limits: true, max_acceleration: 1.0}
"""
    )
    x, diags, _ = convert_files(UR10E_URDF, ConvertOptions(joint_limits=limits, acceleration=9.0))
    assert x.cspace is not None
    acc = dict(zip(x.cspace.joint_names, x.cspace.acceleration_limits, strict=True))
    jerk = dict(zip(x.cspace.joint_names, x.cspace.jerk_limits, strict=True))
    assert acc["shoulder_pan_joint"] == 5.0  # abs of the MoveIt 2 value
    assert acc["shoulder_lift_joint"] == 9.0  # has_* false → absent → --acceleration
    assert acc["elbow_joint"] == 2.5  # MoveIt 1 style: present and > 0
    assert acc["wrist_1_joint"] == 9.0  # 0 = absent
    assert jerk["shoulder_pan_joint"] == 300.0 and jerk["elbow_joint"] == 1000.0
    rules = {d.rule for d in diags}
    assert {
        "convert-unknown-joint",
        "convert-default-acceleration",
        "convert-default-jerk",
    } <= rules


@pytest.mark.slow
def test_round_trip_panda_without_set_base_frame(tmp_path: Path) -> None:
    """The Panda fixture has no set_base_frame; cuRobo always names a base_link, which comes
    back as set_base_frame on the URDF root: a no-op that diff, told the root, ignores. cuRobo
    configs do not name geometry groups, so the group name is the only other change."""
    from tests.robots import robot_urdf
    from xrdf_tools.robot.urdf_source import root_link

    urdf_path = robot_urdf("panda")
    urdf = load_urdf(urdf_path)
    original = load_xrdf(PANDA_XRDF)
    text, diags = to_curobo(original, as_robot(urdf).tree, layout="2.0", urdf_path=urdf_path)
    assert diags == []
    cfg = tmp_path / "panda.yml"
    cfg.write_text(text)
    back, _, _ = convert_files(urdf_path, ConvertOptions(curobo=cfg, format_version="2.0"))
    result = diff_xrdf(original, back, root_frame=root_link(urdf))
    assert result.major_changes == (), [c.message for c in result.major_changes]
    assert {c.kind for c in result.minor_changes} <= {"group-renamed"}, [
        c.message for c in result.minor_changes
    ]


_GRIPPER_URDF = """<robot name="arm_with_gripper">
  <link name="base"/><link name="upper"/><link name="hand"/><link name="left"/><link name="right"/>
  <link name="tool"/>
  <joint name="shoulder" type="revolute"><parent link="base"/><child link="upper"/>
    <axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="wrist" type="revolute"><parent link="upper"/><child link="hand"/>
    <origin xyz="0 0 0.3"/><axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="1" velocity="1"/>
  </joint>
  <joint name="finger" type="prismatic"><parent link="hand"/><child link="left"/>
    <axis xyz="0 1 0"/><limit lower="0" upper="0.04" effort="1" velocity="0.1"/></joint>
  <joint name="finger_mirror" type="prismatic"><parent link="hand"/><child link="right"/>
    <axis xyz="0 -1 0"/><mimic joint="finger"/>
    <limit lower="0" upper="0.04" effort="1" velocity="0.1"/></joint>
  <joint name="tool_joint" type="fixed"><parent link="hand"/><child link="tool"/></joint>
</robot>
"""

_GRIPPER_XRDF = """format: xrdf
format_version: 1.0
default_joint_positions: {shoulder: 0.5, wrist: 0.25}
cspace:
  joint_names: [shoulder]
  acceleration_limits: [10.0]
  jerk_limits: [500.0]
tool_frames: [tool]
collision:
  geometry: g
self_collision:
  geometry: g
  ignore: {}
geometry:
  g:
    spheres:
      left:
        - {center: [0.0, 0.0, 0.0], radius: 0.01}
      upper:
        - {center: [0.0, 0.0, 0.1], radius: 0.05}
"""


def test_curobo_export_locks_every_actuated_joint_outside_the_cspace(tmp_path: Path) -> None:
    """cuRobo's XRDF reader holds a finger outside the c-space at 0.0 when it has no default;
    its config loader raises on a joint of the robot it builds that is neither active nor
    locked, so the export lists it in lock_joints (the mimic follows its leader, not locked)."""
    urdf = tmp_path / "robot.urdf"
    urdf.write_text(_GRIPPER_URDF)
    x = parse_xrdf(_GRIPPER_XRDF, "robot.xrdf")
    text, diags = to_curobo(x, as_robot(load_urdf(urdf)).tree, urdf_path=urdf)
    assert diags == []
    kin = yaml.safe_load(text)["robot_cfg"]["kinematics"]
    assert kin["lock_joints"] == {"wrist": 0.25, "finger": 0.0}
    cs = kin["cspace"]
    assert cs["joint_names"] == ["shoulder", "wrist", "finger"]
    assert cs["default_joint_position"] == [0.5, 0.25, 0.0]
    assert len(cs["max_acceleration"]) == len(cs["max_jerk"]) == 3
    cfg = tmp_path / "robot.yml"
    cfg.write_text(text)
    assert from_config(cfg, urdf) == from_xrdf(_GRIPPER_XRDF, urdf)


_TWO_LINK_URDF = """<robot name="two_link">
  <link name="base"/><link name="link0"/><link name="link1"/><link name="tip"/>
  <joint name="joint0" type="revolute"><parent link="base"/><child link="link0"/>
    <axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="joint1" type="revolute"><parent link="link0"/><child link="link1"/>
    <origin xyz="1 0 0"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/>
  </joint>
  <joint name="tip_joint" type="fixed"><parent link="link1"/><child link="tip"/>
    <origin xyz="1 0 0"/></joint>
</robot>
"""


def _two_link_xrdf(section: str) -> str:
    return (
        "format: xrdf\nformat_version: 2.0\n"
        "default_joint_positions: {joint0: 0.0, joint1: 0.0}\n"
        "cspace: {joint_names: [joint0, joint1], acceleration_limits: [10.0, 10.0], "
        "jerk_limits: [100.0, 100.0]}\n"
        f"tool_frames: [tip]\n{section}:\n  geometry: g\n"
        "geometry:\n  g:\n    spheres:\n"
        "      base: [{center: [0.0, 0.0, 0.0], radius: 0.1}]\n"
        "      link0: [{center: [1.0, 0.0, 0.0], radius: 0.1}]\n"
        "      link1: [{center: [0.0, 0.0, 0.0], radius: 0.1}]\n"
    )


def test_curobo_export_of_world_collision_only_checks_no_pair(tmp_path: Path) -> None:
    """cuMotion's two_link_arm.xrdf has world_collision and no self_collision: its spheres are
    never checked against each other, and link0's last sphere sits on link1's first. cuRobo
    checks every pair its config does not ignore, so the export ignores every pair (it wrote
    self_collision_ignore: {}, and cuRobo saw the arm in self-collision everywhere); cuRobo's
    loader then finds no pair to check and raises, which the export says."""
    urdf = tmp_path / "two_link.urdf"
    urdf.write_text(_TWO_LINK_URDF)
    tree = as_robot(load_urdf(urdf)).tree
    x = parse_xrdf(_two_link_xrdf("world_collision"), "two_link.xrdf")
    text, diags = to_curobo(x, tree, urdf_path=urdf)
    kin = yaml.safe_load(text)["robot_cfg"]["kinematics"]
    ignored = {frozenset((a, b)) for a, bs in kin["self_collision_ignore"].items() for b in bs}
    frames = kin["collision_link_names"]
    assert frames == ["base", "link0", "link1"]
    assert ignored == {frozenset((a, b)) for a in frames for b in frames if a != b}
    # and cuRobo's loader raises when no pair is left to check: an error (the command writes
    # nothing), at the world section, with what to do
    assert [(d.rule, d.severity.value, d.line) for d in diags] == [
        ("export-no-self-collision", "info", None),
        ("export-no-pair", "error", 6),
    ]
    assert "ZeroDivisionError" in diags[1].message and "self_collision" in diags[1].message

    self_only = parse_xrdf(_two_link_xrdf("self_collision"), "two_link.xrdf")
    text, diags = to_curobo(self_only, tree, urdf_path=urdf)
    kin = yaml.safe_load(text)["robot_cfg"]["kinematics"]
    assert kin["self_collision_ignore"] == {} and len(kin["collision_spheres"]) == 3
    assert [d.rule for d in diags] == ["export-self-only"]


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (
            lambda t: t + "modifiers:\n  - set_base_frame: nope\n",
            "set_base_frame: frame 'nope' is not a frame of",
        ),
        (
            lambda t: t.replace("    - joint3\n", "    - finger_joint\n"),
            "c-space joint 'finger_joint' is a mimic joint",
        ),
        (
            lambda t: t.replace("    - joint3\n", "    - tool_joint\n"),
            "c-space joint 'tool_joint' is",
        ),
    ],
    ids=["unknown-base", "mimic-in-cspace", "fixed-in-cspace"],
)
def test_curobo_export_refuses_what_no_command_can_pose(
    runner: CliRunner, tmp_path: Path, edit: Any, message: str
) -> None:
    """An XRDF that report and viz refuse against its URDF (a modifier that cannot be applied,
    a c-space joint that is no coordinate) is not exported as a cuRobo config cuRobo cannot
    load: exit 2 at the XRDF's line, nothing written."""
    from tests.cli_checks import MIMIC_URDF, MIMIC_XRDF

    xrdf = tmp_path / "r.xrdf"
    xrdf.write_text(edit(MIMIC_XRDF.read_text()))
    out = tmp_path / "robot.yml"
    r = runner.invoke(
        app, ["export", "curobo", str(xrdf), "--urdf", str(MIMIC_URDF), "-o", str(out)]
    )
    assert r.exit_code == 2 and message in r.output and f"{xrdf}:" in r.output, r.output
    assert not out.exists()
    report = runner.invoke(app, ["report", str(xrdf), "--urdf", str(MIMIC_URDF), "-n", "8"])
    assert report.exit_code == 2, report.output


@pytest.mark.parametrize("what", ["curobo", "srdf"])
def test_export_says_the_urdfs_warnings_in_its_format(
    runner: CliRunner, tmp_path: Path, what: str
) -> None:
    """A defect in a part no command uses (a material colour of five numbers) is a located
    warning in every command that reads --urdf; export loaded the URDF with its own loader and
    said nothing. It is said now, and in the --format asked for."""
    import json

    text = UR10E_URDF.read_text()
    at = text.index('<link name="shoulder_link">')
    odd = '<material name="odd"><color rgba="1 0 0 1 1"/></material>\n'
    urdf = tmp_path / "ur10e.urdf"
    urdf.write_text(text[:at] + odd + text[at:])
    line = text[:at].count("\n") + 1
    out = tmp_path / f"out.{what}"
    args = ["export", what, str(UR10E_XRDF), "--urdf", str(urdf), "-o", str(out)]
    r = runner.invoke(app, args)
    assert r.exit_code == 0 and out.exists(), r.output
    assert f"{urdf}:{line}: warning urdf-color-ignored" in r.stderr, r.stderr
    r = runner.invoke(app, [*args, "-f", "json"])
    found = json.loads(r.stderr)["diagnostics"]
    assert [(d["rule"], d["line"]) for d in found if d["path"] == str(urdf)] == [
        ("urdf-color-ignored", line)
    ]


def test_a_locked_joint_whose_limits_exclude_zero_is_held_inside_them(tmp_path: Path) -> None:
    """Spot's knees (limits [-2.79, -0.25]) outside an arm's c-space: an absent default is 0
    clamped to the limits for the XRDF (and for the mask computed in that pose), but cuRobo's
    XRDF reader locks a joint without a default at 0.0, outside them. convert writes the
    clamped value as the joint's default and says so; export curobo locks a joint the XRDF
    gives no default at the clamped value, so cuRobo plans in the pose that was checked."""
    urdf = tmp_path / "robot.urdf"
    urdf.write_text(_GRIPPER_URDF.replace('lower="0" upper="0.04"', 'lower="0.01" upper="0.04"'))
    robot = as_robot(load_urdf(urdf))
    text, diags = to_curobo(parse_xrdf(_GRIPPER_XRDF, "robot.xrdf"), robot.tree, urdf_path=urdf)
    assert diags == []
    kin = yaml.safe_load(text)["robot_cfg"]["kinematics"]
    assert kin["lock_joints"] == {"wrist": 0.25, "finger": 0.01}
    assert kin["cspace"]["default_joint_position"] == [0.5, 0.25, 0.01]

    x, diags, _ = convert_files(urdf, ConvertOptions(joints=("shoulder", "wrist")))
    assert dict(x.default_joint_positions or {}) == {"shoulder": 0.0, "wrist": 0.0, "finger": 0.01}
    (note,) = [d for d in diags if d.rule == "convert-locked-default"]
    assert "finger = 0.01" in note.message and note.severity.name == "INFO"
    text, _ = to_curobo(x, robot.tree, urdf_path=urdf)
    assert yaml.safe_load(text)["robot_cfg"]["kinematics"]["lock_joints"] == {"finger": 0.01}


def test_a_joint_outside_the_c_space_with_reversed_limits_gets_no_default(tmp_path: Path) -> None:
    """No position fits a joint whose lower limit is above its upper (the URDF check warns):
    writing 0 clamped to its limits as its default made the XRDF's own lint refuse it, so
    `xrdf convert` of a robot with such a joint outside the c-space wrote nothing (exit 1)."""
    for limits in ('lower="0.04" upper="0.01"', 'upper="-0.01"'):
        urdf = tmp_path / "robot.urdf"
        urdf.write_text(_GRIPPER_URDF.replace('lower="0" upper="0.04"', limits, 1))
        out = tmp_path / "robot.xrdf"
        args = ["convert", str(urdf), "--joints", "shoulder,wrist", "-o", str(out)]
        r = CliRunner().invoke(app, args)
        assert r.exit_code == 0 and out.exists(), r.output
        written = yaml.safe_load(out.read_text())["default_joint_positions"]
        assert written == {"shoulder": 0.0, "wrist": 0.0}
        assert "convert-locked-default" not in r.stderr
