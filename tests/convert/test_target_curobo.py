"""``--target curobo``: the c-space put in URDF order (states kept by name), checked before
fitting; the README's two-arm PR2 example passes ``xrdf lint --target curobo``."""

from __future__ import annotations

from pathlib import Path

import pytest
from typer.testing import CliRunner

from tests.robots import robots_dir
from xrdf_tools.cli import app
from xrdf_tools.convert.core import ConvertOptions, convert
from xrdf_tools.convert.sources.srdf import load_srdf
from xrdf_tools.convert.targets import target_errors
from xrdf_tools.robot.core import Robot, as_robot
from xrdf_tools.robot.urdf_source import load_urdf
from xrdf_tools.xrdf.io import dump_xrdf


def _pr2() -> tuple[Path, Path]:
    root = robots_dir()
    if root is None or not (root / "pr2_description/urdf/pr2.urdf").is_file():
        pytest.skip("example-robot-data has no pr2")
    return root / "pr2_description/urdf/pr2.urdf", root / "pr2_description/srdf/pr2.srdf"


@pytest.fixture(scope="module")
def pr2() -> tuple[Robot, Path, Path]:
    urdf, srdf = _pr2()
    return as_robot(load_urdf(urdf)), urdf, srdf


def _states(srdf: Path) -> dict[str, float]:
    return {j: v for st in load_srdf(srdf).group_states for j, v in st.values}


def test_cspace_in_urdf_order_states_kept_by_name(pr2: tuple[Robot, Path, Path]) -> None:
    robot, _, srdf = pr2
    groups = ("left_arm", "right_arm")
    given, _ = convert(robot, ConvertOptions(srdf=srdf, groups=groups))
    fixed, diags = convert(robot, ConvertOptions(srdf=srdf, groups=groups, target="curobo"))
    assert given.cspace is not None and fixed.cspace is not None
    # the same joints; for curobo in the order of the URDF's <joint> elements
    assert sorted(given.cspace.joint_names) == sorted(fixed.cspace.joint_names)
    urdf_order = [j for j in robot.joints if j in set(given.cspace.joint_names)]
    assert list(fixed.cspace.joint_names) == urdf_order != list(given.cspace.joint_names)
    # every default position is the SRDF state's value of that joint
    states = _states(srdf)
    defaults = dict(fixed.default_joint_positions or {})
    assert {j: defaults[j] for j in urdf_order} == {j: states[j] for j in urdf_order}
    said = [d for d in diags if d.rule == "convert-cspace-order"]
    assert len(said) == 1 and "URDF" in said[0].message and "kept by joint name" in said[0].message
    # two readers named: "cuRobo and Isaac ROS cuMotion fills" was no sentence
    assert "positions are filled in URDF order by cuRobo" in said[0].message


def test_target_errors_before_fitting(pr2: tuple[Robot, Path, Path]) -> None:
    """An XRDF in c-space order fails curobo whatever spheres it gets: found before fitting;
    missing spheres (what fitting adds) are not counted."""
    robot, _, srdf = pr2
    groups = ("left_arm", "right_arm")
    given, _ = convert(robot, ConvertOptions(srdf=srdf, groups=groups))
    errors = target_errors(dump_xrdf(given), robot, "curobo", "pr2.xrdf")
    assert [d.rule for d in errors] == ["curobo-default-order", "convert-target-check"]
    assert "stopped before fitting" in errors[-1].message
    fixed, _ = convert(robot, ConvertOptions(srdf=srdf, groups=groups, target="curobo"))
    assert not fixed.world_collision_spheres()  # no spheres yet: not a target error here
    assert target_errors(dump_xrdf(fixed), robot, "curobo", "pr2.xrdf") == []
    assert target_errors(dump_xrdf(given), robot, None, "pr2.xrdf") == []


def test_readme_pr2_example_passes_lint_for_curobo(runner: CliRunner, tmp_path: Path) -> None:
    urdf, srdf = _pr2()
    out = tmp_path / "pr2.xrdf"
    args = ["convert", str(urdf), "--srdf", str(srdf), "--group", "left_arm"]
    # no --fit-spheres here (the README's example fits them; too slow for this test): the
    # links without spheres (and a group without any) are errors for a planner, so convert
    # would fail on them (--no-lint writes the file) and lint leaves those rules out
    result = runner.invoke(
        app, [*args, "--group", "right_arm", "--target", "curobo", "--no-lint", "-o", str(out)]
    )
    assert result.exit_code == 0, result.output
    assert "convert-cspace-order" in result.output
    lint = runner.invoke(
        app,
        [
            *("lint", "--target", "curobo", str(out), "--urdf", str(urdf)),
            *("--ignore", "mesh-without-spheres", "--ignore", "empty-collision-group"),
        ],
    )
    assert lint.exit_code == 0, lint.output
    assert "curobo-default-order" not in lint.output


