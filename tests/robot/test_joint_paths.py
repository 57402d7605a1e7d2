"""KinematicModel.joints_on_path / joint_paths (all frame pairs at once) against the walk that
defines them: the actuated joints of the frames below the two frames' common ancestor, a mimic
joint counted as its master, on robots with mimic joints on one branch and across branches."""

from __future__ import annotations

import random
from itertools import combinations

import pytest

from tests.many_frames import tree_robot
from tests.robots import robot_urdf
from xrdf_tools.robot.kinematics import KinematicModel, build_kinematic_model
from xrdf_tools.robot.urdf_source import load_urdf, parse_urdf_string


def _walked(kin: KinematicModel, a: int, b: int) -> int:
    """The joints between frames ``a`` and ``b`` as a bit mask, by walking up from both."""
    up_a, up_b = kin.ancestors(a), kin.ancestors(b)
    moving = set(up_a) ^ set(up_b)
    return sum({1 << int(kin.q_index[f]) for f in moving if int(kin.q_index[f]) >= 0})


def _check_every_pair(kin: KinematicModel) -> None:
    pairs = list(combinations(range(kin.n_frames), 2))
    a, b = [p[0] for p in pairs], [p[1] for p in pairs]
    assert kin.joint_paths.between(a, b) == [_walked(kin, x, y) for x, y in pairs]
    assert kin.joint_paths.between(b, a) == kin.joint_paths.between(a, b)


def _revolute(name: str, parent: str, child: str, mimic: str = "") -> str:
    extra = f'<mimic joint="{mimic}" multiplier="-1"/>' if mimic else ""
    return (
        f'<joint name="{name}" type="revolute"><parent link="{parent}"/><child link="{child}"/>'
        f'<axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/>{extra}</joint>'
    )


def test_a_mimic_below_its_master_on_one_branch_counts_below_their_common_ancestor() -> None:
    # base -j1-> l1 -fixed-> l2 -j3 (mimics j1)-> l3 -j4-> l4, and l1 -j5 (mimics j1)-> m1
    links = "".join(f'<link name="{n}"/>' for n in ("base", "l1", "l2", "l3", "l4", "m1"))
    fixed = '<joint name="j2" type="fixed"><parent link="l1"/><child link="l2"/></joint>'
    joints = (
        _revolute("j1", "base", "l1")
        + fixed
        + _revolute("j3", "l2", "l3", mimic="j1")
        + _revolute("j4", "l3", "l4")
        + _revolute("j5", "l1", "m1", mimic="j1")
    )
    urdf = parse_urdf_string(f'<robot name="r">{links}{joints}</robot>', "r.urdf")
    kin, _ = build_kinematic_model(urdf)
    # l2 lies below j1, yet l4 moves relative to it by j1 again (through the mimic j3)
    assert kin.joints_on_path("l2", "l4") == ("j1", "j4")
    assert kin.joints_on_path("l1", "l2") == ()
    assert kin.joints_on_path("m1", "l2") == ("j1",)
    assert kin.joints_on_path("base", "m1") == ("j1",)
    _check_every_pair(kin)


def test_every_frame_pair_of_a_branched_tree_with_mimics() -> None:
    urdf_text, _ = tree_robot(100)
    kin, _ = build_kinematic_model(parse_urdf_string(urdf_text, "tree.urdf"))
    assert kin.mimic_joints  # the tree has them, on one branch and across branches
    _check_every_pair(kin)


@pytest.mark.parametrize("name", ["romeo", "pr2"])
def test_every_frame_pair_of_real_robots_with_mimics(name: str) -> None:
    kin, _ = build_kinematic_model(load_urdf(robot_urdf(name)))
    _check_every_pair(kin)


def _random_tree_urdf(seed: int, links: int) -> str:
    """A seeded tree mixing chains and stars, with fixed, revolute, prismatic and continuous
    joints and mimics whose master is anywhere: above, below, on another branch."""
    rng = random.Random(seed)
    spec = []
    for i in range(1, links):
        shape = rng.choice(["chain", "star", "any"])
        parent = i - 1 if shape == "chain" else (0 if shape == "star" else rng.randrange(i))
        spec.append((i, parent, rng.choice(["revolute", "prismatic", "continuous", "fixed"])))
    masters = [f"j{i}" for i, _, kind in spec if kind != "fixed"]
    joints = []
    for i, parent, kind in spec:
        extra = ""
        if kind != "fixed":
            extra = '<axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/>'
            if rng.random() < 0.3 and len(masters) > 1:
                master = rng.choice([m for m in masters if m != f"j{i}"])
                extra += f'<mimic joint="{master}" multiplier="-1"/>'
                masters.remove(f"j{i}")
        joints.append(
            f'<joint name="j{i}" type="{kind}"><parent link="l{parent}"/>'
            f'<child link="l{i}"/>{extra}</joint>'
        )
    body = "".join(f'<link name="l{i}"/>' for i in range(links)) + "".join(joints)
    return f'<robot name="r">{body}</robot>'


@pytest.mark.parametrize("seed", range(4))
def test_every_frame_pair_of_random_trees_with_mimics_anywhere(seed: int) -> None:
    for k in range(10):
        text = _random_tree_urdf(100 * seed + k, 5 + (7 * k) % 30)
        kin, _ = build_kinematic_model(parse_urdf_string(text, "r.urdf"))
        _check_every_pair(kin)
