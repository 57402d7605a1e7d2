"""MoveIt joint_limits.yaml as MoveIt 2 configs ship it: a ROS 2 parameter file whose joint names
carry a launch substitution for the prefix."""

from __future__ import annotations

from pathlib import Path

from typer.testing import CliRunner

from xrdf_tools.cli import app
from xrdf_tools.xrdf.io import load_xrdf

_ARM = """<?xml version="1.0"?>
<robot name="arm" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:arg name="tf_prefix" default=""/>
  <xacro:property name="p" value="$(arg tf_prefix)"/>
  <link name="${p}base"/>
  <link name="${p}l1"/>
  <link name="${p}l2"/>
  <joint name="${p}j1" type="revolute"><parent link="${p}base"/><child link="${p}l1"/>
    <axis xyz="0 0 1"/><limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
  <joint name="${p}j2" type="revolute"><parent link="${p}l1"/><child link="${p}l2"/>
    <origin xyz="0 0 0.3"/><axis xyz="0 1 0"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
</robot>
"""

#: The layout of a ROS 2 MoveIt config's joint_limits.yaml (Annin AR4's, shortened).
_ROS2_LIMITS = """/**/move_group:
  ros__parameters:
    robot_description_planning:
      joint_limits:
        $(var tf_prefix)j1:
          has_acceleration_limits: true
          max_acceleration: 0.5
          has_jerk_limits: true
          max_jerk: 40
        $(var tf_prefix)j2:
          has_acceleration_limits: true
          max_acceleration: -0.75
      cartesian_limits:
        max_trans_vel: 0.05
"""


def _convert(runner: CliRunner, tmp_path: Path, *args: str) -> tuple[str, Path]:
    arm = tmp_path / "arm.urdf.xacro"
    arm.write_text(_ARM)
    limits = tmp_path / "joint_limits.yaml"
    limits.write_text(_ROS2_LIMITS)
    out = tmp_path / "arm.xrdf"
    r = runner.invoke(
        app,
        ["convert", str(arm), "--joint-limits", str(limits), "-o", str(out), *args],
    )
    assert r.exit_code == 0, r.output
    return r.stderr, out


def test_a_ros2_parameter_file_gives_the_limits_with_the_prefix_empty(
    runner: CliRunner, tmp_path: Path
) -> None:
    err, out = _convert(runner, tmp_path)
    cspace = load_xrdf(out).cspace
    assert cspace.joint_names == ("j1", "j2")
    assert cspace.acceleration_limits == (0.5, 0.75)
    assert cspace.jerk_limits[0] == 40.0
    limits = tmp_path / "joint_limits.yaml"
    assert (
        f"{limits}:4:7: info convert-ros-parameters a ROS 2 parameter file: joint limits read "
        "from /**/move_group.ros__parameters.robot_description_planning.joint_limits"
    ) in err
    assert (
        f"{limits}:5:9: info convert-launch-substitution $(var tf_prefix) in joint names taken "
        "as '' (no --xacro-arg tf_prefix:=VALUE given)"
    ) in err
    assert f"{limits}:13:7: warning convert-dropped-key 'cartesian_limits'" in err
    assert "convert-unknown-joint" not in err and "convert-default-acceleration" not in err


def test_the_prefix_takes_the_xacro_argument(runner: CliRunner, tmp_path: Path) -> None:
    err, out = _convert(runner, tmp_path, "--xacro-arg", "tf_prefix:=left_")
    cspace = load_xrdf(out).cspace
    assert cspace.joint_names == ("left_j1", "left_j2")
    assert cspace.acceleration_limits == (0.5, 0.75)
    assert "convert-launch-substitution" not in err and "convert-unknown-joint" not in err


_SRDF = """<robot name="arm">
  <group name="arm"><joint name="j1"/><joint name="j2"/></group>
</robot>
"""

