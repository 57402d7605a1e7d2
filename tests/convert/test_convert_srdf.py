"""URDF + MoveIt SRDF → XRDF on the real robots of example-robot-data."""

from __future__ import annotations

import math
import re
from pathlib import Path

import pytest
from typer.testing import CliRunner

from tests.robots import robots_dir
from xrdf_tools.cli import app
from xrdf_tools.convert.core import ConvertOptions, convert_files
from xrdf_tools.convert.sources import RobotTree
from xrdf_tools.convert.sources.srdf import cspace_of, group_joints, load_srdf, parse_srdf
from xrdf_tools.robot.core import as_robot
from xrdf_tools.util.errors import SourceError
from xrdf_tools.xrdf.io import dump_xrdf, parse_xrdf

#: SRDF (below robots/) -> (URDF below robots/, planning group or None for the default choice).
#: Every SRDF in example-robot-data that has a URDF beside it (cassie ships only SDF files).
SRDF_ROBOTS: dict[str, tuple[str, str | None]] = {
    "a1_description/srdf/a1.srdf": ("a1_description/urdf/a1.urdf", None),
    "alex_description/srdf/alex_nub_hands.srdf": (
        "alex_description/urdf/alex_nub_hands.urdf",
        None,
    ),
    "alex_description/srdf/alex_psyonic_hands.srdf": (
        "alex_description/urdf/alex_psyonic_hands.urdf",
        None,
    ),
    "alex_description/srdf/alex_sake_hands.srdf": (
        "alex_description/urdf/alex_sake_hands.urdf",
        None,
    ),
    "alexander_description/srdf/alexander.srdf": (
        "alexander_description/urdf/alexander_v1.lowerBodyOnly.urdf",
        None,
    ),
    "anymal_b_simple_description/srdf/anymal-kinova.srdf": (
        "anymal_b_simple_description/robots/anymal-kinova.urdf",
        None,
    ),
    "anymal_b_simple_description/srdf/anymal.srdf": (
        "anymal_b_simple_description/robots/anymal.urdf",
        None,
    ),
    "anymal_c_simple_description/srdf/anymal.srdf": (
        "anymal_c_simple_description/urdf/anymal.urdf",
        None,
    ),
    "b1_description/srdf/b1-z1.srdf": ("b1_description/urdf/b1-z1.urdf", None),
    "b1_description/srdf/b1.srdf": ("b1_description/urdf/b1.urdf", None),
    "baxter_description/srdf/baxter_manipulation.srdf": (
        "baxter_description/urdf/baxter.urdf",
        None,
    ),
    "bolt_description/srdf/bolt.srdf": ("bolt_description/robots/bolt.urdf", None),
    "borinot_description/srdf/borinot_flying_arm_2.srdf": (
        "borinot_description/urdf/borinot_flying_arm_2.urdf",
        None,
    ),
    "centauro_description/srdf/centauro.srdf": ("centauro_description/urdf/centauro.urdf", None),
    "finger_edu_description/srdf/finger_edu.srdf": (
        "finger_edu_description/robots/finger_edu.urdf",
        None,
    ),
    "go1_description/srdf/go1.srdf": ("go1_description/urdf/go1.urdf", None),
    "go2_description/srdf/go2.srdf": ("go2_description/urdf/go2.urdf", None),
    "hextilt_description/srdf/hextilt_flying_arm_5.srdf": (
        "hextilt_description/urdf/hextilt_flying_arm_5.urdf",
        None,
    ),
    "hyq_description/srdf/hyq.srdf": ("hyq_description/robots/hyq_no_sensors.urdf", None),
    "icub_description/srdf/icub.srdf": ("icub_description/robots/icub.urdf", None),
    "kinova_description/srdf/kinova.srdf": ("kinova_description/robots/kinova.urdf", None),
    "panda_description/srdf/panda.srdf": ("panda_description/urdf/panda.urdf", "arm"),
    "pr2_description/srdf/pr2.srdf": ("pr2_description/urdf/pr2.urdf", "right_arm"),
    "pr2_description/srdf/pr2_manipulation.srdf": ("pr2_description/urdf/pr2.urdf", "left_arm"),
    "romeo_description/srdf/romeo.srdf": ("romeo_description/urdf/romeo.urdf", None),
    "romeo_description/srdf/romeo_moveit.srdf": ("romeo_description/urdf/romeo.urdf", None),
    "romeo_description/srdf/romeo_small.srdf": ("romeo_description/urdf/romeo_small.urdf", None),
    "simple_humanoid_description/srdf/simple_humanoid.srdf": (
        "simple_humanoid_description/urdf/simple_humanoid.urdf",
        None,
    ),
    "simple_humanoid_description/srdf/simple_humanoid_classical.srdf": (
        "simple_humanoid_description/urdf/simple_humanoid_classical.urdf",
        None,
    ),
    "solo_description/srdf/solo.srdf": ("solo_description/robots/solo12.urdf", None),
    "talos_data/srdf/talos.srdf": ("talos_data/robots/talos_full_v2.urdf", "r_arm"),
    "ur_description/srdf/ur3_gripper.srdf": ("ur_description/urdf/ur3_gripper.urdf", None),
    "ur_description/srdf/ur5.srdf": ("ur_description/urdf/ur5_robot.urdf", None),
    "ur_description/srdf/ur5_gripper.srdf": ("ur_description/urdf/ur5_gripper.urdf", None),
    "ur_description/srdf/ur5_joint_limited_robot.srdf": (
        "ur_description/urdf/ur5_joint_limited_robot.urdf",
        None,
    ),
    "xarm_description/srdf/xarm7.srdf": ("xarm_description/urdf/xarm7.urdf", None),
    "z1_description/srdf/z1.srdf": ("z1_description/urdf/z1.urdf", None),
}


#: URDFs that are themselves invalid (lint reports urdf-invalid with this reason).
BROKEN_URDF = {
    "alex_description/srdf/alex_psyonic_hands.srdf": "mimics 'index_q1', which is not a joint",
}


#: SRDFs with groups that name joints/links/subgroups the URDF lacks, none of them the group
#: converted: each broken group is a located warning (never a silently skipped group, never a
#: refusal of the whole SRDF): (line of the first, regex of its message).
BROKEN_SRDF = {
    "alexander_description/srdf/alexander.srdf": (
        22,
        "group 'right_arm' does not match the URDF \\(unknown joints 'RIGHT_SHOULDER_Y'",
    ),
    "baxter_description/srdf/baxter_manipulation.srdf": (
        None,
        "unknown joints 'baxter/head_pan'.*did you mean 'head_pan'",
    ),
    "borinot_description/srdf/borinot_flying_arm_2.srdf": (
        None,
        "group 'end_effector' .*unknown chain link 'base'",
    ),
    "hextilt_description/srdf/hextilt_flying_arm_5.srdf": (None, "unknown chain link 'base'"),
    "hyq_description/srdf/hyq.srdf": (None, "group 'all_legs' .*unknown subgroups 'lf'"),
    "icub_description/srdf/icub.srdf": (
        None,
        "chain base 'chest' is not an ancestor of tip 'l_sole'",
    ),
    "simple_humanoid_description/srdf/simple_humanoid.srdf": (None, "unknown chain link 'r_foot'"),
    "simple_humanoid_description/srdf/simple_humanoid_classical.srdf": (
        None,
        "unknown chain link 'r_foot'",
    ),
    "solo_description/srdf/solo.srdf": (None, "unknown subgroups 'lf', 'rf'"),
    "z1_description/srdf/z1.srdf": (
        4,
        "group 'end_effector' does not match the URDF \\(unknown chain link 'base'\\); it is not "
        "used for this conversion",
    ),
}


def _robots() -> Path:
    root = robots_dir()
    if root is None:
        pytest.skip("example-robot-data is not installed")
    return root


def _pair(srdf: str) -> tuple[Path, Path, str | None]:
    root = _robots()
    urdf, group = SRDF_ROBOTS[srdf]
    if not (root / srdf).is_file() or not (root / urdf).is_file():
        pytest.skip(f"{srdf} / {urdf} not in this example-robot-data version")
    return root / urdf, root / srdf, group


def test_every_srdf_is_paired() -> None:
    """The table covers every SRDF shipped with a URDF (a new one makes this test fail)."""
    root = _robots()
    shipped = {str(p.relative_to(root)) for p in root.glob("*/srdf/*.srdf")}
    without_urdf = {s for s in shipped if not any((root / s).parent.parent.rglob("*.urdf"))}
    assert shipped - without_urdf <= set(SRDF_ROBOTS)


def _lint_errors(xrdf_text: str, urdf_path: Path) -> list[str]:
    from xrdf_tools.lint import lint_text

    diags = lint_text(xrdf_text, "<converted>", urdf=urdf_path)
    return [f"{d.rule}: {d.message}" for d in diags if d.severity.value == "error"]


