"""URDF joint graphs that loop (a link the child of two joints, joint cycles, mimic chains
and loops): refused with their path, walked in linear time, never a hang."""

from __future__ import annotations

import time
from pathlib import Path

import pytest
from typer.testing import CliRunner

from tests.cli_checks import run_cli
from xrdf_tools.convert.sources import RobotTree
from xrdf_tools.util.errors import UrdfError

CYCLE_URDF = """<robot name="r">
  <link name="base"/><link name="a"/><link name="b"/>
  <joint name="j0" type="fixed"><parent link="base"/><child link="a"/></joint>
  <joint name="j1" type="fixed"><parent link="a"/><child link="b"/></joint>
  <joint name="j2" type="fixed"><parent link="b"/><child link="a"/></joint>
</robot>
"""


CHAIN_SRDF = (
    '<robot name="r"><group name="arm"><chain base_link="base" tip_link="b"/></group></robot>'
)


def test_joint_whose_parent_is_its_own_child_with_srdf_chain_does_not_hang(
    runner: CliRunner,
    tmp_path: Path,
) -> None:
    urdf = tmp_path / "cyc.urdf"
    urdf.write_text(CYCLE_URDF)
    srdf = tmp_path / "cyc.srdf"
    srdf.write_text(CHAIN_SRDF)
    start = time.monotonic()
    code, out = run_cli(runner, "convert", str(urdf), "--srdf", str(srdf))
    assert code == 2 and "is the child of two joints" in out and f"{urdf}:5" in out
    assert time.monotonic() - start < 10


def test_a_loop_of_joints_is_refused_with_its_path(tmp_path: Path) -> None:
    from xrdf_tools.robot.urdf_source import parse_urdf_string

    text = CYCLE_URDF.replace(
        '<child link="a"/></joint>\n  <joint name="j1"',
        '<child link="c"/></joint>\n  <joint name="j1"',
    ).replace('<link name="b"/>', '<link name="b"/><link name="c"/>')
    with pytest.raises(
        UrdfError, match=r"the joints form a cycle \(b -> a -> b, through joints j2 -> j1\)"
    ):
        parse_urdf_string(text, "loop.urdf")
    self_loop = CYCLE_URDF.replace(
        '<parent link="b"/><child link="a"/>', '<parent link="b"/><child link="b"/>'
    )
    with pytest.raises(UrdfError, match="as both parent and child"):
        parse_urdf_string(self_loop, "self.urdf")


def test_robot_tree_walks_terminate_on_a_hand_made_cycle() -> None:
    from xrdf_tools.robot.urdf_source import JointInfo

    eye = [[1.0, 0, 0, 0], [0, 1.0, 0, 0], [0, 0, 1.0, 0], [0, 0, 0, 1.0]]
    joints = {
        "j0": JointInfo("j0", "fixed", "base", "a", eye),
        "j1": JointInfo("j1", "fixed", "a", "b", eye),
        "j2": JointInfo("j2", "fixed", "b", "a", eye),
    }
    tree = RobotTree(
        "r",
        "r.urdf",
        ("base", "a", "b"),
        joints,
        "base",
        {"a": "j2", "b": "j1"},
        {"base": ("j0",), "a": ("j1",), "b": ("j2",)},
    )
    with pytest.raises(UrdfError, match="cycle"):
        tree.ancestors("a")
    assert tree.dfs_joints() == ["j0", "j1", "j2"]
    assert sorted(tree.descendants("base")) == ["a", "b"]


def _mimic_chain_urdf(n: int, loop: bool = False) -> str:
    links = "".join(f'<link name="l{i}"/>' for i in range(n + 1))
    joints = []
    for i in range(n):
        mimic = f'<mimic joint="j{i + 1}"/>' if i < n - 1 else ""
        if loop and i == n - 1:
            mimic = '<mimic joint="j0"/>'
        joints.append(
            f'<joint name="j{i}" type="revolute"><parent link="l{i}"/><child link="l{i + 1}"/>'
            f'<limit lower="-1" upper="1" effort="1" velocity="1"/>{mimic}</joint>'
        )
    return f'<robot name="chain">{links}{"".join(joints)}</robot>'


def test_a_long_mimic_chain_resolves_in_linear_time() -> None:
    from xrdf_tools.robot.kinematics import _resolve_mimic
    from xrdf_tools.robot.urdf_source import joints_of, parse_urdf_string

    joints = joints_of(parse_urdf_string(_mimic_chain_urdf(3000), "chain.urdf"))
    memo: dict[str, tuple[str | None, float, float, str]] = {}
    start = time.monotonic()
    for j in joints.values():
        if j.is_mimic:
            master, m, o, _ = _resolve_mimic(j, joints, joints, {}, UrdfError, memo)
            assert (master, m, o) == ("j2999", 1.0, 0.0)
    assert time.monotonic() - start < 2


def test_mimic_loop_is_an_error() -> None:
    from xrdf_tools.robot.kinematics import build_kinematic_model
    from xrdf_tools.robot.urdf_source import parse_urdf_string
    from xrdf_tools.xrdf.io import parse_xrdf

    urdf = parse_urdf_string(_mimic_chain_urdf(4, loop=True), "loop.urdf")
    x = parse_xrdf("format: xrdf\nformat_version: 2.0\n", "x.xrdf")
    with pytest.raises(UrdfError, match="mimic joints form a loop"):
        build_kinematic_model(urdf, x)
