"""Patterns of cuRobo configs and Lula robot descriptions found in public repositories (an
xArm Lite6 and an xArm6 in forks of cuRobo, a Husky + UR5 + Robotiq Lula description, a Dexmate
Vega config written by cuRobo v2): each reproduced in a few lines."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.paths import FIXTURES, UR10E_URDF
from xrdf_tools.convert.core import ConvertOptions, convert_files
from xrdf_tools.diagnostics import Diagnostic, Severity
from xrdf_tools.util.errors import SourceError
from xrdf_tools.xrdf.model import Xrdf

MIMIC_URDF = FIXTURES / "urdf" / "three_link_mimic.urdf"


def _convert(urdf: Path, config: Path) -> tuple[Xrdf, list[Diagnostic]]:
    x, diags, _ = convert_files(urdf, ConvertOptions(curobo=config))
    return x, diags


def _write(tmp_path: Path, text: str, name: str = "robot.yml") -> Path:
    p = tmp_path / name
    p.write_text(text)
    return p


# A Lula description fixes the gripper's mimic joints too (Husky + UR5 + Robotiq 2F-85:
# left_inner_knuckle_joint follows finger_joint), as Isaac Sim's editor lists every joint.
LULA_MIMIC = """api_version: 1.0
cspace: [joint1, joint2, joint3]
default_q: [0.0, 0.0, 0.0]
cspace_to_urdf_rules:
  - {name: finger_joint, rule: fixed, value: 0.0002}
  - {name: tool_joint, rule: fixed, value: 0.0}
  - {name: fnger_joint, rule: fixed, value: 0.0}
  - {name: joint3, rule: fixed, default: 0.01}
  - {name: joint2, rule: extract}
"""


def test_lula_rules_on_mimic_fixed_and_unknown_joints_say_what_the_joint_is(
    tmp_path: Path,
) -> None:
    _, diags = _convert(MIMIC_URDF, _write(tmp_path, LULA_MIMIC, "desc.yaml"))
    by_line = {d.line: d for d in diags if d.path.endswith("desc.yaml")}
    mimic = by_line[5]
    assert mimic.rule == "convert-dropped-joint-value" and mimic.severity is Severity.INFO
    assert "a mimic joint (it follows 'joint1')" in mimic.message
    assert "did you mean" not in mimic.message  # it said: did you mean 'finger_joint'?
    fixed = by_line[6]
    assert fixed.rule == "convert-dropped-joint-value" and "a fixed joint" in fixed.message
    unknown = by_line[7]
    assert unknown.rule == "convert-unknown-joint"
    assert "not a joint of the URDF; did you mean 'finger_joint'?" in unknown.message


def test_lula_rules_that_give_no_position_are_said_not_skipped(tmp_path: Path) -> None:
    # `default:` instead of `value:` (a tutorial's description) and a rule of another kind
    # were skipped without a word: the joint silently kept no position
    _, diags = _convert(MIMIC_URDF, _write(tmp_path, LULA_MIMIC, "desc.yaml"))
    by_line = {d.line: d for d in diags if d.path.endswith("desc.yaml")}
    assert by_line[8].rule == "convert-dropped-key"
    assert "without a numeric 'value'" in by_line[8].message
    assert by_line[9].rule == "convert-dropped-key" and "'extract' rule" in by_line[9].message


# An xArm6 config in a fork of cuRobo names the links where the joints belong.
LINKS_AS_JOINTS = """robot_cfg:
  kinematics:
    base_link: base_link
    ee_link: tool0
    cspace:
      joint_names: [shoulder_link, upper_arm_link, forearm_link, wrist_1_link, wrist_2_link,
        wrist_3_link]
      retract_config: [0.0, 0.0, 0.9, 0.0, 0.9, 0.0]
"""


def test_link_names_in_joint_names_are_said_with_the_joints_that_move_them(
    tmp_path: Path,
) -> None:
    with pytest.raises(SourceError) as e:
        _convert(UR10E_URDF, _write(tmp_path, LINKS_AS_JOINTS))
    assert e.value.line == 6
    message = e.value.message
    assert "lists links of ur10e.urdf (shoulder_link, upper_arm_link, forearm_link" in message
    assert "name the joints that move them (shoulder_pan_joint, shoulder_lift_joint" in message
    assert "different robots" not in message


# A config cuRobo v2 writes back (Dexmate Vega) carries every setting at its default; a Lite6
# config in a fork of cuRobo has a cspace.joint_limits block no cuRobo version reads.
SETTINGS = """kinematics:
  format_version: 2.0
  base_link: base_link
  tool_frames: [tool0]
  add_object_link: false
  grasp_contact_link_names: null
  load_tool_frames_with_mesh: false
  num_envs: 1
  root_link: base_link
  cspace:
    joint_names: [shoulder_pan_joint, shoulder_lift_joint, elbow_joint, wrist_1_joint,
      wrist_2_joint, wrist_3_joint]
    default_joint_position: [0.0, -1.57, 1.57, -1.57, -1.57, 0.0]
    velocity_scale: [0.5, 1.0, 1.0, 1.0, 1.0, 1.0]
    acceleration_scale: 1.0
    jerk_scale: [1.0, 1.0, 1.0, 1.0, 1.0, 1.0]
    position_limit_clip: 0.0
    null_space_maximum_distance: null
    joint_limits:
      jerk: [100.0, 100.0, 100.0, 100.0, 100.0, 100.0]