@pytest.mark.slow
@pytest.mark.parametrize("srdf", sorted(SRDF_ROBOTS))
def test_example_robot_data_srdf_converts_and_lints(srdf: str) -> None:
    urdf, srdf_path, group = _pair(srdf)
    x, diags, _ = convert_files(urdf, ConvertOptions(srdf=srdf_path, group=group))
    broken = [d for d in diags if d.rule == "convert-srdf-unused-group"]
    if srdf in BROKEN_SRDF:
        line, pattern = BROKEN_SRDF[srdf]
        assert broken and all(d.line for d in broken)
        assert any(re.search(pattern, d.message) for d in broken), broken
        assert line is None or broken[0].line == line
    else:
        assert broken == []
    assert x.cspace is not None and x.cspace.joint_names, "empty c-space"
    assert x.tool_frames
    text = dump_xrdf(x)
    assert parse_xrdf(text) == x  # canonical and loss-free
    x1, _, _ = convert_files(
        urdf, ConvertOptions(srdf=srdf_path, group=group, format_version="1.0")
    )
    assert x1.format_version == "1.0" and x1 == x  # 1.0 is the default
    if srdf in BROKEN_URDF:
        # the URDF itself is invalid: no reader loads the result with it, and lint says why
        (error,) = _lint_errors(text, urdf)
        assert error.startswith("urdf-invalid: ") and BROKEN_URDF[srdf] in error
        return
    assert _lint_errors(text, urdf) == []
    assert _lint_errors(dump_xrdf(x1), urdf) == []


def _srdf_pairs(srdf_path: Path) -> set[frozenset[str]]:
    s = load_srdf(srdf_path)
    return {frozenset((a, b)) for a, b, _, _ in s.disable_collisions if a != b}


def test_panda_against_srdf() -> None:
    urdf, srdf, _ = _pair("panda_description/srdf/panda.srdf")
    x, diags, _ = convert_files(urdf, ConvertOptions(srdf=srdf))
    rules = {d.rule for d in diags}
    assert "convert-chosen-group" in rules  # 'arm' was chosen, not given
    assert x.cspace is not None
    assert x.cspace.joint_names == tuple(f"panda_joint{i}" for i in range(1, 8))
    assert x.tool_frames == ("panda_hand_tcp",)  # end_effector parent_link
    # group_state 'default' belongs to arm_and_hand: arm joints + the finger as auxiliary joint
    assert dict(x.default_joint_positions or {}) == {
        "panda_joint1": 0.0,
        "panda_joint2": -0.785398,
        "panda_joint3": 0.0,
        "panda_joint4": -2.35619,
        "panda_joint5": 0.0,
        "panda_joint6": 1.5707,
        "panda_joint7": 0.785398,
        "panda_finger_joint1": 0.001,
    }
    assert x.self_collision is not None
    assert x.self_collision.ignore_pairs() == _srdf_pairs(srdf)
    assert len(_srdf_pairs(srdf)) == 35
    # limits were not in the inputs: defaults, reported
    assert x.cspace.acceleration_limits == (10.0,) * 7
    assert {"convert-default-acceleration", "convert-default-jerk", "convert-no-spheres"} <= rules


def test_ur5_against_srdf() -> None:
    urdf, srdf, _ = _pair("ur_description/srdf/ur5.srdf")
    x, diags, _ = convert_files(urdf, ConvertOptions(srdf=srdf))
    assert x.cspace is not None
    assert x.cspace.joint_names == (
        "shoulder_pan_joint",
        "shoulder_lift_joint",
        "elbow_joint",
        "wrist_1_joint",
        "wrist_2_joint",
        "wrist_3_joint",
    )
    # the ur5 SRDF has no group, state or end effector: all three are guessed and reported
    rules = {d.rule for d in diags}
    assert {"convert-chosen-group", "convert-chosen-tool-frame", "convert-default-positions"} <= (
        rules
    )
    # the tool frame: UR's tool0, rigidly attached to wrist_3_link (not wrist_3_link itself)
    assert x.tool_frames == ("tool0",)
    assert dict(x.default_joint_positions or {}) == dict.fromkeys(x.cspace.joint_names, 0.0)
    assert x.self_collision is not None
    assert x.self_collision.ignore_pairs() == _srdf_pairs(srdf)
    # given on the command line instead: taken, and no longer reported as guessed
    x2, diags2, _ = convert_files(
        urdf, ConvertOptions(srdf=srdf, tool_frames=("tool0",), acceleration=5.0, jerk=100.0)
    )
    assert x2.tool_frames == ("tool0",)
    assert x2.cspace is not None and x2.cspace.acceleration_limits == (5.0,) * 6
    warned = {d.rule for d in diags2 if d.severity.value == "warning"}
    assert "convert-chosen-tool-frame" not in warned
    assert "convert-default-acceleration" not in warned


# --- group expansion on a small synthetic tree -------------------------------------------------

TREE_URDF = """<robot name="t">
  <link name="base"/><link name="a"/><link name="b"/><link name="c"/><link name="tip"/>
  <link name="z_side"/><link name="a_side"/><link name="m"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="a"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="a"/><child link="b"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="jfix" type="fixed"><parent link="b"/><child link="c"/></joint>
  <joint name="j3" type="prismatic"><parent link="c"/><child link="tip"/>
    <limit lower="0.5" upper="1" effort="1" velocity="1"/></joint>
  <joint name="zz" type="revolute"><parent link="base"/><child link="z_side"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="aa" type="continuous"><parent link="base"/><child link="a_side"/></joint>
  <joint name="mim" type="revolute"><parent link="a_side"/><child link="m"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/><mimic joint="aa"/></joint>
</robot>
"""


@pytest.fixture
def tree(tmp_path: Path) -> RobotTree:
    from xrdf_tools.robot.urdf_source import parse_urdf_string

    return as_robot(parse_urdf_string(TREE_URDF, str(tmp_path / "t.urdf"))).tree


def test_dfs_order_siblings_alphabetical(tree: RobotTree) -> None:
    assert tree.dfs_joints() == ["aa", "mim", "j1", "j2", "jfix", "j3", "zz"]


def test_group_expansion(tree: RobotTree) -> None:
    s = parse_srdf(
        """<robot name="t">
        <group name="chain"><chain base_link="a" tip_link="tip"/></group>
        <group name="mixed"><joint name="zz"/><link name="m"/><group name="chain"/></group>
        <group name="links"><link name="a"/><link name="base"/></group>
        <passive_joint name="zz"/>
        </robot>"""
    )
    # the chain stops at base 'a': j1 (a's own parent joint) is not included
    assert group_joints(s, "chain", tree) == ["j2", "jfix", "j3"]
    assert cspace_of(s, "chain", tree) == ["j2", "j3"]  # minus fixed
    # joint + link (its parent joint) + subgroup, in DFS order; minus mimic and passive
    assert group_joints(s, "mixed", tree) == ["mim", "j2", "jfix", "j3", "zz"]
    assert cspace_of(s, "mixed", tree) == ["j2", "j3"]
    assert group_joints(s, "links", tree) == ["j1"]  # the root link has no parent joint


def test_group_errors(tree: RobotTree) -> None:
    s = parse_srdf(
        """<robot name="t"><group name="g"><chain base_link="tip" tip_link="a"/></group>
        <group name="typo"><joint name="j22"/></group>
        <group name="loop1"><group name="loop2"/></group>
        <group name="loop2"><group name="loop1"/></group></robot>"""
    )
    with pytest.raises(SourceError, match="not an ancestor"):
        group_joints(s, "g", tree)
    with pytest.raises(SourceError, match="did you mean 'j2'"):
        group_joints(s, "typo", tree)
    with pytest.raises(SourceError, match="include each other"):
        group_joints(s, "loop1", tree)
    with pytest.raises(SourceError, match="no group 'nope'"):
        group_joints(s, "nope", tree)


def test_srdf_mapping_details(tree: RobotTree, tmp_path: Path) -> None:
    srdf = tmp_path / "t.srdf"
    srdf.write_text(
        """<robot name="t">
        <virtual_joint name="world" type="fixed" parent_frame="world" child_link="base"/>
        <group name="arm"><chain base_link="base" tip_link="tip"/></group>
        <group name="other"><joint name="zz"/></group><group name="hand"><link name="c"/></group>
        <group_state name="first" group="arm"><joint name="j1" value="0.1"/></group_state>
        <group_state name="home" group="arm"><joint name="j1" value="0.2"/>
          <joint name="j3" value="5"/><joint name="mim" value="0.3"/>
          <joint name="nope" value="1"/></group_state>
        <end_effector name="ee" parent_link="c" group="hand" parent_group="arm"/>
        <disable_collisions link1="a" link2="b" reason="Adjacent"/>
        <disable_collisions link1="b" link2="a" reason="Never"/>
        <disable_collisions link1="a" link2="tpi" reason="Never"/>
        <disable_default_collisions link="m"/>
        <link_sphere_approximation link="a">
          <sphere center="0 0 0.1" radius="0.05"/><sphere center="0 0 0" radius="0"/>
        </link_sphere_approximation>
        <link_sphere_approximation link="b"><sphere center="0 0 0" radius="0"/>
        </link_sphere_approximation>
        </robot>"""
    )
    from xrdf_tools.convert.core import convert

    x, diags = convert(tree, ConvertOptions(srdf=srdf))
    by_rule = {d.rule: d for d in diags}
    assert x.cspace is not None and x.cspace.joint_names == ("j1", "j2", "j3")
    assert x.tool_frames == ("c", "tip")  # end effector parent link first, then chain tip
    defaults = dict(x.default_joint_positions or {})
    assert defaults["j1"] == 0.2  # the state named 'home' wins over the first one
    assert defaults["j3"] == 1.0  # 5 is outside [0.5, 1]: clamped and reported
    assert "mim" not in defaults  # mimic joints never written
    assert defaults["j2"] == 0.0  # missing → 0, reported
    assert {
        "convert-clamped-default",
        "convert-default-positions",
        "convert-unknown-joint",
        "convert-virtual-joint",
    } <= set(by_rule)
    unknown = by_rule["convert-unknown-link"]
    assert "did you mean 'tip'" in unknown.message and unknown.line == 12
    assert x.self_collision is not None
    pairs = x.self_collision.ignore_pairs()
    assert frozenset(("a", "b")) in pairs
    assert {frozenset(("m", link)) for link in tree.links if link != "m"} <= pairs
    assert x.geometry is not None
    spheres = x.resolved_spheres(x.self_collision.geometry)
    assert list(spheres) == ["a"]  # zero radii dropped; all-zero 'b' has no spheres
    assert len(spheres["a"]) == 1