#: A MoveIt 1 joint_limits.yaml that halves j1's velocity and narrows j2's range (Baxter's
#: halves every arm joint's), rounds j2's velocity (Fetch's 1.57 for 1.571), and limits a
#: finger outside the c-space alike.
_TIGHTER = """joint_limits:
  j1:
    has_velocity_limits: true
    max_velocity: 0.5
    has_acceleration_limits: true
    max_acceleration: 2
  j2:
    has_velocity_limits: true
    max_velocity: 0.995
    has_position_limits: true
    min_position: -1.0
    max_position: 2
  finger:
    has_velocity_limits: true
    max_velocity: 0.01
"""


def test_velocity_and_position_limits_tighter_than_the_urdf_are_reported_as_lost(
    runner: CliRunner, tmp_path: Path
) -> None:
    """An XRDF carries only acceleration and jerk: a tighter MoveIt velocity or range of a
    c-space joint is one located warning naming each value (a looser or rounded one, or one of
    a joint outside the c-space, is not)."""
    arm = tmp_path / "arm.urdf"
    arm.write_text(
        _ARM.replace("${p}", "").replace(
            "</robot>",
            '<link name="f"/><joint name="finger" type="prismatic"><parent link="l2"/>'
            '<child link="f"/><limit lower="0" upper="0.04" effort="1" velocity="0.1"/>'
            "</joint></robot>",
        )
    )
    srdf = tmp_path / "arm.srdf"
    srdf.write_text(_SRDF)
    limits = tmp_path / "joint_limits.yaml"
    limits.write_text(_TIGHTER)
    out = tmp_path / "arm.xrdf"
    args = ["convert", str(arm), "--srdf", str(srdf), "--joint-limits", str(limits)]
    r = runner.invoke(app, [*args, "-o", str(out)])
    assert r.exit_code == 0, r.output
    assert load_xrdf(out).cspace.acceleration_limits == (2.0, 10.0)
    lost = [line for line in r.stderr.splitlines() if "convert-limit-not-carried" in line]
    assert lost == [
        f"{limits}:2:3: warning convert-limit-not-carried MoveIt limits tighter than the URDF's "
        "are lost for 2 c-space joint(s): j1: max_velocity 0.5 (URDF 1); j2: min_position -1 "
        "(URDF -2). An XRDF holds no velocity or position limits and its readers take the "
        "URDF's, so the planner may move these joints faster or farther than MoveIt does; to "
        "keep them, set them in the URDF's <limit>"
    ]
    limits.write_text(_TIGHTER.replace("has_position_limits: true", "has_position_limits: false"))
    r = runner.invoke(app, [*args, "-o", str(out), "--group", "arm"])
    lost = [line for line in r.stderr.splitlines() if "convert-limit-not-carried" in line]
    assert len(lost) == 1 and "1 c-space joint(s): j1: max_velocity 0.5 (URDF 1)." in lost[0]


def test_joints_the_urdf_lacks_are_one_warning(runner: CliRunner, tmp_path: Path) -> None:
    """REEM-C's joint_limits.yaml limits 14 finger joints its URDF lacks: a warning each made
    fourteen lines; now one at the first entry names them all (one alone gets a did-you-mean)."""
    arm = tmp_path / "arm.urdf"
    arm.write_text(_ARM.replace("${p}", ""))
    limits = tmp_path / "joint_limits.yaml"
    fingers = "".join(f"  finger_{i}:\n    max_acceleration: 1.0\n" for i in range(3))
    limits.write_text(f"joint_limits:\n  j1:\n    max_acceleration: 2.0\n{fingers}")
    r = runner.invoke(app, ["convert", str(arm), "--joint-limits", str(limits)])
    assert r.exit_code == 0, r.output
    unknown = [ln for ln in r.stderr.splitlines() if "convert-unknown-joint" in ln]
    assert unknown == [
        f"{limits}:4:3: warning convert-unknown-joint joint_limits names 3 joints the URDF does "
        "not have (finger_0, finger_1, finger_2); ignored"
    ]
    limits.write_text("joint_limits:\n  j11:\n    max_acceleration: 2.0\n")
    r = runner.invoke(app, ["convert", str(arm), "--joint-limits", str(limits)])
    assert (
        f"{limits}:2:3: warning convert-unknown-joint joint_limits names 'j11', which is not a "
        "joint of the URDF; did you mean 'j1'?; ignored"
    ) in r.stderr