def test_a_planning_target_without_any_sphere_fails_and_writes_nothing(
    runner: CliRunner, tmp_path: Path
) -> None:
    """`convert --target curobo` without spheres wrote an XRDF that cuRobo loads with
    collision checking off, and exited 0, while `xrdf lint --target curobo` of that file
    exits 1: the empty group is an error for a planning reader. One error line (not one per
    link) and a closing line naming --fit-spheres; for Isaac Sim (spheres drawn in its
    editor) it stays a warning."""
    from tests.paths import FIXTURES

    demo = FIXTURES / "demo_arm"
    args = ["convert", str(demo / "demo_arm.urdf"), "--srdf", str(demo / "demo_arm.srdf")]
    out = tmp_path / "demo.xrdf"
    r = runner.invoke(app, [*args, "--target", "curobo", "-o", str(out)])
    assert r.exit_code == 1 and not out.exists()
    errors = [x for x in r.stderr.splitlines() if " error " in x or x.startswith("error:")]
    assert len(errors) == 2 and "error empty-collision-group" in errors[0], r.stderr
    assert "no collision spheres at all: --fit-spheres fits them" in errors[1]
    assert "mesh-without-spheres" not in r.stderr
    r = runner.invoke(app, [*args, "--target", "isaac-sim", "-o", str(out)])
    assert r.exit_code == 0 and out.exists()
    assert "warning empty-collision-group" not in r.stderr  # said once, by convert-no-spheres


def test_a_urdf_velocity_of_zero_stops_curobo_before_fitting(
    runner: CliRunner, tmp_path: Path
) -> None:
    """AUBO's i5 URDF writes velocity="0" on every joint (the real limits are in MoveIt's
    joint_limits.yaml, which cuRobo never reads): convert --target curobo exited 0 with an XRDF
    whose arm cuRobo cannot move. It is an error for curobo, found before fitting, naming the
    joint and its URDF line; without a target a warning, and the file is written."""
    from tests.paths import FIXTURES

    urdf = FIXTURES / "urdf" / "zero_velocity_arm.urdf"
    out = tmp_path / "arm.xrdf"
    args = ["convert", str(urdf), "--fit-spheres", "-o", str(out)]
    r = runner.invoke(app, [*args, "--target", "curobo"])
    assert r.exit_code == 1 and not out.exists(), r.stderr
    zero = [x for x in r.stderr.splitlines() if "curobo-zero-velocity" in x]
    assert len(zero) == 1 and " error " in zero[0], r.stderr
    # joint2 (velocity 2.0) and joint3 (no velocity: cuRobo assumes one) are fine
    assert "'joint1' (line 36)" in zero[0] and "in zero_velocity_arm.urdf" in zero[0]
    assert "stopped before fitting" in r.stderr and "convert-fitted-spheres" not in r.stderr
    # --fit-spheres was given: no "NO COLLISION SPHERES ... add spheres (--fit-spheres)"
    assert "convert-no-spheres" not in r.stderr, r.stderr
    # the stop has no line, so it is printed before the errors it counts: it said "above"
    lines = r.stderr.splitlines()
    stop = next(i for i, x in enumerate(lines) if "stopped before fitting" in x)
    assert stop < lines.index(zero[0]) and "above" not in lines[stop], r.stderr
    # the closing line counts that one error, not the stop that reports it too
    assert "has 1 lint error(s) against the URDF" in r.stderr.splitlines()[-1], r.stderr
    # the error is placed at a line of arm.xrdf, which does not exist: the last line says so
    assert zero[0].startswith(f"{out}:") and not out.exists()
    assert "nothing was written: their lines are those of the XRDF convert would write" in (
        " ".join(r.stderr.split())
    )
    r = runner.invoke(app, args)
    assert r.exit_code == 0 and out.exists(), r.stderr
    assert "warning curobo-zero-velocity" in r.stderr