# --- broken groups, virtual joints, several groups, the default choice -------------------------


def _write(tmp_path: Path, text: str, name: str = "t.srdf") -> Path:
    p = tmp_path / name
    p.write_text(text)
    return p


def test_a_virtual_joint_to_a_link_the_urdf_lacks_is_warned(
    tree: RobotTree, tmp_path: Path
) -> None:
    """Neuromeka's Indy7 SRDF attaches its virtual joint to 'world', which only
    indy7_fixed.xacro has: with indy7.xacro it was an info "not represented", hiding that
    the SRDF belongs to another URDF. A warning at its line names the link; a virtual joint
    to a link of the URDF stays the info."""
    from xrdf_tools.convert.sources.srdf import read_srdf

    srdf = _write(
        tmp_path,
        """<robot name="t">
        <group name="arm"><chain base_link="base" tip_link="tip"/></group>
        <virtual_joint name="FixedBase" type="fixed" parent_frame="global" child_link="world"/>
        <virtual_joint name="odom" type="fixed" parent_frame="map" child_link="base"/>
        </robot>""",
    )
    d = read_srdf(load_srdf(srdf), tree, group="arm")
    said = [(w.rule, w.line, w.severity.value, w.message) for w in d.diagnostics]
    unknown = [s for s in said if s[0] == "convert-unknown-link"]
    assert len(unknown) == 1 and unknown[0][1:3] == (3, "warning"), said
    assert "virtual_joint 'FixedBase' attaches 'world'" in unknown[0][3]
    assert "another URDF" in unknown[0][3]
    assert [s[1] for s in said if s[0] == "convert-virtual-joint"] == [4]


def test_a_passive_virtual_joint_is_no_unknown_joint(tree: RobotTree, tmp_path: Path) -> None:
    """A mobile manipulator's SRDF marks its planar virtual joint passive (MoveIt reads a
    virtual joint there): no warning; a passive joint naming nothing is warned at its line."""
    srdf = _write(
        tmp_path,
        """<robot name="t">
        <group name="arm"><chain base_link="base" tip_link="tip"/></group>
        <virtual_joint name="virtual_joint" type="planar" parent_frame="odom" child_link="base"/>
        <passive_joint name="virtual_joint"/>
        <passive_joint name="ghost"/>
        </robot>""",
    )
    from xrdf_tools.convert.sources.srdf import read_srdf

    d = read_srdf(load_srdf(srdf), tree, group="arm")
    unknown = [(w.line, w.message) for w in d.diagnostics if w.rule == "convert-unknown-joint"]
    assert len(unknown) == 1 and unknown[0][0] == 5, unknown
    assert unknown[0][1].startswith("passive_joint 'ghost' is not a joint of the URDF")


def test_broken_groups_not_used_are_located_warnings_used_ones_errors(
    tree: RobotTree, tmp_path: Path
) -> None:
    srdf = _write(
        tmp_path,
        """<robot name="t">
        <group name="arm"><chain base_link="base" tip_link="tip"/></group>
        <group name="typo"><joint name="j22"/><joint name="j33"/><link name="nope"/></group>
        <group name="sub"><group name="missing"/></group>
        <group name="both"><group name="arm"/><group name="typo"/></group>
        <passive_joint name="ghost"/>
        </robot>""",
    )
    from xrdf_tools.convert.sources.srdf import read_srdf

    d = read_srdf(load_srdf(srdf), tree, group="arm")
    assert d.cspace == cspace_of(load_srdf(srdf), "arm", tree)
    warned = {(w.rule, w.line): w.message for w in d.diagnostics}
    typo = warned[("convert-srdf-unused-group", 3)]
    assert "group 'typo'" in typo and "unknown joints 'j22', 'j33'" in typo
    assert "unknown link 'nope'" in typo and "not used for this conversion" in typo
    assert "'missing'" in warned[("convert-srdf-unused-group", 4)]
    assert any("passive_joint 'ghost'" in m for m in warned.values())
    # the chosen default skips broken groups and says so (HSR's whole_body, whose base names
    # odom_x/odom_y/odom_t that its URDF lacks, was listed as having 0 actuated joints)
    chosen = read_srdf(load_srdf(srdf), tree)
    assert chosen.group == "arm"
    (why,) = [w.message for w in chosen.diagnostics if w.rule == "convert-chosen-group"]
    assert "others (actuated joints): typo (does not match the URDF), sub (does not match " in why
    assert "both (does not match the URDF)" in why
    # a group that is used, or includes a broken one, stays an error naming every broken one,
    # and the group that includes it (HSR's --group whole_body named only its subgroup 'base')
    for used, via in (("typo", ""), ("both", ", a subgroup of 'both'")):
        with pytest.raises(SourceError) as err:
            read_srdf(load_srdf(srdf), tree, group=used)
        msg = str(err.value)
        assert "1 SRDF group(s) used for the conversion do not match the URDF" in msg
        assert f"group 'typo' (line 3){via}: unknown joints 'j22', 'j33'" in msg
        assert "\n" not in msg


def test_an_srdf_xacros_groups_are_located_in_the_xacro_file(
    tree: RobotTree, tmp_path: Path
) -> None:
    """Trossen's wxai.srdf.xacro: a group naming a joint the URDF lacks was reported without a
    line ('bad.srdf.xacro: warning ...'), and as '(line None)' when used. A group written
    literally in the xacro file is located at its line there; one a macro makes from its
    arguments alone (name="${name}") at the macro call that makes it."""
    srdf = _write(
        tmp_path,
        """<robot name="t" xmlns:xacro="http://www.ros.org/wiki/xacro">
        <xacro:arg name="variant" default="base"/>
        <xacro:macro name="hand" params="name">
          <group name="${name}"><joint name="ghost"/></group>
        </xacro:macro>
        <group name="arm"><chain base_link="base" tip_link="tip"/></group>
        <group name="typo"><joint name="j22"/></group>
        <xacro:hand name="made"/>
        </robot>""",
        "t.srdf.xacro",
    )
    from xrdf_tools.convert.sources.srdf import read_srdf

    loaded = load_srdf(srdf)
    assert (loaded.groups["arm"].line, loaded.groups["typo"].line) == (6, 7)
    assert loaded.groups["made"].line is None
    assert loaded.at(loaded.groups["made"]) == (str(srdf), 8)
    d = read_srdf(loaded, tree, group="arm")
    warned = {w.message.split("'")[1]: w.line for w in d.diagnostics if "unused-group" in w.rule}
    assert warned == {"typo": 7, "made": 8}
    with pytest.raises(SourceError) as err:
        read_srdf(loaded, tree, group="made")
    msg = str(err.value)
    assert "group 'made' (line 8): unknown joint 'ghost'" in msg and "None" not in msg
    assert err.value.line == 8
    with pytest.raises(SourceError) as err:
        read_srdf(loaded, tree, group="typo")
    assert err.value.line == 7
    assert "group 'typo' (line 7): unknown joint 'j22' (did you mean 'j2'?)" in str(err.value)


def test_groups_that_include_themselves_warn_unless_used(tree: RobotTree, tmp_path: Path) -> None:
    """Subgroups that include each other in groups the conversion does not use are located
    warnings naming the loop (they were ignored without a word); a used one is an error."""
    srdf = _write(
        tmp_path,
        """<robot name="t">
        <group name="arm"><chain base_link="base" tip_link="tip"/></group>
        <group name="a"><group name="b"/></group>
        <group name="b"><group name="a"/></group>
        <group name="self"><group name="self"/><group name="arm"/></group>
        </robot>""",
    )
    from xrdf_tools.convert.sources.srdf import read_srdf

    d = read_srdf(load_srdf(srdf), tree, group="arm")
    warned = {(w.rule, w.line): w.message for w in d.diagnostics}
    assert (
        "group 'a' includes itself through its subgroups (a -> b -> a)"
        in (warned[("convert-srdf-unused-group", 3)])
    )
    assert "(b -> a -> b)" in warned[("convert-srdf-unused-group", 4)]
    assert "(self -> self)" in warned[("convert-srdf-unused-group", 5)]
    with pytest.raises(SourceError, match="groups include each other: self -> self"):
        read_srdf(load_srdf(srdf), tree, group="self")


