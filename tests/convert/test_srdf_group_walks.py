"""SRDF subgroups: thousands nested, diamonds and cycles, walked once each."""

from __future__ import annotations

import time

import pytest

from tests.paths import UR10E_URDF
from xrdf_tools.convert.sources import RobotTree
from xrdf_tools.robot.core import as_robot
from xrdf_tools.util.errors import SourceError


def _nested_groups(n: int, close_cycle: bool = False) -> str:
    groups = [f'<group name="g{i}"><group name="g{i + 1}"/></group>' for i in range(n)]
    last = '<group name="g0"/>' if close_cycle else '<joint name="shoulder_pan_joint"/>'
    groups.append(f'<group name="g{n}">{last}</group>')
    return f'<robot name="ur10e">{"".join(groups)}</robot>'


def _tree() -> RobotTree:
    from xrdf_tools.robot.urdf_source import load_urdf

    return as_robot(load_urdf(UR10E_URDF)).tree


def test_1200_nested_srdf_subgroups() -> None:
    from xrdf_tools.convert.sources.srdf import group_joints, parse_srdf

    srdf = parse_srdf(_nested_groups(1200), "deep.srdf")
    assert group_joints(srdf, "g0", _tree()) == ["shoulder_pan_joint"]


def test_srdf_subgroup_cycle_is_an_error() -> None:
    from xrdf_tools.convert.sources.srdf import group_joints, parse_srdf

    srdf = parse_srdf(_nested_groups(5, close_cycle=True), "loop.srdf")
    with pytest.raises(SourceError, match=r"groups include each other: g0 -> g1 .* -> g0"):
        group_joints(srdf, "g0", _tree())


def test_srdf_diamond_of_subgroups_is_linear() -> None:
    from xrdf_tools.convert.sources.srdf import group_joints, parse_srdf

    n = 40  # each group includes the next two: 2**40 paths, 40 groups
    groups = [
        f'<group name="g{i}"><group name="g{i + 1}"/><group name="g{i + 2}"/></group>'
        for i in range(n)
    ]
    groups += [
        f'<group name="g{n}"><joint name="elbow_joint"/></group>',
        f'<group name="g{n + 1}"/>',
    ]
    srdf = parse_srdf(f'<robot name="r">{"".join(groups)}</robot>', "diamond.srdf")
    start = time.monotonic()
    assert group_joints(srdf, "g0", _tree()) == ["elbow_joint"]
    assert time.monotonic() - start < 2


def test_choosing_among_thousands_of_nested_groups_is_linear() -> None:
    from xrdf_tools.convert.sources.srdf import choose_group, parse_srdf

    srdf = parse_srdf(_nested_groups(5000), "deep.srdf")
    start = time.monotonic()
    group, _ = choose_group(srdf, _tree())
    assert group is not None and time.monotonic() - start < 5
    looped = parse_srdf(_nested_groups(50, close_cycle=True), "loop.srdf")
    assert choose_group(looped, _tree()) == (None, "the SRDF has no group with movable joints")
