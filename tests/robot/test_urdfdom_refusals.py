"""What ROS's URDF parser (urdfdom) refuses is read anyway, with a located warning.

urdfdom refuses a robot whose revolute or prismatic joint has no ``<limit>``, whose ``<limit>``
lacks ``effort`` or ``velocity``, whose ``<safety_controller>`` lacks ``k_velocity`` or whose
``<dynamics>`` has neither ``damping`` nor ``friction`` (checked against pinocchio's urdfdom by
``benchmarks/check_urdf_srdf_readers.py``). Every command reads such a robot as yourdfpy and
cuRobo do, and says once per kind, at the first joint, that ROS would stop there.
"""

from __future__ import annotations

from pathlib import Path

from typer.testing import CliRunner

from tests.cli_checks import run_cli
from tests.robots import robot_urdf
from xrdf_tools.robot.urdf_source import parse_robot, read_robot
from xrdf_tools.robot.urdfdom_refusals import RULE_ROS_REFUSES

RULE = RULE_ROS_REFUSES

REFUSED = """<robot name="r">
  <link name="a"/><link name="b"/><link name="c"/><link name="d"/><link name="e"/>
  <joint name="j1" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/>
  </joint>
  <joint name="j2" type="prismatic"><parent link="b"/><child link="c"/>
    <limit lower="0" upper="0.1" effort="5"/>
  </joint>
  <joint name="j3" type="revolute"><parent link="c"/><child link="d"/>
    <limit lower="-1" upper="1" effort="5" velocity="1"/>
    <safety_controller soft_lower_limit="-0.9" soft_upper_limit="0.9"/>
    <dynamics/>
  </joint>
  <joint name="j4" type="prismatic"><parent link="d"/><child link="e"/></joint>
</robot>
"""


def _refusals(text: str) -> list[tuple[int | None, str]]:
    robot = parse_robot(text, "r.urdf")
    return [(w.line, w.message) for w in robot.warnings if w.rule == RULE]


def test_each_kind_is_said_once_at_its_first_joint_naming_the_joints() -> None:
    said = _refusals(REFUSED)
    assert [(line, m.split(":")[0]) for line, m in said] == [
        (3, "revolute joint without <limit> (joint j1)"),
        (6, "<limit> without 'velocity' (joint j2)"),
        (10, "<safety_controller> without 'k_velocity' (joint j3)"),
        (11, "<dynamics> with neither 'damping' nor 'friction' (joint j3)"),
        (13, "prismatic joint without <limit> (joint j4)"),
    ]
    assert all("ROS's URDF parser (urdfdom" in m for _, m in said)
    assert "read here as position limits [0, 0]" in said[0][1]
    assert said[1][1].endswith("read here as no velocity limit")


def test_several_joints_of_one_kind_are_one_warning() -> None:
    text = REFUSED.replace('effort="5" velocity="1"', 'effort="5"')
    said = [m for _, m in _refusals(text) if m.startswith("<limit> without 'velocity'")]
    assert len(said) == 1 and said[0].startswith("<limit> without 'velocity' (joints j2, j3)")


def test_what_urdfdom_reads_is_not_said() -> None:
    """A continuous or fixed joint needs no <limit>; a <limit> needs no lower or upper; a
    <dynamics> with only friction and a <safety_controller> with k_velocity are complete."""
    text = (
        '<robot name="r"><link name="a"/><link name="b"/><link name="c"/>'
        '<joint name="j1" type="continuous"><parent link="a"/><child link="b"/>'
        '<dynamics friction="0.1"/><safety_controller k_velocity="1"/></joint>'
        '<joint name="j2" type="revolute"><parent link="b"/><child link="c"/>'
        '<limit effort="1" velocity="1"/></joint></robot>'
    )
    assert _refusals(text) == []


def test_real_robots_that_ros_loads_are_not_warned() -> None:
    for name in ("panda", "pr2", "talos"):
        assert [w for w in read_robot(robot_urdf(name)).warnings if w.rule == RULE] == []


def test_every_command_reads_the_robot_and_says_where(runner: CliRunner, tmp_path: Path) -> None:
    urdf = tmp_path / "r.urdf"
    urdf.write_text(REFUSED)
    code, out = run_cli(runner, "inspect", str(urdf))
    assert code == 0, out
    assert f"{urdf}:3: warning {RULE} revolute joint without <limit> (joint j1)" in out
    assert "4 joints (2 revolute, 2 prismatic)" in out


def test_expand_says_ros_would_refuse_its_urdf(runner: CliRunner, tmp_path: Path) -> None:
    """A joint a macro writes has no line in the xacro file: the warning names the file only."""
    xacro = tmp_path / "m.urdf.xacro"
    xacro.write_text(
        '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:macro name="j" params="n p c">\n'
        '    <joint name="${n}" type="revolute"><parent link="${p}"/><child link="${c}"/>'
        "</joint>\n  </xacro:macro>\n"
        '  <link name="a"/><link name="b"/>\n  <xacro:j n="j1" p="a" c="b"/>\n</robot>\n'
    )
    code, out = run_cli(runner, "expand", str(xacro), "-o", str(tmp_path / "m.urdf"))
    assert code == 0, out
    assert f"{xacro}: warning {RULE} revolute joint without <limit> (joint j1)" in out
    assert (tmp_path / "m.urdf").is_file()