def test_a_link_missing_from_many_disable_collisions_is_reported_once(
    tree: RobotTree, tmp_path: Path
) -> None:
    """An SRDF written for another base (LoCoBot's kobuki SRDF on a create3 base) names each
    missing link in a dozen pairs: one warning per link, at its first entry, with the count;
    the pairs of known links are kept."""
    pairs = "".join(
        f'<disable_collisions link1="{a}" link2="caster" reason="Never"/>\n'
        for a in ("a", "b", "c", "tip")
    )
    srdf = _write(
        tmp_path,
        '<robot name="t">\n<group name="arm"><chain base_link="base" tip_link="tip"/></group>\n'
        f'{pairs}<disable_collisions link1="a" link2="b" reason="Adjacent"/>\n'
        '<disable_collisions link1="wheel" link2="a" reason="Never"/>\n</robot>\n',
    )
    from xrdf_tools.convert.sources.srdf import read_srdf

    d = read_srdf(load_srdf(srdf), tree, group="arm")
    unknown = [w for w in d.diagnostics if w.rule == "convert-unknown-link"]
    assert [(w.line, w.message) for w in unknown] == [
        (
            3,
            "'caster' (in 4 disable_collisions entries, first as link2) is not a link of the "
            "URDF; dropped; did you mean 'base'?",
        ),
        (8, "'wheel' (disable_collisions link1) is not a link of the URDF; dropped"),
    ]
    assert d.ignore == {"a": ["b"]}


def test_a_revolute_default_a_full_turn_outside_its_limits_is_turned_in_not_clamped(
    tree: RobotTree, tmp_path: Path
) -> None:
    """A state written as 6 rad for a joint limited to [-1, 1] is the pose of 6 − 2π: taken
    (clamping would give another pose); where no whole turn lands inside, or on a prismatic
    joint, the value is clamped; each is said."""
    from xrdf_tools.convert.core import convert

    srdf = _write(
        tmp_path,
        '<robot name="t">\n<group name="arm"><chain base_link="base" tip_link="tip"/></group>\n'
        '<group_state name="home" group="arm"><joint name="j1" value="6"/>'
        '<joint name="j2" value="3"/><joint name="j3" value="5"/></group_state>\n</robot>\n',
    )
    x, diags = convert(tree, ConvertOptions(srdf=srdf))
    defaults = dict(x.default_joint_positions or {})
    assert defaults["j1"] == pytest.approx(6 - 2 * math.pi)
    assert (defaults["j2"], defaults["j3"]) == (1.0, 1.0)
    said = [d.message for d in diags if d.rule == "convert-clamped-default"]
    assert len(said) == 3
    assert "'j1' is outside its URDF limits [-1, 1]; the same angle a full turn away" in said[0]
    assert "clamped to 1" in said[1] and "clamped to 1" in said[2]
    # each said at the group_state that gives the value (line 3 of the SRDF)
    places = {(d.path, d.line) for d in diags if d.rule == "convert-clamped-default"}
    assert places == {(str(srdf), 3)}
    # an infinite state value turns by no whole turn: clamped (it raised OverflowError)
    inf = _write(tmp_path, srdf.read_text().replace('value="6"', 'value="inf"'), "inf.srdf")
    x, diags = convert(tree, ConvertOptions(srdf=inf))
    assert dict(x.default_joint_positions or {})["j1"] == 1.0
    said_inf = [d for d in diags if d.rule == "convert-clamped-default" and "inf" in d.message]
    assert [(d.path, d.line) for d in said_inf] == [(str(inf), 3)]


def test_a_link_disabled_against_itself_is_said_not_dropped_silently(
    tree: RobotTree, tmp_path: Path
) -> None:
    """``<disable_collisions link1="a" link2="a"/>`` holds no pair (a link is never checked
    against itself): it is said at its line, and the other pairs are kept."""
    srdf = _write(
        tmp_path,
        '<robot name="t">\n<group name="arm"><chain base_link="base" tip_link="tip"/></group>\n'
        '<disable_collisions link1="a" link2="a" reason="Never"/>\n'
        '<disable_collisions link1="a" link2="b" reason="Adjacent"/>\n</robot>\n',
    )
    from xrdf_tools.convert.sources.srdf import read_srdf

    d = read_srdf(load_srdf(srdf), tree, group="arm")
    said = [w for w in d.diagnostics if "twice" in w.message]
    assert [(w.rule, w.line) for w in said] == [("convert-dropped-key", 3)]
    assert "'a'" in said[0].message
    assert d.ignore == {"a": ["b"]}


def test_an_srdf_naming_thousands_of_missing_links_says_ten_and_counts_the_rest(
    tree: RobotTree, tmp_path: Path
) -> None:
    """An SRDF of another robot names 2,000 links this URDF lacks: ten warnings name one each,
    one more counts the others at the first entry of the eleventh (not 2,000 lines)."""
    pairs = "".join(
        f'<disable_collisions link1="a" link2="ghost{i}" reason="Never"/>\n' for i in range(2000)
    )
    srdf = _write(
        tmp_path,
        '<robot name="t">\n<group name="arm"><chain base_link="base" tip_link="tip"/></group>\n'
        f'{pairs}<disable_collisions link1="a" link2="b" reason="Adjacent"/>\n</robot>\n',
    )
    from xrdf_tools.convert.sources.srdf import read_srdf

    d = read_srdf(load_srdf(srdf), tree, group="arm")
    unknown = [w for w in d.diagnostics if w.rule == "convert-unknown-link"]
    assert [w.message.split("'")[1] for w in unknown[:10]] == [f"ghost{i}" for i in range(10)]
    assert len(unknown) == 11
    assert unknown[-1].line == 3 + 10
    assert unknown[-1].message.startswith("1,990 more links of disable_collisions entries")
    assert "ghost10, ghost11, ghost12, ghost13 and 1986 more" in unknown[-1].message
    assert d.ignore == {"a": ["b"]}


def test_virtual_joint_in_a_group_is_known(tree: RobotTree) -> None:
    s = parse_srdf(
        """<robot name="t">
        <virtual_joint name="world_joint" type="planar" parent_frame="odom" child_link="base"/>
        <group name="base"><joint name="world_joint"/></group>
        <group name="body"><group name="base"/><chain base_link="base" tip_link="tip"/></group>
        </robot>"""
    )
    assert cspace_of(s, "base", tree) == []
    assert cspace_of(s, "body", tree) == ["j1", "j2", "j3"]


def test_several_groups_are_one_cspace_in_the_given_order(tree: RobotTree, tmp_path: Path) -> None:
    srdf = _write(
        tmp_path,
        """<robot name="t">
        <group name="arm"><chain base_link="base" tip_link="tip"/></group>
        <group name="side"><chain base_link="base" tip_link="z_side"/></group>
        <group_state name="home" group="arm"><joint name="j1" value="0.2"/></group_state>
        <group_state name="home" group="side"><joint name="zz" value="0.3"/></group_state>
        </robot>""",
    )
    from xrdf_tools.convert.core import convert

    x, _ = convert(tree, ConvertOptions(srdf=srdf, groups=("side", "arm")))
    assert x.cspace is not None and x.cspace.joint_names == ("zz", "j1", "j2", "j3")
    assert x.tool_frames == ("z_side", "tip")
    assert x.default_joint_positions["zz"] == 0.3 and x.default_joint_positions["j1"] == 0.2


def test_an_end_effector_without_parent_group_gives_the_tool_frame_of_the_arm_moving_it(
    tree: RobotTree, tmp_path: Path
) -> None:
    """Interbotix's SRDFs list the arm as joints (no chain) and the end effector without
    parent_group: MoveIt gives it to the group that moves its parent_link, so the tool frame
    is that link ('b'), not the guess at the end of the chain ('c'); a group that does not
    move it gets no such frame."""
    srdf = _write(
        tmp_path,
        """<robot name="t">
        <group name="arm"><joint name="j1"/><joint name="j2"/><joint name="jfix"/></group>
        <group name="gripper"><link name="tip"/></group>
        <group name="side"><joint name="zz"/></group>
        <end_effector name="hand" parent_link="b" group="gripper"/>
        </robot>""",
    )
    from xrdf_tools.convert.core import convert

    x, _ = convert(tree, ConvertOptions(srdf=srdf))
    assert x.cspace is not None and x.cspace.joint_names == ("j1", "j2")
    assert x.tool_frames == ("b",)
    x, _ = convert(tree, ConvertOptions(srdf=srdf, groups=("side",)))
    assert x.tool_frames == ("z_side",)  # the guess at the end of the side chain


def test_an_end_effector_of_a_bigger_group_gives_the_tool_frame_of_its_subgroup_moving_it(
    tree: RobotTree, tmp_path: Path
) -> None:
    """TIAGo++'s SRDF gives each gripper to the arm-and-torso group (`parent_group=
    "arm_left_torso"`); the default group is the arm alone, its subgroup, which moves the
    gripper's parent link last: convert said 'no tool frame in the inputs' and guessed. The
    subgroup carries the end effector; a subgroup that does not move it (the torso) does
    not."""
    srdf = _write(
        tmp_path,
        """<robot name="t">
        <group name="arm"><joint name="j2"/><joint name="jfix"/></group>
        <group name="torso"><joint name="j1"/></group>
        <group name="arm_torso"><group name="arm"/><group name="torso"/></group>
        <group name="gripper"><link name="tip"/></group>
        <end_effector name="hand" parent_link="b" group="gripper" parent_group="arm_torso"/>
        </robot>""",
    )
    from xrdf_tools.convert.core import convert

    x, diags = convert(tree, ConvertOptions(srdf=srdf, groups=("arm",)))
    assert x.tool_frames == ("b",)
    assert not [d for d in diags if d.rule == "convert-chosen-tool-frame"], diags
    x, _ = convert(tree, ConvertOptions(srdf=srdf, groups=("torso",)))
    assert x.tool_frames == ("a",)  # the guess: the torso does not move the hand last