def test_a_templates_joint_names_say_the_file_is_a_template(
    runner: CliRunner, tmp_path: Path
) -> None:
    """Clearpath's kinova_gen3_7dof/joint_limits.yaml names '${name}_joint_1': a template its
    generator fills in. The one warning about the unknown joints says so and what to give."""
    arm = tmp_path / "arm.urdf"
    arm.write_text(_ARM.replace("${p}", "arm_0_"))
    limits = tmp_path / "joint_limits.yaml"
    limits.write_text(
        "joint_limits:\n"
        "  ${name}_j1:\n    max_acceleration: 1.0\n"
        "  ${name}_j2:\n    max_acceleration: 1.0\n"
    )
    r = runner.invoke(app, ["convert", str(arm), "--joint-limits", str(limits)])
    assert r.exit_code == 0, r.output
    (unknown,) = [ln for ln in r.stderr.splitlines() if "convert-unknown-joint" in ln]
    assert unknown.startswith(f"{limits}:2:3: warning convert-unknown-joint joint_limits names 2")
    assert unknown.endswith(
        "; ignored: ${name} in a joint name is a template's expression that a generator or "
        "xacro fills in: give the file it writes"
    )
    assert "convert-default-acceleration" in r.stderr  # nothing was taken from it


def test_a_one_arm_file_given_for_two_prefixed_arms_says_so(
    runner: CliRunner, tmp_path: Path
) -> None:
    """xArm's dual-arm URDF names its joints L_joint1 … and R_joint1 …; the Lite 6's own
    joint_limits.yaml (joint1 …) given for it was 'joints the URDF does not have; ignored',
    which did not say why nor what to give."""
    body = "".join(
        _ARM.split("\n", 4)[4].replace("</robot>\n", "").replace("${p}", side)
        + f'<joint name="{side}mount" type="fixed"><parent link="world"/>'
        f'<child link="{side}base"/></joint>'
        for side in ("L_", "R_")
    )
    dual = tmp_path / "dual.urdf"
    dual.write_text(f'<robot name="dual"><link name="world"/>{body}</robot>')
    limits = tmp_path / "joint_limits.yaml"
    limits.write_text(
        "joint_limits:\n  j1:\n    max_acceleration: 1.0\n  j2:\n    max_acceleration: 1.0\n"
    )
    r = runner.invoke(app, ["convert", str(dual), "--joint-limits", str(limits)])
    assert r.exit_code == 0, r.output
    (unknown,) = [ln for ln in r.stderr.splitlines() if "convert-unknown-joint" in ln]
    assert unknown.endswith(
        "names 2 joints the URDF does not have (j1, j2); ignored (the URDF has each of them "
        "prefixed with 'L_', 'R_': a file for the robot without those prefixes; give one "
        "naming this URDF's joints)"
    ), unknown


def test_limits_the_file_turns_off_are_said_at_the_file(tmp_path: Path) -> None:
    """MoveIt Setup Assistant writes `has_acceleration_limits: false` for every joint: the
    default acceleration is then said at the joint limits file, naming the joints it turns
    off, not as if no file had been given."""
    from tests.paths import UR10E_URDF
    from xrdf_tools.convert.core import ConvertOptions, convert_files

    limits = tmp_path / "joint_limits.yaml"
    limits.write_text(
        "joint_limits:\n"
        "  shoulder_pan_joint:\n"
        "    has_acceleration_limits: false\n"
        "    max_acceleration: 0\n"
        "  elbow_joint:\n"
        "    has_acceleration_limits: true\n"
        "    max_acceleration: 5\n"
    )
    x, diags, _ = convert_files(
        UR10E_URDF, ConvertOptions(joint_limits=limits, chains=(("base_link", "tool0"),))
    )
    (d,) = [d for d in diags if d.rule == "convert-default-acceleration"]
    assert (d.path, d.line) == (str(limits), 2), d
    assert "turns it off (has_acceleration_limits: false) for shoulder_pan_joint" in d.message
    assert "elbow_joint" not in d.message.split("for ")[1].split(":")[0]
    assert x.cspace is not None
    accel = dict(zip(x.cspace.joint_names, x.cspace.acceleration_limits, strict=True))
    assert accel["elbow_joint"] == 5.0 and accel["shoulder_pan_joint"] == 10.0
    # a joint the file does not mention is still just "no limit in the inputs"
    (jerk,) = [d for d in diags if d.rule == "convert-default-jerk"]
    assert jerk.line is None and "turns it off" not in jerk.message


