"""The frozen Robot value: built once by the loader, views cached, accepted by entry points."""

from __future__ import annotations

import dataclasses

import pytest

from tests.paths import UR10E_URDF, UR10E_XRDF
from xrdf_tools.export.curobo import to_curobo
from xrdf_tools.lint import lint_text
from xrdf_tools.robot.core import Robot, as_robot
from xrdf_tools.robot.kinematics import build_kinematic_model
from xrdf_tools.robot.urdf_source import joints_of, load_urdf, source_line, urdf_path, urdf_text
from xrdf_tools.robot.xacro_source import load_robot
from xrdf_tools.xrdf.io import load_xrdf


def test_loader_builds_one_frozen_robot() -> None:
    robot = load_robot(UR10E_URDF)
    assert isinstance(robot, Robot)
    assert robot.path == str(UR10E_URDF)
    assert robot.text == UR10E_URDF.read_text(encoding="utf-8")
    assert robot.xacro_text is None
    assert robot.links[0] == robot.root_link()
    joint = next(iter(robot.joints.values()))
    assert joint.line == robot.joint_lines[joint.name] == robot.source_line("joint", joint.name)
    with pytest.raises(dataclasses.FrozenInstanceError):
        robot.path = "elsewhere"  # type: ignore[misc]
    assert robot.tree is robot.tree


def test_bare_yourdfpy_object_keeps_its_provenance() -> None:
    urdf = load_urdf(UR10E_URDF)
    robot = as_robot(urdf)
    assert robot.urdf is urdf and as_robot(urdf) is robot
    assert urdf_path(urdf) == str(UR10E_URDF)
    assert urdf_text(urdf) == robot.text
    name = next(iter(robot.joints))
    assert source_line(urdf, "joint", name) == robot.joint_lines[name]
    assert joints_of(urdf) == dict(robot.joints)


def test_kinematic_model_built_once_per_modifiers() -> None:
    robot = load_robot(UR10E_URDF)
    x = load_xrdf(UR10E_XRDF)
    kin, _ = build_kinematic_model(robot, x)
    assert build_kinematic_model(robot.urdf, x)[0] is kin


def test_entry_points_take_the_robot() -> None:
    robot = load_robot(UR10E_URDF)
    x = load_xrdf(UR10E_XRDF)
    assert to_curobo(x, robot) == to_curobo(x, robot.tree)
    text = UR10E_XRDF.read_text(encoding="utf-8")
    assert lint_text(text, "u.xrdf", urdf_model=robot) == lint_text(
        text, "u.xrdf", urdf_model=robot.urdf
    )