def test_a_group_of_subgroups_without_states_takes_its_subgroups_states(
    tree: RobotTree, tmp_path: Path
) -> None:
    """Baxter's both_arms has no group_state; its arms have one each (left_neutral,
    right_neutral): the two-arm c-space takes both instead of zeros for every joint."""
    srdf = _write(
        tmp_path,
        """<robot name="t">
        <group name="arm"><chain base_link="base" tip_link="tip"/></group>
        <group name="side"><chain base_link="base" tip_link="z_side"/></group>
        <group name="both"><group name="side"/><group name="arm"/></group>
        <group_state name="arm_neutral" group="arm"><joint name="j1" value="0.2"/>
          <joint name="j2" value="-0.4"/></group_state>
        <group_state name="side_neutral" group="side"><joint name="zz" value="0.3"/></group_state>
        </robot>""",
    )
    from xrdf_tools.convert.core import convert

    x, diags = convert(tree, ConvertOptions(srdf=srdf, groups=("both",)))
    assert x.cspace is not None and set(x.cspace.joint_names) == {"zz", "j1", "j2", "j3"}
    assert dict(x.default_joint_positions) == {"zz": 0.3, "j1": 0.2, "j2": -0.4, "j3": 0.75}
    chosen = [d.message for d in diags if d.rule == "convert-chosen-state"]
    assert len(chosen) == 2 and "'side_neutral'" in chosen[0] and "'arm_neutral'" in chosen[1]


def _body_states(tree: RobotTree, srdf: Path) -> tuple[dict[str, float], list[str]]:
    """Convert the group 'body' (c-space j1, j2, j3): its default positions and the
    convert-chosen-state messages."""
    from xrdf_tools.convert.core import convert

    x, diags = convert(tree, ConvertOptions(srdf=srdf, groups=("body",)))
    assert x.cspace is not None and x.cspace.joint_names == ("j1", "j2", "j3")
    chosen = [d.message for d in diags if d.rule == "convert-chosen-state"]
    return dict(x.default_joint_positions), chosen


def test_a_subgroup_without_cspace_joints_takes_no_state(tree: RobotTree, tmp_path: Path) -> None:
    """PR2's whole_body: its 'base' subgroup holds only the planar virtual joint (no c-space
    joint). No state is chosen for it: an empty c-space is not "covered" by every state, so
    an unrelated group's state ('look', first in the file) is neither taken nor reported."""
    srdf = _write(
        tmp_path,
        """<robot name="t">
        <virtual_joint name="world_joint" type="planar" parent_frame="odom" child_link="base"/>
        <group name="base"><joint name="world_joint"/></group>
        <group name="arm"><chain base_link="base" tip_link="tip"/></group>
        <group name="side"><chain base_link="base" tip_link="z_side"/></group>
        <group name="body"><group name="base"/><group name="arm"/></group>
        <group_state name="look" group="side"><joint name="zz" value="0.3"/>
          <joint name="j1" value="0.5"/></group_state>
        <group_state name="arm_neutral" group="arm"><joint name="j1" value="0.2"/>
          <joint name="j2" value="-0.4"/></group_state>
        </robot>""",
    )
    defaults, chosen = _body_states(tree, srdf)
    assert defaults == {"j1": 0.2, "j2": -0.4, "j3": 0.75}
    assert chosen == [
        "default positions from group_state 'arm_neutral' (the state named 'arm_neutral' of "
        "group 'arm')"
    ]


def test_a_home_state_of_a_group_covering_the_cspace_wins_over_an_odd_first_state(
    tree: RobotTree, tmp_path: Path
) -> None:
    """The Husky dual-UR5 SRDF: its arm group's only state is 'right_aggressive' (a pose
    reaching across the other arm), the two-arm group's is 'home_position'. The home state,
    named home among its words and covering the c-space, is the default, and it holds the
    joint outside the c-space there too; the arm's first state was taken before."""
    srdf = _write(
        tmp_path,
        """<robot name="t">
        <group name="arm"><chain base_link="base" tip_link="tip"/></group>
        <group name="side"><joint name="zz"/></group>
        <group name="both"><group name="arm"/><group name="side"/></group>
        <group_state name="aggressive" group="arm"><joint name="j1" value="0.9"/>
          <joint name="j2" value="0.9"/><joint name="j3" value="0.9"/></group_state>
        <group_state name="home_position" group="both"><joint name="j1" value="0.1"/>
          <joint name="j2" value="-0.2"/><joint name="j3" value="0.6"/>
          <joint name="zz" value="0.4"/></group_state>
        </robot>""",
    )
    from xrdf_tools.convert.core import convert

    x, diags = convert(tree, ConvertOptions(srdf=srdf, groups=("arm",)))
    assert dict(x.default_joint_positions) == {"j1": 0.1, "j2": -0.2, "j3": 0.6, "zz": 0.4}
    assert [d.message for d in diags if d.rule == "convert-chosen-state"] == [
        "default positions from group_state 'home_position' (the state named 'home_position' "
        "covering the c-space)"
    ]


def test_a_state_of_a_group_inside_the_cspace_gives_its_joints_defaults(
    tree: RobotTree, tmp_path: Path
) -> None:
    """Galaxea R1's mobile_both_arms: neither it nor its subgroups have a state, but the group
    both_arms, whose joints are all in that c-space, has 'home'. Its values are taken for those
    joints (and said); a state of a group reaching outside the c-space is not."""
    srdf = _write(
        tmp_path,
        """<robot name="t">
        <group name="arm"><joint name="j1"/><joint name="j2"/></group>
        <group name="side"><joint name="zz"/></group>
        <group name="body"><group name="arm"/><joint name="j3"/></group>
        <group name="outside"><joint name="j3"/><joint name="aa"/></group>
        <group name="lower"><joint name="j2"/><joint name="j3"/></group>
        <group_state name="wide" group="outside"><joint name="j3" value="0.9"/>
          <joint name="aa" value="0.1"/></group_state>
        <group_state name="home" group="lower"><joint name="j2" value="-0.4"/>
          <joint name="j3" value="0.75"/></group_state>
        </robot>""",
    )
    defaults, chosen = _body_states(tree, srdf)
    assert defaults == {"j1": 0.0, "j2": -0.4, "j3": 0.75}
    assert chosen == [
        "default positions of j2, j3 from group_state 'home' (the state named 'home' of "
        "group 'lower'; a group inside the c-space)"
    ]


def test_a_state_value_of_a_joint_that_is_no_cspace_coordinate_is_dropped_with_its_kind(
    tree: RobotTree, tmp_path: Path
) -> None:
    """HSR's 'neutral' state sets its passive wrist_ft_sensor_frame_joint: each value of a
    passive, mimic or fixed joint is dropped with a note that says which it is."""
    srdf = _write(
        tmp_path,
        """<robot name="t">
        <group name="arm"><chain base_link="base" tip_link="tip"/></group>
        <group_state name="neutral" group="arm"><joint name="j1" value="0.2"/>
          <joint name="zz" value="0.1"/><joint name="mim" value="0.1"/>
          <joint name="jfix" value="0"/></group_state>
        <passive_joint name="zz"/>
        </robot>""",
    )
    from xrdf_tools.convert.core import convert

    _, diags = convert(tree, ConvertOptions(srdf=srdf, groups=("arm",)))
    notes = [d.message for d in diags if d.rule == "convert-dropped-joint-value"]
    assert [n.split(", which is ")[1].split(";")[0] for n in notes] == [
        "a passive joint",
        "a mimic joint",
        "a fixed joint",
    ]


def test_an_unknown_state_lists_the_states_with_their_groups(
    tree: RobotTree, tmp_path: Path
) -> None:
    """HSR has a 'neutral' state for its arm and one for its head: the list of states says
    whose each is, instead of naming 'neutral' twice."""
    srdf = _write(
        tmp_path,
        """<robot name="t">
        <group name="arm"><chain base_link="base" tip_link="tip"/></group>
        <group name="side"><joint name="zz"/></group>
        <group_state name="neutral" group="arm"><joint name="j1" value="0.2"/></group_state>
        <group_state name="go" group="arm"><joint name="j1" value="0.1"/></group_state>
        <group_state name="neutral" group="side"><joint name="zz" value="0.3"/></group_state>
        </robot>""",
    )
    from xrdf_tools.convert.core import convert

    with pytest.raises(SourceError) as err:
        convert(tree, ConvertOptions(srdf=srdf, state="neutrl"))
    assert str(err.value).endswith(
        "no group_state 'neutrl'; did you mean 'neutral'? "
        "(states: neutral (arm), go (arm), neutral (side))"
    )


