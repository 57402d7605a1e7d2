"""Messages name a file that a `$(find pkg)` include reached as the user would type it.

xacro finds such a file by its absolute path (Flexiv's `rizon.srdf.xacro` includes
`$(find flexiv_moveit_config)/srdf/rizon_macro.srdf.xacro`; Motoman's `sda10f.xacro` its
`arm_macro.xacro`): the diagnostics placed in it printed `/home/…/arm_macro.xacro:4` beside
`sda10f.xacro` for the top file. Below the current directory it is now a relative path."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from xrdf_tools.robot.xacro_source import load_robot

PACKAGE = (
    '<package format="3"><name>arm_support</name><version>0.0.0</version>'
    "<description>d</description><maintainer email='a@b.c'>a</maintainer>"
    "<license>MIT</license></package>\n"
)
MACRO = """<robot xmlns:xacro="http://wiki.ros.org/xacro">
  <xacro:macro name="arm" params="prefix">
    <link name="${prefix}base"/>
    <link name="${prefix}link1"/>
    <joint name="${prefix}joint_1" type="revolute"><parent link="${prefix}base"/>
      <child link="${prefix}link1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  </xacro:macro>
</robot>
"""
TOP = """<robot name="arm" xmlns:xacro="http://wiki.ros.org/xacro">
  <xacro:include filename="$(find arm_support)/urdf/arm_macro.xacro"/>
  <xacro:arm prefix=""/>
</robot>
"""


def test_a_found_include_is_placed_relative_to_the_current_directory(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    urdf = tmp_path / "arm_support" / "urdf"
    urdf.mkdir(parents=True)
    (tmp_path / "arm_support" / "package.xml").write_text(PACKAGE)
    (urdf / "arm_macro.xacro").write_text(MACRO)
    (urdf / "arm.xacro").write_text(TOP)
    monkeypatch.chdir(tmp_path)
    robot = load_robot("arm_support/urdf/arm.xacro")
    macro = os.path.join("arm_support", "urdf", "arm_macro.xacro")
    assert robot.included_files == (macro,)
    assert robot.include_places[("joint", "joint_1")] == (macro, 5)
    assert robot.include_places[("link", "link1")] == (macro, 4)


def test_a_relative_include_through_a_parent_is_placed_without_the_dotdot(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The human hand model's ``robots/human_hand.urdf.xacro`` includes
    ``../model/human_hand.urdf.xacro``: its links were placed in
    ``human_hand/robots/../model/human_hand.urdf.xacro:41``."""
    (tmp_path / "hand" / "robots").mkdir(parents=True)
    (tmp_path / "hand" / "model").mkdir()
    (tmp_path / "hand" / "model" / "arm_macro.xacro").write_text(MACRO)
    top = TOP.replace("$(find arm_support)/urdf/arm_macro.xacro", "../model/arm_macro.xacro")
    (tmp_path / "hand" / "robots" / "arm.xacro").write_text(top)
    monkeypatch.chdir(tmp_path)
    robot = load_robot("hand/robots/arm.xacro")
    macro = os.path.join("hand", "model", "arm_macro.xacro")
    assert robot.included_files == (macro,)
    assert robot.include_places[("link", "link1")] == (macro, 4)