def test_a_zero_effort_written_by_an_included_macro_names_that_file(
    runner: CliRunner, tmp_path: Path
) -> None:
    """KUKA's LBR iiwa 14 xacro writes effort="0" on every joint in lbr_iiwa14_r820_macro.xacro:
    convert --target curobo stopped at a line of the XRDF it did not write, naming only the
    top xacro file; the joints are now placed where the macro writes them, and the message says
    the limits are in that file."""
    (tmp_path / "arm_macro.xacro").write_text(
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '<xacro:macro name="arm" params="prefix">\n'
        '<link name="${prefix}base"/><link name="${prefix}link1">\n'
        '<collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision></link>\n'
        '<joint name="${prefix}joint_1" type="revolute">\n'
        '<parent link="${prefix}base"/><child link="${prefix}link1"/>\n'
        '<limit effort="0" lower="-1" upper="1" velocity="1"/></joint>\n'
        "</xacro:macro></robot>\n"
    )
    robot = tmp_path / "arm.urdf.xacro"
    robot.write_text(
        '<robot name="arm" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '<xacro:include filename="arm_macro.xacro"/>\n<xacro:arm prefix=""/>\n</robot>\n'
    )
    r = runner.invoke(app, ["convert", str(robot), "--fit-spheres", "--target", "curobo"])
    assert r.exit_code == 1, r.stderr
    zero = [x for x in r.stderr.splitlines() if "curobo-zero-velocity" in x]
    assert len(zero) == 1 and "'joint_1' (arm_macro.xacro:5)" in zero[0], r.stderr
    # the <limit> to edit is in the macro file, not in the top file (Motoman SDA10F)
    assert '<limit effort="0"> in arm_macro.xacro:' in zero[0], r.stderr


def _two_arms_with_tilted_shoulders(tmp_path: Path) -> Path:
    """A torso with two one-joint arms whose shoulder axes are tilted, as Rainbow's RB-Y1
    writes them (``0 0.939693 ±0.34202``): cuRobo's loader raises on either."""

    def arm(side: str, y: float, axis: str) -> str:
        return (
            f'<link name="{side}_link1"><collision><geometry><box size="0.05 0.05 0.3"/>'
            f'</geometry></collision></link><link name="{side}_tool"/>\n'
            f'<joint name="{side}_shoulder" type="revolute"><parent link="torso"/>'
            f'<child link="{side}_link1"/><origin xyz="0 {y} 0.5"/><axis xyz="{axis}"/>'
            '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint>\n'
            f'<joint name="{side}_tool_joint" type="fixed"><parent link="{side}_link1"/>'
            f'<child link="{side}_tool"/><origin xyz="0 0 0.3"/></joint>\n'
        )

    urdf = tmp_path / "two_arms.urdf"
    urdf.write_text(
        '<robot name="two_arms">\n<link name="torso"><collision><geometry>'
        '<box size="0.2 0.2 0.4"/></geometry></collision></link>\n'
        + arm("left", 0.3, "0 0.939693 0.34202")
        + arm("right", -0.3, "0 0.939693 -0.34202")
        + "</robot>\n"
    )
    return urdf


def test_a_tilted_cspace_axis_stops_curobo_before_fitting(
    runner: CliRunner, tmp_path: Path
) -> None:
    """RB-Y1: `convert --fit-spheres --target curobo` fitted and sampled the mask before
    failing on the shoulder's axis (its finding had no section, so the check before fitting
    passed it by). The c-space joint's axis stops the command before fitting, at its entry."""
    urdf = _two_arms_with_tilted_shoulders(tmp_path)
    out = tmp_path / "arm.xrdf"
    args = ["convert", str(urdf), "--chain", "torso:left_tool", "--fit-spheres"]
    r = runner.invoke(app, [*args, "--target", "curobo", "--samples", "100", "-o", str(out)])
    assert r.exit_code == 1 and not out.exists(), r.stderr
    assert "stopped before fitting" in r.stderr and "convert-fitted-spheres" not in r.stderr
    axis = [x for x in r.stderr.splitlines() if "curobo-joint-axis" in x]
    assert len(axis) == 1 and "'left_shoulder' (line" in axis[0], r.stderr
    assert " error " in axis[0] and "held outside" not in axis[0]


def test_a_tilted_axis_of_the_held_arm_is_placed_and_explained(tmp_path: Path) -> None:
    """The other arm, held outside the c-space, is built by cuRobo when it carries spheres:
    its finding names the sphere frame that brings it in, at the collision group (fitting
    decides it), not at line 1 with no reason."""
    from xrdf_tools.lint import lint_text

    urdf = _two_arms_with_tilted_shoulders(tmp_path)
    robot = as_robot(load_urdf(urdf))
    x, _ = convert(robot, ConvertOptions(chains=(("torso", "left_tool"),)))
    sphere = "right_link1:\n        - center: [0.0, 0.0, 0.1]\n          radius: 0.05"
    text = dump_xrdf(x)
    assert text.count("spheres: {}") == 1, text
    text = text.replace("spheres: {}", f"spheres:\n      {sphere}")
    found = [
        d
        for d in lint_text(text, "arm.xrdf", urdf_model=robot, target="curobo")
        if d.rule == "curobo-joint-axis"
    ]
    by_joint = {d.message.split("'")[1]: d for d in found}
    assert set(by_joint) == {"left_shoulder", "right_shoulder"}, found
    held = by_joint["right_shoulder"]
    assert "held outside the c-space on the chain to sphere frame 'right_link1'" in held.message
    assert held.key_path == "collision.geometry" and held.line not in (None, 1), held
    assert by_joint["left_shoulder"].key_path.startswith("cspace.joint_names[")