def test_joints_and_chain_choose_the_cspace_without_srdf(tree: RobotTree) -> None:
    from xrdf_tools.convert.core import convert

    x, diags = convert(tree, ConvertOptions(joints=("j3", "j1")))
    assert x.cspace is not None and x.cspace.joint_names == ("j3", "j1")  # the given order
    assert x.tool_frames == ("tip",)
    assert "convert-chosen-group" not in {d.rule for d in diags}
    x, _ = convert(tree, ConvertOptions(chains=(("base", "c"), ("base", "z_side"))))
    assert x.cspace is not None and x.cspace.joint_names == ("j1", "j2", "zz")
    assert x.tool_frames == ("c", "z_side")
    for options, match in (
        (ConvertOptions(joints=("j9",)), "--joints: 'j9' is not a joint"),
        (ConvertOptions(joints=("jfix",)), "'jfix' is a fixed joint"),
        (ConvertOptions(joints=("mim",)), "'mim' is a mimic joint"),
        (ConvertOptions(chains=(("tip", "a"),)), "'tip' is not an ancestor of 'a'"),
        (ConvertOptions(chains=(("base", "tpi"),)), "did you mean 'tip'"),
        (ConvertOptions(joints=("j1",), chains=(("base", "c"),)), "not both"),
        (ConvertOptions(joints=("j1",), groups=("arm",)), "--group or --joints/--chain"),
    ):
        with pytest.raises(SourceError, match=match):
            convert(tree, options)


@pytest.mark.parametrize(
    ("srdf", "chosen", "why"),
    [
        (
            "pr2_description/srdf/pr2.srdf",
            "right_arm_and_torso",
            "carrying end effector 'right_eef'",
        ),
        ("talos_data/srdf/talos.srdf", "r_arm", "most actuated joints (7)"),
        ("panda_description/srdf/panda.srdf", "arm", "carrying end effector 'end_effector'"),
    ],
)
def test_default_group_prefers_arms_with_the_most_joints(srdf: str, chosen: str, why: str) -> None:
    """Not PR2's one-joint gripper, not Talos's leg (its only end effectors are its feet)."""
    urdf, srdf_path, _ = _pair(srdf)
    x, diags, _ = convert_files(urdf, ConvertOptions(srdf=srdf_path))
    msg = next(d.message for d in diags if d.rule == "convert-chosen-group")
    assert msg.startswith(f"planning group '{chosen}' chosen: ") and why in msg
    assert "others (actuated joints): " in msg and "use --group" in msg
    assert x.cspace is not None and len(x.cspace.joint_names) >= 7


def _legged_arm(tmp_path: Path, with_arm: bool) -> tuple[RobotTree, str]:
    """A quadruped (four legs of hip, thigh and calf joints) with or without a six-joint arm
    whose names say nothing (a Unitree Z1's joint1…joint6), and an SRDF with a group for the
    legs (12 joints), one per leg and one for the arm."""
    from xrdf_tools.robot.urdf_source import load_urdf

    limit = '<limit lower="-1" upper="1" effort="1" velocity="1"/>'
    links, joints, groups = ['<link name="trunk"/>'], [], []
    for leg in ("lf", "rf", "lh", "rh"):
        parent = "trunk"
        for part in ("hip", "thigh", "calf"):
            links.append(f'<link name="{leg}_{part}"/>')
            joints.append(
                f'<joint name="{leg}_{part}_joint" type="revolute"><parent link="{parent}"/>'
                f'<child link="{leg}_{part}"/><axis xyz="0 1 0"/>{limit}</joint>'
            )
            parent = f"{leg}_{part}"
        groups.append(f'<group name="{leg}_leg"><chain base_link="trunk" tip_link="{parent}"/>')
        groups[-1] += "</group>"
    legs = "".join(f"<joint name='{leg}_{p}_joint'/>" for leg in ("lf", "rf", "lh", "rh")
                   for p in ("hip", "thigh", "calf"))  # fmt: skip
    groups.insert(0, f'<group name="whole_body">{legs}</group>')
    if with_arm:
        parent = "trunk"
        for i in range(1, 7):
            links.append(f'<link name="link{i}"/>')
            joints.append(
                f'<joint name="joint{i}" type="revolute"><parent link="{parent}"/>'
                f'<child link="link{i}"/><axis xyz="0 0 1"/>{limit}</joint>'
            )
            parent = f"link{i}"
        groups.append('<group name="arm"><chain base_link="trunk" tip_link="link6"/></group>')
    urdf = tmp_path / "legged.urdf"
    urdf.write_text(f'<robot name="legged">{"".join(links + joints)}</robot>')
    srdf = tmp_path / "legged.srdf"
    srdf.write_text(f'<robot name="legged">{"".join(groups)}</robot>')
    return as_robot(load_urdf(urdf)).tree, str(srdf)


def test_a_humanoids_arm_wins_over_a_whole_body_joint_list_with_its_legs(tmp_path: Path) -> None:
    """An SRDF with arm chains that also lists every joint, legs and arms, in one group for a
    controller (example-robot-data's simple humanoid has such a 29-joint mapURDFToOpenHRP,
    its arm groups commented out). Its arm joints made it no leg's group, so it won as the
    biggest; a group that moves a leg now comes after those that move none."""
    from xrdf_tools.convert.sources.srdf import choose_group
    from xrdf_tools.robot.urdf_source import load_urdf

    limit = '<limit lower="-1" upper="1" effort="1" velocity="1"/>'
    links, joints = ['<link name="torso"/>'], []
    chains = {"r_leg": ("hip_y", "hip_p", "knee", "ankle_p"), "r_arm": ("shoulder", "elbow")}
    for limb, parts in chains.items():
        parent = "torso"
        for part in parts:
            name = f"{limb}_{part}"
            links.append(f'<link name="{name}_link"/>')
            joints.append(
                f'<joint name="{name}" type="revolute"><parent link="{parent}"/>'
                f'<child link="{name}_link"/><axis xyz="0 1 0"/>{limit}</joint>'
            )
            parent = f"{name}_link"
    urdf = tmp_path / "humanoid.urdf"
    urdf.write_text(f'<robot name="h">{"".join(links + joints)}</robot>')
    every = "".join(f'<joint name="{limb}_{p}"/>' for limb, ps in chains.items() for p in ps)
    srdf = tmp_path / "humanoid.srdf"
    srdf.write_text(
        '<robot name="h"><group name="r_arm"><chain base_link="torso" '
        'tip_link="r_arm_elbow_link"/></group>'
        f'<group name="mapToController">{every}</group></robot>'
    )
    group, why = choose_group(load_srdf(str(srdf)), as_robot(load_urdf(urdf)).tree)
    assert group == "r_arm"
    assert "(2) among the groups that move no leg" in why


def test_a_legged_manipulators_arm_wins_over_its_bigger_legs_group(tmp_path: Path) -> None:
    from xrdf_tools.convert.sources.srdf import choose_group

    tree, path = _legged_arm(tmp_path, with_arm=True)
    group, why = choose_group(load_srdf(path), tree)
    assert group == "arm"
    assert "(6) among the groups that move no leg" in why


def test_a_robot_of_legs_only_still_takes_its_biggest_group(tmp_path: Path) -> None:
    from xrdf_tools.convert.sources.srdf import choose_group

    tree, path = _legged_arm(tmp_path, with_arm=False)
    group, why = choose_group(load_srdf(path), tree)
    assert group == "whole_body"
    assert "not a leg" not in why


def test_example_robot_data_b1_with_z1_plans_the_arm() -> None:
    root = robots_dir()
    urdf, srdf = (
        root / f"b1_description/{d}/b1-z1.{d}" if root else None for d in ("urdf", "srdf")
    )
    if urdf is None or srdf is None or not urdf.is_file() or not srdf.is_file():
        pytest.skip("example-robot-data's b1-z1 is not installed")
    x, _, _ = convert_files(urdf, ConvertOptions(srdf=srdf))
    assert x.cspace is not None
    assert x.cspace.joint_names[:6] == tuple(f"joint{i}" for i in range(1, 7))
    assert not any("hip" in j or "thigh" in j or "calf" in j for j in x.cspace.joint_names)


_TWO_LINKS = """<?xml version="1.0"?>
<robot name="arm">
  <link name="base"/>
  <link name="l1"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>
    <axis xyz="0 0 1"/><limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
</robot>
"""


def test_a_urdf_given_as_the_srdf_is_refused_where_it_defines_a_link(
    runner: CliRunner, tmp_path: Path
) -> None:
    """The URDF and the SRDF of a MoveIt config share the root <robot>: one passed for the
    other read as an SRDF without groups, and convert then said 'no planning group given ...
    change it with --srdf' with exit 0; export srdf --merge wrote disable_collisions into the
    URDF's copy. Both now stop (exit 2) at the first <link>; an SRDF that also carries URDF
    elements is still read."""
    urdf = tmp_path / "arm.urdf"
    urdf.write_text(_TWO_LINKS)
    out = tmp_path / "arm.xrdf"
    r = runner.invoke(app, ["convert", str(urdf), "--srdf", str(urdf), "-o", str(out)])
    assert r.exit_code == 2, r.output
    assert r.stderr.startswith(f"error: {urdf}:3: a URDF, not a MoveIt SRDF: it defines <link ")
    assert not out.exists()
    x = tmp_path / "arm_default.xrdf"
    assert runner.invoke(app, ["convert", str(urdf), "-q", "-o", str(x)]).exit_code == 0
    r = runner.invoke(app, ["export", "srdf", str(x), "--merge", str(urdf), "-o", str(out)])
    assert r.exit_code == 2, r.output
    assert f"{urdf}:3: a URDF, not a MoveIt SRDF" in r.stderr and not out.exists()
    both = tmp_path / "both.srdf"
    both.write_text(
        _TWO_LINKS.replace("</robot>", '<group name="arm"><joint name="j1"/></group></robot>')
    )
    r = runner.invoke(app, ["convert", str(urdf), "--srdf", str(both), "-o", str(out)])
    assert r.exit_code == 0, r.output
    assert "planning group 'arm' chosen" in r.stderr


