"""`xrdf export curobo` of one xacro with different `--xacro-arg`s into one folder.

Vendor xacros describe several arms (UR's `ur.urdf.xacro` with `ur_type:=ur3e|ur5e`, Flexiv's
`rizon.urdf.xacro` with `rizon_type:=rizon4|rizon10`). The expanded URDF is named after the
output, so each exported config keeps its own: it was named after the xacro, and the second
export silently replaced the first one's URDF (the Rizon 10 config then loaded the Rizon 4)."""

from __future__ import annotations

from pathlib import Path

import yaml
from typer.testing import CliRunner

from xrdf_tools.cli import app

XACRO = """<?xml version="1.0"?>
<robot xmlns:xacro="http://wiki.ros.org/xacro" name="arm">
  <xacro:arg name="reach" default="0.3"/>
  <link name="base"><collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision></link>
  <link name="tip"><collision><geometry><box size="0.05 0.05 0.05"/></geometry></collision></link>
  <link name="post"><collision><geometry><box size="0.05 0.05 0.05"/></geometry></collision></link>
  <joint name="fix" type="fixed"><parent link="base"/><child link="post"/>
    <origin xyz="0.3 0 0"/></joint>
  <joint name="j1" type="revolute"><parent link="base"/><child link="tip"/>
    <origin xyz="0 0 $(arg reach)"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="10" velocity="1"/></joint>
</robot>
"""

XRDF = """format: xrdf
format_version: 1.0
modifiers: []
default_joint_positions: {j1: 0.0}
cspace:
  joint_names: [j1]
  acceleration_limits: [10.0]
  jerk_limits: [1000.0]
tool_frames: [tip]
collision:
  geometry: arm_spheres
self_collision:
  geometry: arm_spheres
  ignore: {base: [tip, post]}
geometry:
  arm_spheres:
    spheres:
      base: [{center: [0.0, 0.0, 0.0], radius: 0.05}]
      tip: [{center: [0.0, 0.0, 0.0], radius: 0.03}]
      post: [{center: [0.0, 0.0, 0.0], radius: 0.03}]
"""


def test_each_export_keeps_its_own_expanded_urdf(runner: CliRunner, tmp_path: Path) -> None:
    xacro, xrdf = tmp_path / "arm.urdf.xacro", tmp_path / "arm.xrdf"
    xacro.write_text(XACRO)
    xrdf.write_text(XRDF)
    out = tmp_path / "cfg"
    out.mkdir()
    for reach in ("0.3", "0.5"):
        args = ["export", "curobo", str(xrdf), "--urdf", str(xacro), "--xacro-arg"]
        r = runner.invoke(app, [*args, f"reach:={reach}", "-o", str(out / f"arm{reach}.yml")])
        assert r.exit_code == 0, r.output
    for reach in ("0.3", "0.5"):
        cfg = yaml.safe_load((out / f"arm{reach}.yml").read_text())
        urdf = out / cfg["robot_cfg"]["kinematics"]["urdf_path"]
        assert urdf.name == f"arm{reach}.urdf"
        assert f'xyz="0 0 {reach}"' in urdf.read_text()
