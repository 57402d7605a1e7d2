"""An SRDF read as MoveIt (srdfdom) and pinocchio read it, where they agree on odd input.

``benchmarks/check_urdf_srdf_readers.py`` compares ``convert --srdf`` with pinocchio's SRDF
reader on the real robots of example-robot-data; these tests pin the odd inputs it found.
"""

from __future__ import annotations

from pathlib import Path

from xrdf_tools.convert.core import ConvertOptions, convert
from xrdf_tools.robot.urdf_source import parse_robot

URDF = """<robot name="t">
  <link name="base"/><link name="l1"/><link name="tip"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
  <joint name="j2" type="continuous"><parent link="l1"/><child link="tip"/><axis xyz="0 0 1"/>
  </joint>
</robot>
"""


def _srdf(tmp_path: Path, state: str) -> Path:
    srdf = tmp_path / "t.srdf"
    srdf.write_text(
        '<robot name="t"><group name="arm"><chain base_link="base" tip_link="tip"/></group>'
        f'<group_state name="home" group="arm">{state}</group_state></robot>'
    )
    return srdf


def test_a_state_value_of_several_numbers_for_a_one_variable_joint_is_dropped(
    tmp_path: Path,
) -> None:
    """MoveIt uses a group_state value only when it has one number per variable of the joint
    (srdfdom reads every number; the joint model logs "requires 1 variable values" and skips
    it) and pinocchio leaves such a joint at its neutral value: ``value="1.5 0.3"`` on a
    revolute joint is no default position of 1.5, as the first number was read."""
    srdf = _srdf(tmp_path, '<joint name="j1" value="1.5 0.3"/><joint name="j2" value="4 "/>')
    tree = parse_robot(URDF, str(tmp_path / "t.urdf"))
    x, diags = convert(tree, ConvertOptions(srdf=srdf, groups=("arm",)))
    assert x.default_joint_positions is not None
    assert "j1" not in x.default_joint_positions or x.default_joint_positions["j1"] != 1.5
    assert x.default_joint_positions["j2"] == 4.0  # one number, spaces around it: read
    said = [d for d in diags if d.rule == "convert-dropped-joint-value"]
    assert [d.message for d in said] == [
        "group_state 'home' gives 'j1' several numbers; a revolute joint takes one, so MoveIt "
        "and pinocchio ignore the value; dropped"
    ]
    assert said[0].line == 1