def _arm_with_sandia_hand(tmp_path: Path) -> tuple[Path, Path]:
    """Atlas with Sandia hands, in small: a 2-joint arm whose hand link carries a palm, and on
    it two finger bases with accelerometer frames (``f0_fixed_accel``) and fingers of three
    and one joints named ``f0_j0`` … (nothing says finger); the SRDF has ``arm`` and a bigger
    ``right_hand`` group (its end effector commented out, as Atlas' is)."""

    def joint(name: str, kind: str, parent: str, child: str) -> str:
        limit = '<limit lower="-1" upper="1" effort="1" velocity="1"/>' if kind != "fixed" else ""
        return (
            f'<joint name="{name}" type="{kind}"><parent link="{parent}"/>'
            f'<child link="{child}"/><origin xyz="0 0 0.1"/><axis xyz="0 1 0"/>{limit}</joint>'
        )

    links = ["torso", "upper", "r_hand", "right_palm", "f0_base", "f0_fixed_accel"]
    links += ["f0_0", "f0_1", "f0_2", "f0_2_accel", "f1_base", "f1_fixed_accel", "f1_0"]
    joints = [
        joint("r_arm_shy", "revolute", "torso", "upper"),
        joint("r_arm_wrx", "revolute", "upper", "r_hand"),
        joint("right_hand_joint", "fixed", "r_hand", "right_palm"),
        joint("f0_base_joint", "fixed", "right_palm", "f0_base"),
        joint("f0_fixed_accel_joint", "fixed", "f0_base", "f0_fixed_accel"),
        joint("f0_j0", "revolute", "f0_base", "f0_0"),
        joint("f0_j1", "revolute", "f0_0", "f0_1"),
        joint("f0_j2", "revolute", "f0_1", "f0_2"),
        joint("f0_2_accel_joint", "fixed", "f0_2", "f0_2_accel"),
        joint("f1_base_joint", "fixed", "right_palm", "f1_base"),
        joint("f1_fixed_accel_joint", "fixed", "f1_base", "f1_fixed_accel"),
        joint("f1_j0", "revolute", "f1_base", "f1_0"),
    ]
    urdf = tmp_path / "atlas.urdf"
    urdf.write_text(
        '<robot name="atlas">'
        + "".join(f'<link name="{n}"/>' for n in links)
        + "".join(joints)
        + "</robot>"
    )
    srdf = tmp_path / "atlas.srdf"
    srdf.write_text(
        '<robot name="atlas">'
        '<group name="arm"><joint name="r_arm_shy"/><joint name="r_arm_wrx"/></group>'
        '<group name="right_hand"><joint name="f0_j0"/><joint name="f0_j1"/>'
        '<joint name="f0_j2"/><joint name="f1_j0"/></group></robot>'
    )
    return urdf, srdf


def test_a_group_named_like_a_hand_is_not_planned_over_a_smaller_arm(
    runner: CliRunner, tmp_path: Path
) -> None:
    """Atlas' SRDF: 'right_hand' (12 finger joints, no end effector naming it) was chosen over
    the 6-joint arms, and its tool frame was a finger's accelerometer frame. A group named
    like a hand, head or wheels now comes after the others (said in the message), and the arm's
    tool frame is the palm, not an accelerometer frame on a finger base."""
    urdf, srdf = _arm_with_sandia_hand(tmp_path)
    out = tmp_path / "atlas.xrdf"
    r = runner.invoke(app, ["convert", str(urdf), "--srdf", str(srdf), "-o", str(out)])
    assert r.exit_code == 0, r.output
    x = parse_xrdf(out.read_text())
    assert x.cspace.joint_names == ("r_arm_shy", "r_arm_wrx")
    assert x.tool_frames == ("right_palm",)
    assert (
        "planning group 'arm' chosen: the group without subgroups with the most actuated "
        "joints (2) (passed over, named like a hand, head or wheels: right_hand)"
    ) in r.stderr
    r = runner.invoke(
        app, ["convert", str(urdf), "--srdf", str(srdf), "--group", "right_hand", "-q"]
    )
    assert r.exit_code == 0 and "f0_j2" in r.stdout  # asked for by name, the hand is planned
    # a group naming a hand with an arm is no hand: the biggest group wins again
    joints = "".join(f'<joint name="{j}"/>' for j in ("r_arm_shy", "r_arm_wrx", "f0_j0", "f0_j1"))
    whole = f'<group name="manipulator_with_hand">{joints}</group></robot>'
    srdf.write_text(srdf.read_text().replace("</robot>", whole))
    r = runner.invoke(app, ["convert", str(urdf), "--srdf", str(srdf), "-o", str(out)])
    assert r.exit_code == 0, r.output
    assert "planning group 'manipulator_with_hand' chosen" in r.stderr


def test_a_state_named_home_in_capitals_is_the_default_state(
    runner: CliRunner, tmp_path: Path
) -> None:
    """Interbotix's gripper group lists Closed, Open, Home (Kinova writes Home, Retract): the
    preferred names matched only in lower case, so the gripper defaulted to 'Closed'."""
    urdf = tmp_path / "arm.urdf"
    urdf.write_text(_TWO_LINKS)
    srdf = tmp_path / "arm.srdf"
    srdf.write_text(
        '<robot name="arm"><group name="arm"><joint name="j1"/></group>'
        + "".join(
            f'<group_state name="{n}" group="arm"><joint name="j1" value="{v}"/></group_state>'
            for n, v in (("Closed", -1.5), ("Open", 1.5), ("Home", 0.25))
        )
        + "</robot>"
    )
    r = runner.invoke(app, ["convert", str(urdf), "--srdf", str(srdf)])
    assert r.exit_code == 0, r.output
    assert parse_xrdf(r.stdout).default_joint_positions["j1"] == 0.25
    assert "group_state 'Home' (the state named 'Home' of group 'arm')" in r.stderr


def test_the_only_group_of_an_srdf_is_a_note_not_a_guess(runner: CliRunner, tmp_path: Path) -> None:
    """UR's, Fanuc's and ABB's MoveIt configs have one planning group: taking it was a warning
    (a guess, counted by --strict) though there was nothing to choose; with a second group it
    is one."""
    urdf = tmp_path / "arm.urdf"
    urdf.write_text(_TWO_LINKS)
    srdf = tmp_path / "arm.srdf"
    one = '<robot name="arm"><group name="manipulator"><joint name="j1"/></group></robot>'
    srdf.write_text(one)
    r = runner.invoke(app, ["convert", str(urdf), "--srdf", str(srdf)])
    assert r.exit_code == 0, r.output
    assert f"{srdf}:1: info convert-chosen-group planning group 'manipulator' chosen" in r.stderr
    srdf.write_text(
        one.replace("</robot>", '<group name="other"><joint name="j1"/></group></robot>')
    )
    r = runner.invoke(app, ["convert", str(urdf), "--srdf", str(srdf)])
    assert r.exit_code == 0, r.output
    assert f"{srdf}:1: warning convert-chosen-group planning group 'manipulator'" in r.stderr


def test_an_srdf_without_groups_is_not_met_with_use_srdf(runner: CliRunner, tmp_path: Path) -> None:
    """UR5's SRDF in example-robot-data has only disable_collisions: `convert --srdf` (and
    `inspect --srdf`) took the longest chain and said 'no planning group given ... change it
    with --chain world:tool0, --joints or --srdf', the flag just given. It says the SRDF has no
    group and that one in it would change the choice."""
    urdf = tmp_path / "arm.urdf"
    urdf.write_text(_TWO_LINKS)
    srdf = tmp_path / "arm.srdf"
    srdf.write_text('<robot name="arm"><disable_collisions link1="base" link2="l1"/></robot>\n')
    r = runner.invoke(app, ["convert", str(urdf), "--srdf", str(srdf)])
    assert r.exit_code == 0, r.output
    (chosen,) = [x for x in r.stderr.splitlines() if "convert-chosen-group" in x]
    assert "no planning group in the SRDF: c-space is the longest" in chosen, chosen
    assert chosen.endswith("--joints or a planning group in the SRDF"), chosen
    r = runner.invoke(app, ["convert", str(urdf)])
    (chosen,) = [x for x in r.stderr.splitlines() if "convert-chosen-group" in x]
    assert "no planning group given: " in chosen and chosen.endswith("--joints or --srdf")