def test_an_axis_a_rounding_error_off_a_coordinate_axis_is_printed_as_written(
    runner: CliRunner, tmp_path: Path
) -> None:
    """iCub's creo2urdf model writes `l_shoulder_yaw`'s axis as `-4.44e-16 1.69e-15
    1.0000000000000004`; cuRobo's parser needs a component exactly ±1, and the error printed
    the axis as `... 1`, hiding why. It prints the component as written and says to write
    the axis exactly; a truly tilted axis still says to rotate the origin."""
    urdf = _two_arms_with_tilted_shoulders(tmp_path)
    text = urdf.read_text().replace(
        "0 0.939693 0.34202", "-4.440892098500626e-16 0 1.0000000000000004"
    )
    urdf.write_text(text)
    args = ["convert", str(urdf), "--chain", "torso:left_tool", "--target", "curobo"]
    r = runner.invoke(app, [*args, "-o", str(tmp_path / "arm.xrdf")])
    assert r.exit_code == 1, r.stderr
    (axis,) = [x for x in r.stderr.splitlines() if "curobo-joint-axis" in x]
    assert '<axis xyz="-4.44089e-16 0 1.0000000000000004">' in axis, axis
    assert 'it is z but for rounding: write it exactly, <axis xyz="0 0 1">' in axis, axis
    args[3] = "torso:right_tool"
    r = runner.invoke(app, [*args, "-o", str(tmp_path / "arm.xrdf")])
    (axis,) = [x for x in r.stderr.splitlines() if "curobo-joint-axis" in x]
    assert '<axis xyz="0 0.939693 -0.34202">' in axis and "rotate the joint's origin" in axis


_GRIPPER = """<robot name="jaw">
  <link name="base"><collision><geometry><box size="0.1 0.1 0.05"/></geometry></collision></link>
  <link name="left_finger"><collision><geometry><box size="0.02 0.02 0.06"/></geometry>
  </collision></link>
  <link name="right_finger"><collision><geometry><box size="0.02 0.02 0.06"/></geometry>
  </collision></link>
  <joint name="finger_joint" type="prismatic"><parent link="base"/>
    <child link="left_finger"/><axis xyz="1 0 0"/>
    <limit lower="0" upper="0.04" velocity="0.1" effort="10"/></joint>
  <joint name="right_finger_joint" type="prismatic"><parent link="base"/>
    <child link="right_finger"/><axis xyz="-1 0 0"/><mimic joint="finger_joint"/>
    <limit lower="0" upper="0.04" velocity="0.1" effort="10"/></joint>
</robot>
"""


def test_a_gripper_alone_says_first_that_its_cspace_is_empty(
    runner: CliRunner, tmp_path: Path
) -> None:
    """A Robotiq 2F-140 on its own: the default c-space is empty (every actuated joint is a
    gripper's). `--target curobo` stopped on "no tool_frames", and the reason (an empty
    c-space, which --joints chooses) came only in a warning among others; that warning spoke
    of a "chosen group" where none was chosen. The stop now names it."""
    urdf = tmp_path / "jaw.urdf"
    urdf.write_text(_GRIPPER)
    out = tmp_path / "jaw.xrdf"
    args = ["convert", str(urdf), "--target", "curobo", "-o", str(out)]
    r = runner.invoke(app, [*args, "--fit-spheres"])
    assert r.exit_code == 1 and not out.exists(), r.stderr
    (stop,) = [x for x in r.stderr.splitlines() if "stopped before fitting" in x]
    assert "the c-space is empty" in stop and "--joints" in stop, r.stderr
    r = runner.invoke(app, args)  # no fit: the closing line says it
    assert r.exit_code == 1 and not out.exists(), r.stderr
    assert "the c-space is empty: choose its joints" in r.stderr.splitlines()[-1], r.stderr
    r = runner.invoke(app, ["convert", str(urdf), "-o", str(out)])
    assert r.exit_code == 0, r.stderr
    (empty,) = [x for x in r.stderr.splitlines() if "convert-empty-cspace" in x]
    assert "chosen group" not in empty and "--joints" in empty, empty
    # with a c-space chosen, the stop says nothing of it
    r = runner.invoke(
        app,
        ["convert", str(urdf), "--joints", "finger_joint", "--target", "curobo", "-o", str(out)],
    )
    assert "the c-space is empty" not in r.stderr, r.stderr
