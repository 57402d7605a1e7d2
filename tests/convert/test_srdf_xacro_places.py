"""An SRDF xacro whose groups and states a macro of an included file writes (the ROS 2 MoveIt
configurations of UR and xArm): every diagnostic about them names that file and line."""

from __future__ import annotations

from pathlib import Path

from typer.testing import CliRunner

from xrdf_tools.cli import app
from xrdf_tools.convert.sources.srdf import load_srdf

URDF = """<robot name="t">
  <link name="base"/><link name="l1"/><link name="tip"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="tip"/>
    <origin xyz="0 0 0.5"/><axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/>
  </joint>
</robot>
"""

TOP = """<?xml version="1.0"?>
<robot name="t" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:arg name="prefix" default=""/>
  <xacro:include filename="macros/arm_macro.srdf.xacro"/>
  <xacro:arm_srdf prefix="$(arg prefix)"/>
  <xacro:hand_srdf name="hand"/>
</robot>
"""

MACROS = """<?xml version="1.0"?>
<robot xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:macro name="arm_srdf" params="prefix:=''">
    <group name="${prefix}arm">
      <chain base_link="${prefix}base" tip_link="${prefix}tip"/>
    </group>
    <group name="${prefix}wrist"><joint name="${prefix}j2"/></group>
    <group_state name="home" group="${prefix}arm">
      <joint name="${prefix}j1" value="0.5"/>
      <joint name="${prefix}j2" value="0.25"/>
    </group_state>
    <disable_collisions link1="${prefix}base" link2="${prefix}ghost" reason="Never"/>
  </xacro:macro>
  <xacro:macro name="hand_srdf" params="name">
    <group name="${name}"><joint name="finger"/></group>
  </xacro:macro>
</robot>
"""


def _files(tmp_path: Path) -> tuple[Path, Path, Path]:
    urdf = tmp_path / "t.urdf"
    urdf.write_text(URDF)
    top = tmp_path / "t.srdf.xacro"
    top.write_text(TOP)
    (tmp_path / "macros").mkdir()
    macros = tmp_path / "macros" / "arm_macro.srdf.xacro"
    macros.write_text(MACROS)
    return urdf, top, macros


def test_elements_a_macro_of_an_included_file_writes_are_placed_there(tmp_path: Path) -> None:
    """convert-chosen-group and convert-chosen-state had no line ('t.srdf.xacro: info
    convert-chosen-group ...') when a macro of an included file wrote the group and the state;
    so had every other diagnostic about an SRDF element a macro writes."""
    urdf, top, macros = _files(tmp_path)
    r = CliRunner().invoke(
        app, ["convert", str(urdf), "--srdf", str(top), "-o", str(tmp_path / "t.xrdf")]
    )
    assert r.exit_code == 0, r.output
    said = {line.split(" ")[2]: line.split(" ")[0] for line in r.stderr.splitlines() if " " in line}
    assert said["convert-chosen-group"] == f"{macros}:4:"
    assert said["convert-chosen-state"] == f"{macros}:8:"
    assert said["convert-unknown-link"] == f"{macros}:12:"  # the disable_collisions entry
    # a group named by the macro's argument alone: the call that makes it
    assert said["convert-srdf-unused-group"] == f"{top}:6:"


def test_the_places_of_an_srdf_xacro(tmp_path: Path) -> None:
    """The places are found by the attributes that tell the elements apart, in the files the
    expansion included; elements written literally in the top file keep their line there."""
    _, top, macros = _files(tmp_path)
    srdf = load_srdf(top)
    assert srdf.groups["arm"].line is None
    assert srdf.at(srdf.groups["arm"]) == (str(macros), 4)
    assert srdf.at(srdf.groups["wrist"]) == (str(macros), 7)
    assert srdf.at(srdf.group_states[0]) == (str(macros), 8)
    assert srdf.where(("disable_collisions", "base", "ghost"), None) == (str(macros), 12)
    assert srdf.at(srdf.groups["hand"]) == (str(top), 6)
    # with a prefix the same templates fit
    prefixed = load_srdf(top, xacro_args={"prefix": "left_"})
    assert prefixed.at(prefixed.groups["left_arm"]) == (str(macros), 4)
    assert prefixed.at(prefixed.group_states[0]) == (str(macros), 8)


def test_inspect_json_names_the_file_that_writes_each_group(tmp_path: Path) -> None:
    """`inspect --format json` gave a macro-written group `"line": null`; it now gives the
    included file and its line, and the top file's line for a group the call names."""
    import json

    urdf, top, macros = _files(tmp_path)
    r = CliRunner().invoke(app, ["inspect", str(urdf), "--srdf", str(top), "--format", "json"])
    assert r.exit_code == 0, r.output
    places = {g["name"]: (g["file"], g["line"]) for g in json.loads(r.stdout)["groups"]}
    assert places["arm"] == (str(macros), 4)
    assert places["wrist"] == (str(macros), 7)
    assert places["hand"] == (str(top), 6)
