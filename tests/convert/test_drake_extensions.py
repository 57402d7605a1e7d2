"""Drake's URDF extensions (RobotLocomotion's models): ``drake:acceleration`` limits, collision
filter groups, ``<frame>`` elements and every other ``drake:`` element are read or said, never
silently lost."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from xrdf_tools.cli import app
from xrdf_tools.convert.core import ConvertOptions, convert
from xrdf_tools.diagnostics import Diagnostic, Severity
from xrdf_tools.robot.urdf_source import read_robot
from xrdf_tools.util.errors import SourceError
from xrdf_tools.xrdf.model import AddFrame

_JOINT = """  <joint name="{name}" type="revolute"><parent link="{parent}"/><child link="{child}"/>
    <origin xyz="0 0 0.2"/><axis xyz="0 1 0"/>
    <limit lower="-2" upper="2" effort="10" velocity="1"{extra}/></joint>
"""

#: A three-joint arm as Drake's models write it (line numbers matter: see the tests).
_ARM = (
    """<?xml version="1.0"?>
<robot name="arm" xmlns:drake="http://drake.mit.edu">
  <link name="base"/>
  <link name="l1"/>
  <link name="l2"/>
  <link name="l3"/>
"""
    + _JOINT.format(name="j1", parent="base", child="l1", extra=' drake:acceleration="8.5"')
    + _JOINT.format(name="j2", parent="l1", child="l2", extra=' drake:acceleration="4"')
    + _JOINT.format(name="j3", parent="l2", child="l3", extra="")
    + """  <frame name="tool_frame" link="l3" xyz="0 0  0.1" rpy="0 0 1.5"/>
  <drake:collision_filter_group name="wrist">
    <drake:member link="l2"/>
    <drake:member link="l3"/>
    <drake:ignored_collision_filter_group name="wrist"/>
  </drake:collision_filter_group>
  <drake:collision_filter_group name="base_group">
    <drake:member link="base"/>
    <drake:ignored_collision_filter_group name="wrist"/>
  </drake:collision_filter_group>
  <transmission name="t1"><joint name="j1"/><actuator name="a1">
    <drake:gear_ratio value="160.0"/></actuator></transmission>
  <transmission name="t2"><joint name="j2"/><actuator name="a2">
    <drake:gear_ratio value="160.0"/></actuator></transmission>
  <drake:joint name="slide" type="planar"><parent link="base"/><child link="l1"/></drake:joint>