def test_an_end_effector_naming_a_group_the_srdf_lacks_is_dropped_as_moveit_does(
    tree: RobotTree, tmp_path: Path
) -> None:
    """MoveIt's dual-arm Panda SRDF has end effectors for groups 'left_hand'/'right_hand' it
    does not define; srdfdom skips such an end effector. It picked a tool frame here and was
    named as the reason for a group choice, silently."""
    from xrdf_tools.convert.sources.srdf import read_srdf

    srdf = _write(
        tmp_path,
        """<robot name="t">
        <group name="arm"><chain base_link="base" tip_link="tip"/></group>
        <end_effector name="hand" parent_link="b" group="hnd"/>
        <end_effector name="side" parent_link="tip" group="arm" parent_group="armm"/>
        <end_effector name="ok" parent_link="c" group="arm"/>
        </robot>""",
    )
    d = read_srdf(load_srdf(srdf), tree, group="arm")
    said = [(w.line, w.message) for w in d.diagnostics if w.rule == "convert-srdf-end-effector"]
    assert [line for line, _ in said] == [3, 4], d.diagnostics
    assert "end_effector 'hand' names group 'hnd', which the SRDF does not define" in said[0][1]
    assert "MoveIt skips it" in said[0][1]
    assert "parent_group 'armm'" in said[1][1] and "did you mean 'arm'" in said[1][1]
    # the skipped end effector's parent link is no tool frame; the kept one's is
    assert d.tool_frames == ["c", "tip"]


def test_joints_outside_the_cspace_are_held_at_their_own_groups_home(
    tree: RobotTree, tmp_path: Path
) -> None:
    """MoveIt's dual-arm Panda converted for its left arm held the right arm at 0 although
    the SRDF gives the right arm a 'ready' state: every reader holds a joint outside the
    c-space at its default, and the mask is computed there. A group's home/ready/default
    state is taken for such joints; any other pose of theirs ('reach') is not."""
    from xrdf_tools.convert.sources.srdf import read_srdf

    def defaults(side_states: str) -> tuple[dict[str, float], list[str]]:
        srdf = _write(
            tmp_path,
            f"""<robot name="t">
            <group name="arm"><chain base_link="base" tip_link="tip"/></group>
            <group name="side"><joint name="zz"/></group>
            <group_state name="ready" group="arm"><joint name="j1" value="0.1"/></group_state>
            {side_states}
            </robot>""",
        )
        d = read_srdf(load_srdf(srdf), tree, group="arm")
        said = [w.message for w in d.diagnostics if w.rule == "convert-chosen-state"]
        return d.defaults, said

    held, said = defaults(
        '<group_state name="reach" group="side"><joint name="zz" value="0.9"/></group_state>'
        '<group_state name="Home" group="side"><joint name="zz" value="0.4"/></group_state>'
    )
    assert held == {"j1": 0.1, "zz": 0.4}
    assert any("joints outside the c-space (zz) held at group_state 'Home'" in m for m in said)
    held, said = defaults(
        '<group_state name="reach" group="side"><joint name="zz" value="0.9"/></group_state>'
    )
    assert held == {"j1": 0.1} and not any("outside the c-space" in m for m in said)
    # Baxter: each arm's only state is its 'neutral' pose (Rethink's rest pose); the left
    # arm's conversion held the right one straight out at 0
    held, said = defaults(
        '<group_state name="reach" group="side"><joint name="zz" value="0.9"/></group_state>'
        '<group_state name="right_neutral" group="side"><joint name="zz" value="0.3"/>'
        "</group_state>"
    )
    assert held == {"j1": 0.1, "zz": 0.3}
    assert any("(zz) held at group_state 'right_neutral'" in m for m in said), said


def test_a_state_value_for_the_srdfs_virtual_joint_is_a_note_not_an_unknown_joint(
    tree: RobotTree, tmp_path: Path
) -> None:
    """Legged robots' SRDFs (ANYmal, Go2, B1) give the floating virtual joint a value in their
    states ('0 0 0.528 0 0 0 1'): the base's pose, which no XRDF holds. It is dropped with a
    note naming it, not warned about as "not a joint of the URDF"."""
    from xrdf_tools.convert.core import convert

    srdf = _write(
        tmp_path,
        '<robot name="t">\n<group name="arm"><chain base_link="base" tip_link="tip"/></group>\n'
        '<group_state name="standing" group="arm"><joint name="root_joint" '
        'value="0 0 0.5 0 0 0 1"/><joint name="j1" value="0.5"/></group_state>\n'
        '<virtual_joint name="root_joint" type="floating" parent_frame="world" '
        'child_link="base"/>\n</robot>\n',
    )
    x, diags = convert(tree, ConvertOptions(srdf=srdf))
    assert dict(x.default_joint_positions or {})["j1"] == 0.5
    assert not [d for d in diags if d.rule == "convert-unknown-joint"]
    (note,) = [d for d in diags if "root_joint" in d.message and "group_state" in d.message]
    assert note.rule == "convert-dropped-joint-value" and note.severity.value == "info"
    assert "floating virtual joint 'root_joint' (where 'base' stands)" in note.message
    assert (note.path, note.line) == (str(srdf), 3)


def test_a_base_pose_in_a_state_without_a_virtual_joint_is_a_note(
    tree: RobotTree, tmp_path: Path
) -> None:
    """Bolt's SRDF (example-robot-data) declares no virtual joint, yet its state gives
    'root_joint' seven numbers, as Pinocchio's free-flyer root joint takes: a base's pose, not
    a misspelt joint. It is dropped with a note, not warned about as an unknown joint."""
    from xrdf_tools.convert.core import convert

    srdf = _write(
        tmp_path,
        '<robot name="t">\n<group name="arm"><chain base_link="base" tip_link="tip"/></group>\n'
        '<group_state name="standing" group="arm"><joint name="root_joint" '
        'value="0. 0. 0.35 0. 0. 0. 1."/><joint name="j1" value="0.5"/></group_state>\n'
        "</robot>\n",
    )
    x, diags = convert(tree, ConvertOptions(srdf=srdf))
    assert dict(x.default_joint_positions or {})["j1"] == 0.5
    assert not [d for d in diags if d.rule == "convert-unknown-joint"]
    (note,) = [d for d in diags if "root_joint" in d.message and "group_state" in d.message]
    assert note.rule == "convert-dropped-joint-value" and note.severity.value == "info"
    assert "several numbers" in note.message and "a base's pose" in note.message
    assert (note.path, note.line) == (str(srdf), 3)
    # one number for a joint the URDF lacks is still a warning (a misspelt or stale joint)
    srdf.write_text(srdf.read_text().replace("0. 0. 0.35 0. 0. 0. 1.", "0.2"))
    _, diags = convert(tree, ConvertOptions(srdf=srdf))
    assert [d for d in diags if d.rule == "convert-unknown-joint" and "root_joint" in d.message]


def test_a_chain_tip_taken_as_tool_frame_names_the_frames_fixed_to_it(
    tree: RobotTree, tmp_path: Path
) -> None:
    """The Ridgeback + Panda SRDF's arm chain ends at panda_link7, with panda_link8 and the
    hand fixed below it and no end effector on the group: the tip became the tool frame
    without a word, where the same robot without an SRDF names the alternatives."""
    from xrdf_tools.convert.core import convert

    group = '<group name="arm"><chain base_link="base" tip_link="b"/></group>\n'
    srdf = _write(tmp_path, f'<robot name="t">\n{group}</robot>\n')
    x, diags = convert(tree, ConvertOptions(srdf=srdf))
    assert list(x.tool_frames or []) == ["b"]
    (note,) = [d for d in diags if d.rule == "convert-chosen-tool-frame"]
    assert note.severity.value == "info" and (note.path, note.line) == (str(srdf), 2)
    assert "'b', the tip of group 'arm'" in note.message and "rigidly attached: c" in note.message
    assert "--tool-frame" in note.message
    # an end effector on the group is the SRDF's choice: nothing to say
    srdf.write_text(
        f'<robot name="t">\n{group}<group name="hand"><link name="c"/></group>\n'
        '<end_effector name="ee" parent_link="c" group="hand" parent_group="arm"/>\n</robot>\n'
    )
    x, diags = convert(tree, ConvertOptions(srdf=srdf))
    assert not [d for d in diags if d.rule == "convert-chosen-tool-frame"]


def test_an_end_effector_s_parent_link_names_the_tcp_fixed_below_it() -> None:
    """PR2's right_eef sits on r_wrist_roll_link, with r_gripper_tool_frame fixed below it:
    the SRDF's choice stays the tool frame, and a note names the TCP and the flag that takes
    it (it was said nowhere)."""
    from tests.robots import robot_urdf
    from xrdf_tools.convert.core import convert
    from xrdf_tools.robot.xacro_source import load_robot

    urdf = robot_urdf("pr2")
    srdf = urdf.parent.parent / "srdf" / "pr2.srdf"
    x, diags = convert(load_robot(urdf), ConvertOptions(srdf=srdf, groups=("right_arm",)))
    assert list(x.tool_frames or []) == ["r_wrist_roll_link"]
    (note,) = [d for d in diags if d.rule == "convert-chosen-tool-frame"]
    assert note.severity.value == "info" and note.path == str(srdf)
    written = srdf.read_text().splitlines()[(note.line or 0) - 1]
    assert "<end_effector" in written and 'name="right_eef"' in written  # located at it
    assert "r_gripper_tool_frame" in note.message
    assert "--tool-frame r_gripper_tool_frame" in note.message