"""


def test_settings_at_curobo_defaults_are_not_said_and_unknown_keys_stop_curobo(
    tmp_path: Path,
) -> None:
    _, diags = _convert(UR10E_URDF, _write(tmp_path, SETTINGS))
    dropped = {d.line: d.message for d in diags if d.rule == "convert-dropped-key"}
    # nothing said of the settings at the value cuRobo takes without them (lines 5-8, 15-18)
    assert set(dropped) == {9, 14, 19}, dropped
    assert "'root_link' is not a cuRobo kinematics setting" in dropped[9]
    assert "cuRobo's loader stops on it" in dropped[9]
    # a velocity scale of 0.5 for one joint is a real setting: dropped, said
    assert "cspace.velocity_scale has no XRDF equivalent" in dropped[14]
    assert "cspace.joint_limits is not a cuRobo cspace setting" in dropped[19]


def test_empty_lula_keys_are_not_called_dropped(tmp_path: Path) -> None:
    # Isaac Sim writes `composite_task_spaces: []` into every description: nothing is lost
    text = LULA_MIMIC.replace("cspace_to_urdf_rules:", "composite_task_spaces: []\nextra: 1\nx:")
    _, diags = _convert(MIMIC_URDF, _write(tmp_path, text, "desc.yaml"))
    dropped = [d.message for d in diags if d.rule == "convert-dropped-key"]
    assert any("'extra'" in m for m in dropped)
    assert not any("composite_task_spaces" in m for m in dropped)


def test_load_collision_spheres_false_is_said_to_turn_collision_off(tmp_path: Path) -> None:
    """`load_collision_spheres: false` makes cuRobo load no sphere of the config (no collision
    checking at all); the XRDF keeps them, and the warning says what that changes."""
    cfg = tmp_path / "ur.yml"
    cfg.write_text(
        "robot_cfg:\n  kinematics:\n    base_link: base_link\n    ee_link: tool0\n"
        "    load_collision_spheres: false\n"
        "    collision_link_names: [forearm_link]\n"
        "    collision_spheres:\n      forearm_link:\n        - center: [0, 0, 0.1]\n"
        "          radius: 0.05\n"
        "    cspace:\n      joint_names: [shoulder_pan_joint]\n"
    )
    x, diags, _ = convert_files(UR10E_URDF, ConvertOptions(curobo=cfg))
    (said,) = [d for d in diags if "load_collision_spheres" in d.message]
    assert said.rule == "convert-dropped-key" and (said.path, said.line) == (str(cfg), 5)
    assert "checks no collision" in said.message
    assert x.world_collision_spheres()["forearm_link"]


def test_keys_that_are_not_names_are_said_as_the_file_writes_them(tmp_path: Path) -> None:
    """A key `null`, `true` or `5` is no cuRobo setting: said as written, not as Python's
    `None` or `True`."""
    cfg = tmp_path / "ur.yml"
    cfg.write_text(
        "robot_cfg:\n  kinematics:\n    base_link: base_link\n    ee_link: tool0\n"
        "    null: 1\n    true: 2\n    5: 3\n"
        "    cspace:\n      joint_names: [shoulder_pan_joint]\n      ~: [1]\n"
    )
    _, diags, _ = convert_files(UR10E_URDF, ConvertOptions(curobo=cfg))
    dropped = {d.line: d.message for d in diags if d.rule == "convert-dropped-key"}
    assert dropped[5].startswith("'null' is not a cuRobo kinematics setting"), dropped
    assert dropped[6].startswith("'true' is not a cuRobo kinematics setting")
    assert dropped[7].startswith("'5' is not a cuRobo kinematics setting")
    assert dropped[10].startswith("cspace.null is not a cuRobo cspace setting")


def test_a_link_among_the_joint_names_is_said_to_be_a_link(tmp_path: Path) -> None:
    """`joint_names` mixing a link with joints: the link was said to be 'not in the URDF',
    which it is (as a link); now the message says so and names the joint that moves it."""
    text = LINKS_AS_JOINTS.replace(
        "[shoulder_link, upper_arm_link, forearm_link, wrist_1_link, wrist_2_link,\n"
        "        wrist_3_link]",
        "[shoulder_pan_joint, upper_arm_link, base_link]",
    ).replace("[0.0, 0.0, 0.9, 0.0, 0.9, 0.0]", "[0.0, 0.0, 0.0]")
    text = text.replace("    cspace:", "    lock_joints: {forearm_link: 0.5}\n    cspace:")
    _, diags = _convert(UR10E_URDF, _write(tmp_path, text))
    said = {d.message for d in diags if d.rule == "convert-unknown-joint"}
    assert said == {
        "c-space joint 'upper_arm_link' is a link of the URDF, not a joint (the joint that "
        "moves it is 'shoulder_lift_joint'); dropped",
        "c-space joint 'base_link' is a link of the URDF, not a joint (no joint moves it); dropped",
        "locked joint 'forearm_link' is a link of the URDF, not a joint (the joint that moves "
        "it is 'elbow_joint'); dropped",
    }, said
