"""The default SRDF group of an arm whose SRDF also has a chain down to one jaw of its gripper.

The AgileX Piper's MoveIt config has groups ``arm`` (base_link → link6), ``gripper``
(gripper_base → link7) and ``piper`` (base_link → link7): the arm plus one of the two jaws,
``joint7``. Chosen for having the most actuated joints, ``piper`` put a jaw in the c-space
(the other jaw left at 0) and took the jaw's link as the tool frame.
"""

from __future__ import annotations

from pathlib import Path

from xrdf_tools.convert.core import ConvertOptions, convert_files
from xrdf_tools.convert.sources.srdf import choose_group, load_srdf
from xrdf_tools.robot.core import as_robot
from xrdf_tools.robot.urdf_source import load_urdf

_LIMIT = '<limit lower="-1" upper="1" effort="1" velocity="1"/>'
_JAW = '<limit lower="0" upper="0.035" effort="1" velocity="1"/>'


def _piper_like(tmp_path: Path) -> tuple[Path, Path]:
    """Six revolute joints, a fixed gripper base and two prismatic jaws (no mimic), with the
    Piper's three SRDF groups: ``piper`` (arm and one jaw) listed first."""
    links = ['<link name="base_link"/>']
    joints = []
    parent = "base_link"
    for i in range(1, 7):
        links.append(f'<link name="link{i}"/>')
        joints.append(
            f'<joint name="joint{i}" type="revolute"><parent link="{parent}"/>'
            f'<child link="link{i}"/><origin xyz="0 0 0.1"/><axis xyz="0 0 1"/>{_LIMIT}</joint>'
        )
        parent = f"link{i}"
    links += ['<link name="gripper_base"/>', '<link name="link7"/>', '<link name="link8"/>']
    joints.append(
        '<joint name="joint6_to_gripper_base" type="fixed"><parent link="link6"/>'
        '<child link="gripper_base"/></joint>'
    )
    for jaw, axis in (("7", "1"), ("8", "-1")):
        joints.append(
            f'<joint name="joint{jaw}" type="prismatic"><parent link="gripper_base"/>'
            f'<child link="link{jaw}"/><axis xyz="0 {axis} 0"/>{_JAW}</joint>'
        )
    urdf = tmp_path / "piper.urdf"
    urdf.write_text(f'<robot name="piper">{"".join(links + joints)}</robot>')
    srdf = tmp_path / "piper.srdf"
    srdf.write_text(
        '<robot name="piper">'
        '<group name="piper"><chain base_link="base_link" tip_link="link7"/></group>'
        '<group name="arm"><chain base_link="base_link" tip_link="link6"/></group>'
        '<group name="gripper"><chain base_link="gripper_base" tip_link="link7"/></group>'
        "</robot>"
    )
    return urdf, srdf


def test_the_arm_group_wins_over_the_arm_and_one_jaw(tmp_path: Path) -> None:
    urdf, srdf = _piper_like(tmp_path)
    group, why = choose_group(load_srdf(srdf), as_robot(load_urdf(urdf)).tree)
    assert group == "arm"
    assert "passed over, the same arm joints and a gripper's: piper (+joint7)" in why


def test_convert_plans_the_arm_to_its_last_link_not_a_jaw(tmp_path: Path) -> None:
    urdf, srdf = _piper_like(tmp_path)
    x, _, _ = convert_files(urdf, ConvertOptions(srdf=srdf))
    assert x.cspace is not None
    assert x.cspace.joint_names == tuple(f"joint{i}" for i in range(1, 7))
    assert x.tool_frames == ("link6",)


def test_a_group_of_the_arm_and_both_jaws_alone_is_still_chosen(tmp_path: Path) -> None:
    """Without an arm-only group nothing is passed over: the only group is planned."""
    urdf, srdf = _piper_like(tmp_path)
    srdf.write_text(
        '<robot name="piper"><group name="piper"><chain base_link="base_link" '
        'tip_link="link7"/></group></robot>'
    )
    group, why = choose_group(load_srdf(srdf), as_robot(load_urdf(urdf)).tree)
    assert group == "piper" and "passed over" not in why