</robot>
"""
)
_FRAME_LINE = 16
_WRIST_LINE = 17


def _urdf(tmp_path: Path, text: str = _ARM) -> Path:
    path = tmp_path / "arm.urdf"
    path.write_text(text)
    return path


def _convert(
    tmp_path: Path, text: str = _ARM, **options: object
) -> tuple[dict[str, float], dict[str, list[Diagnostic]], object]:
    robot = read_robot(_urdf(tmp_path, text))
    x, diags = convert(robot, ConvertOptions(joints=("j1", "j2", "j3"), **options))  # type: ignore[arg-type]
    assert x.cspace is not None
    limits = dict(zip(x.cspace.joint_names, x.cspace.acceleration_limits, strict=True))
    by_rule: dict[str, list[Diagnostic]] = {}
    for d in diags:
        by_rule.setdefault(d.rule, []).append(d)
    return limits, by_rule, x


def test_drake_acceleration_is_an_acceleration_limit_source(tmp_path: Path) -> None:
    limits, rules, _ = _convert(tmp_path)
    assert limits == {"j1": 8.5, "j2": 4.0, "j3": 10.0}
    (said,) = rules["convert-drake-acceleration"]
    assert said.severity is Severity.INFO and said.line == 9  # the first <limit>
    assert "j1 8.5, j2 4" in said.message
    (default,) = rules["convert-default-acceleration"]
    assert "for j3:" in default.message  # j1 and j2 have theirs


def test_drake_names_without_the_xmlns_declaration_are_read_as_drake_does(tmp_path: Path) -> None:
    """Drake's parser matches ``drake:`` as written, so a model without ``xmlns:drake`` has
    its limits and filter groups read (ROS ignores them: each name is also warned)."""
    text = _ARM.replace(' xmlns:drake="http://drake.mit.edu"', "")
    limits, _, x = _convert(tmp_path, text)
    assert limits == {"j1": 8.5, "j2": 4.0, "j3": 10.0}
    assert {frozenset(p) for p in x.self_collision.ignore_pairs()} == {  # type: ignore[attr-defined]
        frozenset(p)
        for p in _convert(tmp_path)[2].self_collision.ignore_pairs()  # type: ignore[attr-defined]
    }
    undeclared = [w for w in read_robot(_urdf(tmp_path, text)).warnings]
    assert undeclared and all(w.rule == "urdf-prefix-undeclared" for w in undeclared)
    assert all("read as Drake's" in w.message for w in undeclared)


def test_another_prefix_bound_to_drake_s_uri_is_not_drake_s(tmp_path: Path) -> None:
    """Drake matches ``drake:`` as written: ``xmlns:d="http://drake.mit.edu"`` with
    ``d:acceleration`` and ``<d:collision_filter_group>`` is nothing Drake reads, so no limit
    and no ignored pair comes from it (they made pairs ignored that Drake checks)."""
    text = _ARM.replace("xmlns:drake=", "xmlns:d=").replace("drake:", "d:")
    limits, rules, x = _convert(tmp_path, text)
    assert limits == {"j1": 10.0, "j2": 10.0, "j3": 10.0}  # the default fills them all
    assert not x.self_collision or not x.self_collision.ignore_pairs()  # type: ignore[attr-defined]
    assert "convert-drake-acceleration" not in rules and "convert-drake-filter-group" not in rules


def test_a_joint_limits_file_comes_first_and_acceleration_fills_the_rest(tmp_path: Path) -> None:
    limits_file = tmp_path / "joint_limits.yaml"
    limits_file.write_text("joint_limits:\n  j1:\n    has_acceleration_limits: true\n"
                           "    max_acceleration: 2.0\n")  # fmt: skip
    limits, rules, _ = _convert(tmp_path, joint_limits=limits_file, acceleration=3.0)
    assert limits == {"j1": 2.0, "j2": 4.0, "j3": 3.0}
    (said,) = rules["convert-drake-acceleration"]
    assert "for 1 joint(s): j2 4" in said.message and "j1 take theirs" in said.message


def test_a_drake_acceleration_that_is_no_positive_number_is_said(tmp_path: Path) -> None:
    text = _ARM.replace('drake:acceleration="4"', 'drake:acceleration="-4"')
    limits, rules, _ = _convert(tmp_path, text)
    assert limits["j2"] == 10.0
    bad = [d for d in rules["convert-drake-acceleration"] if d.severity is Severity.WARNING]
    assert len(bad) == 1 and bad[0].line == 12 and "'j2' is not a positive number" in bad[0].message


def test_collision_filter_groups_become_ignored_pairs_with_their_reason(tmp_path: Path) -> None:
    _, rules, x = _convert(tmp_path)
    sc = x.self_collision  # type: ignore[attr-defined]
    assert {frozenset(p) for p in sc.ignore_pairs()} == {
        frozenset(("l2", "l3")),  # wrist ignores itself
        frozenset(("base", "l2")),  # base_group ignores wrist
        frozenset(("base", "l3")),
    }
    said = {d.line: d for d in rules["convert-drake-filter-group"]}
    assert "reason 'Drake collision filter group wrist'" in said[_WRIST_LINE].message
    assert said[_WRIST_LINE].message.startswith("1 pair(s) ignored")
    assert "base/l2, base/l3" in said[_WRIST_LINE + 5].message


def test_filter_groups_naming_what_the_urdf_lacks_are_said(tmp_path: Path) -> None:
    text = _ARM.replace('<drake:member link="l3"/>', '<drake:member link="l9"/>').replace(
        '<drake:ignored_collision_filter_group name="wrist"/>\n  </drake:collision_filter_group>'
        '\n  <drake:collision_filter_group name="base_group">',
        '<drake:ignored_collision_filter_group name="elbow"/>\n  '
        '</drake:collision_filter_group>\n  <drake:collision_filter_group name="base_group">',
    )
    _, rules, x = _convert(tmp_path, text)
    (unknown,) = rules["convert-unknown-link"]
    assert "'l9'" in unknown.message and unknown.line == _WRIST_LINE
    (missing,) = [d for d in rules["convert-drake-filter-group"] if "elbow" in d.message]
    assert missing.severity is Severity.WARNING and missing.line == _WRIST_LINE
    assert {frozenset(p) for p in x.self_collision.ignore_pairs()} == {frozenset(("base", "l2"))}  # type: ignore[attr-defined]


def test_a_drake_frame_is_said_and_becomes_an_add_frame_as_tool_frame(tmp_path: Path) -> None:
    _, rules, x = _convert(tmp_path)
    (frame,) = rules["convert-drake-frame"]
    assert frame.line == _FRAME_LINE and "'tool_frame' on link 'l3'" in frame.message
    assert "tool_frame" not in x.tool_frames  # type: ignore[attr-defined]
    assert not x.modifiers  # type: ignore[attr-defined]
    _, rules, x = _convert(tmp_path, tool_frames=("tool_frame",))
    assert x.tool_frames == ("tool_frame",)  # type: ignore[attr-defined]
    (added,) = x.modifiers  # type: ignore[attr-defined]
    assert isinstance(added, AddFrame)
    assert (added.frame_name, added.parent_frame_name) == ("tool_frame", "l3")
    assert added.joint_name == "tool_frame_joint" and added.position == (0.0, 0.0, 0.1)
    w, qx, qy, qz = added.orientation.as_wxyz()  # rpy 0 0 1.5: a turn of 1.5 rad about z
    assert (qx, qy) == (0.0, 0.0) and math.isclose(2 * math.atan2(qz, w), 1.5)
    (note,) = rules["convert-frame-added"]
    assert note.severity is Severity.INFO and note.line == _FRAME_LINE


def test_the_added_drake_frame_is_where_drake_puts_it(tmp_path: Path) -> None:
    """Forward kinematics of the written XRDF put the added tool frame 0.1 m above l3, turned
    1.5 rad about its z axis, at any configuration."""
    from xrdf_tools.robot.kinematics import build_kinematic_model, fk

    _, _, x = _convert(tmp_path, tool_frames=("tool_frame",))
    robot = read_robot(_urdf(tmp_path))
    kin, _ = build_kinematic_model(robot, x)  # type: ignore[arg-type]
    q = np.array([0.3, -0.7, 1.1])[: len(kin.actuated_joints)]
    l3, tool = fk(kin, q, ["l3", "tool_frame"])
    c, s = math.cos(1.5), math.sin(1.5)
    local = np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0.1], [0, 0, 0, 1]])
    np.testing.assert_allclose(tool, l3 @ local, atol=1e-12)


def test_a_drake_frame_on_no_link_stops_as_tool_frame(tmp_path: Path) -> None:
    text = _ARM.replace('<frame name="tool_frame" link="l3"', '<frame name="tool_frame" link="l7"')
    with pytest.raises(SourceError) as caught:
        _convert(tmp_path, text, tool_frames=("tool_frame",))
    e = caught.value
    assert e.line == _FRAME_LINE and "its link 'l7' is not a link of the URDF" in e.message


_TOOL = '<frame name="tool_frame" link="l3" xyz="0 0  0.1" rpy="0 0 1.5"/>'


def test_a_drake_frame_named_twice_stops_as_tool_frame(tmp_path: Path) -> None:
    """Drake refuses a second frame of one name; the last one was taken without a word."""
    text = _ARM.replace(_TOOL, _TOOL + '<frame name="tool_frame" link="l1" xyz="0 0 0.5"/>')
    with pytest.raises(SourceError) as caught:
        _convert(tmp_path, text, tool_frames=("tool_frame",))
    e = caught.value
    assert e.line == _FRAME_LINE
    assert "Drake refuses it: 2 <frame> elements are named 'tool_frame'" in e.message


def test_a_drake_frame_named_as_a_link_is_not_offered(tmp_path: Path) -> None:
    """``--tool-frame l2`` is the link: the note no longer promises to add the frame."""
    text = _ARM.replace('<frame name="tool_frame"', '<frame name="l2"')
    _, rules, x = _convert(tmp_path, text, tool_frames=("l2",))
    (note,) = rules["convert-drake-frame"]
    assert "Drake refuses it: a link is named 'l2' too" in note.message
    assert "writes it as an add_frame" not in note.message
    assert x.tool_frames == ("l2",) and not x.modifiers  # type: ignore[attr-defined]


@pytest.mark.parametrize(
    ("pose", "said"),
    [
        ('xyz="0 0.1"', "its xyz '0 0.1' must be three numbers within ±1e+06 m"),
        ('rpy="0 0 0 1"', "its rpy '0 0 0 1' must be three numbers within ±1e+12"),
        ('xyz="1e300 0 0"', "its xyz '1e300 0 0' must be three numbers within ±1e+06 m"),
        ('rpy="1e300 0 0"', "its rpy '1e300 0 0' must be three numbers within ±1e+12"),
    ],
)
def test_a_drake_frame_past_the_number_bounds_stops_at_its_line(
    tmp_path: Path, pose: str, said: str
) -> None:
    """A frame 1e300 m away was written and then refused by the lint of the converted XRDF
    (exit 1, at a line of a file never written); a 1e300 rad turn was written as a pose."""
    text = _ARM.replace('xyz="0 0  0.1" rpy="0 0 1.5"', pose)
    with pytest.raises(SourceError) as caught:
        _convert(tmp_path, text, tool_frames=("tool_frame",))
    assert caught.value.line == _FRAME_LINE and said in caught.value.message


def test_a_drake_frame_without_name_or_link_is_said_so(tmp_path: Path) -> None:
    """A missing attribute was read as the name 'None' (``--tool-frame None`` added it)."""
    text = _ARM.replace('name="tool_frame" ', "")
    _, rules, _ = _convert(tmp_path, text)
    (note,) = rules["convert-drake-frame"]
    assert "Drake <frame> without a name on link 'l3'" in note.message
    with pytest.raises(SourceError, match="'None' is not a link"):
        _convert(tmp_path, text, tool_frames=("None",))
    text = _ARM.replace('link="l3" xyz="0 0  0.1"', 'xyz="0 0  0.1"')
    with pytest.raises(SourceError) as caught:
        _convert(tmp_path, text, tool_frames=("tool_frame",))
    assert "a Drake <frame> on no link" in caught.value.message
    assert "Drake refuses it: it names no link" in caught.value.message


def test_other_drake_elements_are_one_note_per_kind(tmp_path: Path) -> None:
    _, rules, _ = _convert(tmp_path)
    notes = {d.message.split(" left out", 1)[0]: d for d in rules["convert-drake-ignored"]}
    assert set(notes) == {"drake:gear_ratio", "drake:joint planar"}
    assert "(2 in the file)" in notes["drake:gear_ratio"].message
    assert notes["drake:gear_ratio"].severity is Severity.INFO
    assert notes["drake:joint planar"].severity is Severity.WARNING
    assert notes["drake:joint planar"].line == 30


def test_convert_on_the_command_line(runner: CliRunner, tmp_path: Path) -> None:
    urdf = _urdf(tmp_path)
    out = tmp_path / "arm.xrdf"
    r = runner.invoke(app, ["convert", str(urdf), "--joints", "j1,j2,j3", "-o", str(out)])
    assert r.exit_code == 0, r.output
    assert f"arm.urdf:{_FRAME_LINE}: warning convert-drake-frame" in r.stderr
    r = runner.invoke(app, ["convert", str(urdf), "--tool-frame", "tool_frame", "-o", str(out)])
    assert r.exit_code == 0, r.output
    assert f"arm.urdf:{_FRAME_LINE}: info convert-frame-added" in r.stderr
    r = runner.invoke(app, ["lint", str(out), "--urdf", str(urdf), "--target", "curobo"])
    assert "tool_frame" not in r.output  # the tool frame is known to every check (the arm
    # has no spheres, which lint says)


def test_inspect_lists_drake_frames(runner: CliRunner, tmp_path: Path) -> None:
    urdf = _urdf(tmp_path)
    r = runner.invoke(app, ["inspect", str(urdf)])
    assert r.exit_code == 0, r.output
    assert f"  tool_frame on l3 (xyz 0 0 0.1, rpy 0 0 1.5, line {_FRAME_LINE})" in r.stdout
    r = runner.invoke(app, ["inspect", str(urdf), "-f", "json"])
    frames = json.loads(r.stdout)["frames"]
    assert frames == [
        {
            "name": "tool_frame",
            "link": "l3",
            "xyz": "0 0 0.1",
            "rpy": "0 0 1.5",
            "line": _FRAME_LINE,
        }
    ]
