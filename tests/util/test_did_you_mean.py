"""The 'did you mean' of a name the robot lacks: a name close to it, not one that only shares
an ending every joint of the robot has."""

from __future__ import annotations

from pathlib import Path

from typer.testing import CliRunner

from xrdf_tools.cli import app
from xrdf_tools.util.errors import did_you_mean


def test_a_shared_ending_alone_suggests_nothing() -> None:
    assert did_you_mean("gripper_joint", ["base_joint", "L1"]) == ""
    assert did_you_mean("grippr_joint", ["base_joint", "gripper_joint"]) == (
        "; did you mean 'gripper_joint'?"
    )
    assert did_you_mean("arm_8_joint", ["arm_7_joint"]) == "; did you mean 'arm_7_joint'?"
    assert did_you_mean("wrist_3_lnk", ["wrist_3_link"]) == "; did you mean 'wrist_3_link'?"
    assert did_you_mean("shoulder_pan", ["shoulder_pan_joint"]) == (
        "; did you mean 'shoulder_pan_joint'?"
    )


def test_a_prefix_written_the_other_way_round_is_matched_before_another_arm() -> None:
    """Mobile ALOHA's community SRDF names its left rear arm rl_ where the URDF says lr_:
    'rl_base_link' was offered 'rr_base_link', a link of the other rear arm (one letter
    changed), so following the hint would disable pairs of the wrong arm."""
    links = ["fl_base_link", "fr_base_link", "lr_base_link", "rr_base_link", "rr_link1"]
    assert did_you_mean("rl_base_link", links) == "; did you mean 'lr_base_link'?"
    assert did_you_mean("rl_link1", ["rr_link1", "lr_link1"]) == "; did you mean 'lr_link1'?"
    # the same letters moved further than a swap are not preferred: the closest name wins
    assert did_you_mean("arm_l_link", ["l_arm_link", "arm_r_link"]) == (
        "; did you mean 'arm_r_link'?"
    )


def test_a_name_written_out_is_matched_to_its_abbreviation() -> None:
    """Talos' SRDF names its arms l_arm and r_arm: --group left_arm was offered 'all_arms'
    (its '_arm' ending is shared, and 'left' and 'l' have one letter in common)."""
    talos_groups = ["all_arms", "arms", "l_arm", "r_arm", "l_gripper", "r_gripper"]
    assert did_you_mean("left_arm", talos_groups) == "; did you mean 'l_arm'?"
    assert did_you_mean("right_arm", talos_groups) == "; did you mean 'r_arm'?"
    assert did_you_mean("gripper_joint", ["base_joint"]) == ""


def test_an_srdf_group_of_a_gripper_the_urdf_lacks_is_not_matched_to_the_base(
    runner: CliRunner, tmp_path: Path
) -> None:
    # a PAROL6 export (joints L1.., a fixed base_joint) with a MoveIt config for its gripper
    urdf = tmp_path / "r.urdf"
    urdf.write_text(
        '<robot name="r"><link name="world"/><link name="base"/><link name="l1"/>'
        '<joint name="base_joint" type="fixed"><parent link="world"/><child link="base"/></joint>'
        '<joint name="L1" type="revolute"><parent link="base"/><child link="l1"/>'
        '<axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>'
    )
    srdf = tmp_path / "r.srdf"
    srdf.write_text(
        '<robot name="r"><group name="arm"><joint name="L1"/></group>'
        '<group name="gripper"><joint name="gripper_joint"/></group></robot>'
    )
    r = runner.invoke(app, ["convert", str(urdf), "--srdf", str(srdf), "-o", str(tmp_path / "o")])
    assert r.exit_code == 0, r.output
    (line,) = [t for t in r.output.splitlines() if "convert-srdf-unused-group" in t]
    assert "unknown joint 'gripper_joint'" in line and "base_joint" not in line