def test_a_quoted_switch_is_said_at_its_line_and_read_as_absent(tmp_path: Path) -> None:
    """`has_acceleration_limits: "false"` is a string, which MoveIt does not read as a switch:
    said at its line and read as absent (the limit then follows its value, as without the
    key); a negative value under it is no longer taken by its absolute value."""
    from tests.paths import UR10E_URDF
    from xrdf_tools.convert.core import ConvertOptions, convert_files

    limits = tmp_path / "joint_limits.yaml"
    limits.write_text(
        "joint_limits:\n"
        "  shoulder_pan_joint:\n"
        '    has_acceleration_limits: "false"\n'
        "    max_acceleration: -3\n"
        "  elbow_joint:\n"
        "    has_jerk_limits: 'true'\n"
        "    max_jerk: 500\n"
    )
    x, diags, _ = convert_files(
        UR10E_URDF, ConvertOptions(joint_limits=limits, chains=(("base_link", "tool0"),))
    )
    said = [d for d in diags if "not true or false" in d.message]
    assert [(d.path, d.line, d.rule) for d in said] == [
        (str(limits), 3, "convert-dropped-key"),
        (str(limits), 6, "convert-dropped-key"),
    ]
    assert "has_acceleration_limits is 'false'" in said[0].message
    assert x.cspace is not None
    names = x.cspace.joint_names
    accel = dict(zip(names, x.cspace.acceleration_limits, strict=True))
    jerk = dict(zip(names, x.cspace.jerk_limits or (), strict=True))
    assert accel["shoulder_pan_joint"] == 10.0  # -3 with no switch: no limit, the default
    assert jerk["elbow_joint"] == 500.0  # > 0 with no switch: taken (MoveIt 1's reading)


def test_a_plain_yes_or_off_switch_is_the_boolean_moveit_reads(tmp_path: Path) -> None:
    """MoveIt reads joint_limits.yaml with YAML 1.1 readers (ROS 1's rosparam and MoveIt 2's
    launch helpers: PyYAML; a ROS 2 parameter file: rcl's parser): a plain `off` is false and
    `yes` true there. They were said to be no switch and read as absent, so `off` kept a
    limit MoveIt turns off and `yes` dropped the switch over a negative value."""
    from tests.paths import UR10E_URDF
    from xrdf_tools.convert.core import ConvertOptions, convert_files

    limits = tmp_path / "joint_limits.yaml"
    limits.write_text(
        "joint_limits:\n"
        "  shoulder_pan_joint:\n"
        "    has_acceleration_limits: Off\n"
        "    max_acceleration: 3\n"
        "  elbow_joint:\n"
        "    has_acceleration_limits: yes\n"
        "    max_acceleration: -4\n"
        "  wrist_1_joint:\n"
        "    has_acceleration_limits: 'on'\n"
        "    max_acceleration: 6\n"
    )
    x, diags, _ = convert_files(
        UR10E_URDF, ConvertOptions(joint_limits=limits, chains=(("base_link", "tool0"),))
    )
    said = [d for d in diags if "not true or false" in d.message]
    assert [d.line for d in said] == [9]  # only the quoted 'on' is a string to MoveIt
    assert x.cspace is not None
    accel = dict(zip(x.cspace.joint_names, x.cspace.acceleration_limits, strict=True))
    assert accel["shoulder_pan_joint"] == 10.0  # turned off: the default
    assert accel["elbow_joint"] == 4.0  # switched on: abs(max_acceleration)
    assert accel["wrist_1_joint"] == 6.0  # no switch, a value > 0: taken
