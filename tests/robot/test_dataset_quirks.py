"""URDFs as robot collections ship them: each quirk a real description has, reproduced in a
minimal robot, and read as ROS reads it (a located warning) or refused with a located error."""

from __future__ import annotations

import shlex
from pathlib import Path

import pytest
import yaml
from typer.testing import CliRunner

from xrdf_tools.cli import app
from xrdf_tools.robot.chains import default_cspace
from xrdf_tools.robot.tree import RobotTree
from xrdf_tools.util.errors import SourceError
from xrdf_tools.xrdf.io import load_xrdf

ARM = """<robot name="r">
  <link name="base"><collision><geometry><box size="0.2 0.2 0.1"/></geometry></collision></link>
  <link name="arm"{attr}><collision><geometry><box size=".05 .05 .3"/></geometry></collision></link>
  <joint name="j" type="revolute"><parent link="base"/><child link="arm"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
{extra}</robot>
"""


def _run(runner: CliRunner, *args: str | Path) -> tuple[int, str]:
    r = runner.invoke(app, [str(a) for a in args])
    return r.exit_code, r.output


def test_an_undeclared_namespace_prefix_in_a_gazebo_block_is_a_located_warning(
    runner: CliRunner, tmp_path: Path
) -> None:
    # robot-assets' fetch.urdf: <sensor:camera> in a <gazebo> block, no xmlns:sensor
    urdf = tmp_path / "r.urdf"
    gazebo = (
        '<gazebo reference="arm">\n'
        '  <sensor:camera name="rgb"><hfov>50</hfov></sensor:camera>\n</gazebo>\n'
    )
    urdf.write_text(ARM.format(attr=' gazebo:tag="x"', extra=gazebo))
    out = tmp_path / "r.xrdf"
    code, text = _run(runner, "convert", urdf, "-o", out)
    assert code == 0, text
    warnings = [line for line in text.splitlines() if "urdf-prefix-undeclared" in line]
    assert [w.split(": warning")[0].rsplit(":", 1)[0] for w in warnings] == [
        f"{urdf}:3",
        f"{urdf}:8",
    ]
    assert "Namespace prefix sensor on camera is not defined (no xmlns:sensor)" in warnings[1]
    assert "Namespace prefix gazebo for tag on link is not defined" in warnings[0]
    cspace = load_xrdf(out).cspace
    assert cspace is not None and cspace.joint_names == ("j",)
    code, text = _run(runner, "inspect", urdf)
    assert code == 0, text
    assert "c-space #1" in text


def test_an_undeclared_prefix_next_to_a_real_xml_error_still_fails_at_the_error(
    runner: CliRunner, tmp_path: Path
) -> None:
    urdf = tmp_path / "r.urdf"
    urdf.write_text(ARM.format(attr="", extra="<gazebo><sensor:camera></gazebo>\n"))
    code, text = _run(runner, "inspect", urdf)
    assert code == 2, text
    assert f"{urdf}:7:33: malformed XML: Opening and ending tag mismatch" in text
    assert "Traceback" not in text


def test_an_undeclared_xacro_prefix_is_an_error_saying_what_to_declare(
    runner: CliRunner, tmp_path: Path
) -> None:
    urdf = tmp_path / "r.urdf"
    urdf.write_text(ARM.format(attr="", extra='<xacro:property name="p" value="1"/>\n'))
    code, text = _run(runner, "inspect", urdf)
    assert code == 2, text
    assert f"{urdf}:7:" in text
    assert 'must declare xmlns:xacro="http://www.ros.org/wiki/xacro"' in text


def _joint(name: str, parent: str, child: str, kind: str = "revolute") -> str:
    limit = '<limit lower="-1" upper="1" velocity="1" effort="1"/>' if kind != "fixed" else ""
    return (
        f'<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>'
        f'<axis xyz="0 0 1"/>{limit}</joint>'
    )


def _tree(tmp_path: Path, links: list[str], joints: list[str]) -> Path:
    body = "".join(f'<link name="{lk}"/>' for lk in links)
    urdf = tmp_path / "r.urdf"
    urdf.write_text(f'<robot name="r">{body}{"".join(joints)}</robot>')
    return urdf


def _robot_tree(tmp_path: Path, links: list[str], joints: list[str]) -> RobotTree:
    """The tree of the robot :func:`_tree` writes, as the default c-space reads it."""
    from xrdf_tools.robot.core import as_robot
    from xrdf_tools.robot.urdf_source import load_urdf

    return as_robot(load_urdf(_tree(tmp_path, links, joints))).tree


def test_a_pan_tilt_unit_that_carries_a_tool_is_a_wrist_and_a_camera_one_a_head(
    tmp_path: Path,
) -> None:
    # Schunk's PW70 powerball wrist: pw70_pan_joint, pw70_tilt_joint, then pw70_tool_link
    from xrdf_tools.robot.chains import default_cspace, joint_roles

    links = ["world", "pw70_link", "pw70_pan_link", "pw70_tilt_link", "pw70_tool_link"]
    wrist = [
        _joint("pw70_joint", "world", "pw70_link", "fixed"),
        _joint("pw70_pan_joint", "pw70_link", "pw70_pan_link"),
        _joint("pw70_tilt_joint", "pw70_pan_link", "pw70_tilt_link"),
        _joint("pw70_tool_joint", "pw70_tilt_link", "pw70_tool_link", "fixed"),
    ]
    tree = _robot_tree(tmp_path, links, wrist)
    assert joint_roles(tree) == {}
    choice = default_cspace(tree)
    assert choice.joints == ("pw70_pan_joint", "pw70_tilt_joint")
    assert choice.tool is not None and choice.tool.frame == "pw70_tool_link"
    # the same unit carrying a camera frame is a head; so is a head_pan joint with a tool
    links = ["base", "pan", "tilt", "camera_link", "tool_link"]
    head = [
        _joint("ptu_pan", "base", "pan"),
        _joint("ptu_tilt", "pan", "tilt"),
        _joint("cam", "tilt", "camera_link", "fixed"),
        _joint("head_pan", "base", "tool_link"),
    ]
    tree = _robot_tree(tmp_path, links, head)
    assert joint_roles(tree) == {"ptu_pan": "head", "ptu_tilt": "head", "head_pan": "head"}


def test_an_empty_default_cspace_says_which_joints_it_left_out(
    runner: CliRunner, tmp_path: Path
) -> None:
    # a differential-drive base: two wheels and nothing to plan
    links = ["base_link", "wheel_left_link", "wheel_right_link"]
    joints = [
        _joint("wheel_left_joint", "base_link", "wheel_left_link", "continuous"),
        _joint("wheel_right_joint", "base_link", "wheel_right_link", "continuous"),
    ]
    urdf = _tree(tmp_path, links, joints)
    code, text = _run(runner, "inspect", urdf)
    assert code == 0, text
    assert (
        "no serial chain of actuated joints besides 2 wheel joint(s) (wheel_left_joint, "
        "wheel_right_joint) in the URDF (--joints, --chain or --srdf choose one)"
    ) in text


def test_a_package_the_robot_sits_in_wins_over_a_same_named_one_under_a_far_parent(
    runner: CliRunner, tmp_path: Path
) -> None:
    # MATLAB's franka_description/robots/frankaEmikaPanda.urdf names package://franka_description
    # meshes; another franka_description with a package.xml two levels below /tmp took its place
    mesh = "package://franka_description/meshes/link.stl"
    arm = ARM.replace('<box size=".05 .05 .3"/>', f'<mesh filename="{mesh}"/>')
    robot = tmp_path / "data" / "models" / "franka_description"
    (robot / "robots").mkdir(parents=True)
    (robot / "meshes").mkdir()
    urdf = robot / "robots" / "r.urdf"
    urdf.write_text(arm.format(attr="", extra=""))
    _box_stl(robot / "meshes" / "link.stl")
    decoy = tmp_path / "elsewhere" / "franka_description"
    decoy.mkdir(parents=True)
    (decoy / "package.xml").write_text("<package><name>franka_description</name></package>")

    from xrdf_tools.robot.packages import PackageResolver

    assert PackageResolver(urdf).find("franka_description") == robot.resolve()
    out = tmp_path / "r.xrdf"
    code, text = _run(runner, "convert", urdf, "--fit-spheres", "-n", "50", "-o", out)
    assert code == 0, text
    geometry = load_xrdf(out).geometry
    assert geometry is not None and any("arm" in g.spheres for g in geometry.values())
    # a package.xml nearer than the folder named like the package still wins
    named = robot / "robots" / "vendor"
    named.mkdir()
    (named / "package.xml").write_text("<package><name>franka_description</name></package>")
    assert PackageResolver(urdf).find("franka_description") == named.resolve()


def _box_stl(path: Path) -> None:
    import trimesh

    trimesh.creation.box((0.05, 0.05, 0.3)).export(path)


def _without_spheres(runner: CliRunner, tmp_path: Path) -> tuple[Path, Path]:
    """A URDF with collision geometry and its XRDF converted without --fit-spheres."""
    urdf = tmp_path / "r.urdf"
    urdf.write_text(ARM.format(attr="", extra=""))
    xrdf = tmp_path / "r.xrdf"
    code, text = _run(runner, "convert", urdf, "-o", xrdf)
    assert code == 0, text
    return urdf, xrdf


def test_a_report_over_an_xrdf_without_spheres_is_a_finding_not_a_clean_bill(
    runner: CliRunner, tmp_path: Path
) -> None:
    # an XRDF converted without --fit-spheres: the report said
    # "findings: none" and exited 0 over zero spheres
    urdf, xrdf = _without_spheres(runner, tmp_path)
    line = next(
        i + 1 for i, t in enumerate(xrdf.read_text().splitlines()) if t.startswith("self_collision")
    )
    code, text = _run(runner, "report", xrdf, "--urdf", urdf, "-n", "50", "-j", "1")
    assert code == 1, text
    assert f"{xrdf}:{line + 1}:13: error report-no-spheres the self-collision group" in text
    code, text = _run(runner, "report", xrdf, "--urdf", urdf, "-n", "50", "--format", "json")
    assert code == 1 and '"report-no-spheres"' in text


def test_a_curobo_export_without_spheres_warns_at_the_collision_group(
    runner: CliRunner, tmp_path: Path
) -> None:
    urdf, xrdf = _without_spheres(runner, tmp_path)
    line = xrdf.read_text().splitlines().index("collision:") + 2
    code, text = _run(runner, "export", "curobo", xrdf, "--urdf", urdf, "-o", tmp_path / "r.yml")
    assert code == 0, text
    assert f"{xrdf}:{line}:13: warning export-no-spheres no collision sphere to export" in text
    # with spheres there is nothing to say about them; the arm's two sphere frames are
    # adjacent, so their one pair is masked and cuRobo's loader would raise: nothing written
    fitted = tmp_path / "fitted.xrdf"
    code, text = _run(runner, "convert", urdf, "--fit-spheres", "-n", "50", "-o", fitted)
    assert code == 0, text
    code, text = _run(runner, "export", "curobo", fitted, "--urdf", urdf, "-o", tmp_path / "f.yml")
    assert "export-no-spheres" not in text, text
    assert code == 1 and " error export-no-pair " in text and not (tmp_path / "f.yml").exists()


def test_a_pinky_is_a_finger_so_a_humanoid_arm_ends_at_its_palm(tmp_path: Path) -> None:
    # Valkyrie: leftIndexFingerPitch1..3 are fingers by name, leftPinkyPitch1..3 were not, and
    # the default c-space ran down the pinky (13 joints, tool frame 'leftPinkyPitch3Link')
    from xrdf_tools.robot.chains import default_cspace

    links = ["pelvis", "upper", "lower", "leftPalm", "i1", "i2", "p1", "p2", "p3"]
    joints = [
        _joint("leftShoulderPitch", "pelvis", "upper"),
        _joint("leftElbowPitch", "upper", "lower"),
        _joint("leftWristPitch", "lower", "leftPalm"),
        _joint("leftIndexFingerPitch1", "leftPalm", "i1"),
        _joint("leftIndexFingerPitch2", "i1", "i2"),
        _joint("leftPinkyPitch1", "leftPalm", "p1"),
        _joint("leftPinkyPitch2", "p1", "p2"),
        _joint("leftPinkyPitch3", "p2", "p3"),
    ]
    tree = _robot_tree(tmp_path, links, joints)
    choice = default_cspace(tree)
    assert choice.joints == ("leftShoulderPitch", "leftElbowPitch", "leftWristPitch")
    assert choice.tool is not None and choice.tool.frame == "leftPalm"
    assert choice.left_out["gripper"][-3:] == (
        "leftPinkyPitch1",
        "leftPinkyPitch2",
        "leftPinkyPitch3",
    )


def test_wheels_and_hands_written_as_one_word_are_left_out(tmp_path: Path) -> None:
    # Quanser QCar's 'wheelfl', Eve's 'qbhand': a wheel or a hand inside one word was not
    # recognised, so a default c-space could run down them
    from xrdf_tools.robot.chains import default_cspace, joint_roles

    links = ["base", "upper", "lower", "tool0", "h1", "h2", "w1", "w2"]
    joints = [
        _joint("shoulder", "base", "upper"),
        _joint("elbow", "upper", "lower"),
        _joint("wrist", "lower", "tool0"),
        _joint("qbhand_synergy", "tool0", "h1"),
        _joint("lefthand_close", "h1", "h2"),
        _joint("steer_wheelfl", "base", "w1"),
        _joint("frontwheel_spin", "w1", "w2"),
    ]
    tree = _robot_tree(tmp_path, links, joints)
    roles = joint_roles(tree)
    assert roles["qbhand_synergy"] == roles["lefthand_close"] == "gripper"
    assert roles["steer_wheelfl"] == roles["frontwheel_spin"] == "wheel"
    assert "shoulder" not in roles and "elbow" not in roles
    assert default_cspace(tree).joints == ("shoulder", "elbow", "wrist")


def test_a_fit_that_fits_nothing_fails_and_does_not_tell_the_user_to_fit_spheres(
    runner: CliRunner, tmp_path: Path
) -> None:
    # MATLAB's kinovaGen3.urdf names package://JACO3_URDF_V10 meshes that are not there
    mesh = '<mesh filename="package://JACO3_URDF_V10/meshes/Base_Link.STL"/>'
    text = ARM.format(attr="", extra="")
    text = text.replace('<box size=".05 .05 .3"/>', mesh).replace('<box size="0.2 0.2 0.1"/>', mesh)
    urdf = tmp_path / "r.urdf"
    urdf.write_text(text)
    out = tmp_path / "r.xrdf"
    args = ("convert", urdf, "--fit-spheres", "--allow-missing-meshes", "-n", "50", "-o", out)
    code, text = _run(runner, *args)
    assert code == 1, text
    assert not out.exists()
    assert "fitted no sphere" in text.splitlines()[-1]
    (line,) = [t for t in text.splitlines() if "convert-no-spheres" in t]
    assert "--fit-spheres fitted none" in line and "spheres-mesh-unreadable says why" in line
    assert "Add spheres" not in line
    assert text.count("spheres-mesh-unreadable") >= 2


def test_the_package_search_stops_below_the_temporary_and_home_folders(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # a UR5e URDF copied to /tmp/x found the ur_description another project had left in
    # /tmp/outside, without a word; the search now stops below the shared folders
    import tempfile

    from xrdf_tools.robot.packages import PackageResolver

    shared = tmp_path / "tmp"
    urdf = shared / "copy" / "ur5e.urdf"
    urdf.parent.mkdir(parents=True)
    urdf.write_text("<robot name='r'><link name='a'/></robot>")
    left = shared / "outside" / "ur_description"
    left.mkdir(parents=True)
    (left / "package.xml").write_text("<package><name>ur_description</name></package>")
    assert PackageResolver(urdf).find("ur_description") == left.resolve()  # an ordinary folder
    monkeypatch.setattr(tempfile, "tempdir", str(shared))
    with pytest.raises(SourceError, match="cannot find ROS package 'ur_description'"):
        PackageResolver(urdf).find("ur_description")
    # a package beside the input, and the input's own folder when it is the shared one
    (urdf.parent / "ur_description").mkdir()
    assert PackageResolver(urdf).find("ur_description") == (urdf.parent / "ur_description")
    top = shared / "r.urdf"
    top.write_text("<robot name='r'><link name='a'/></robot>")
    assert PackageResolver(top).find("ur_description") == left.resolve()


def test_a_plain_urdf_holding_xacro_substitutions_is_expanded_as_ros_does(
    runner: CliRunner, tmp_path: Path
) -> None:
    # pybullet's husky.urdf: an IMU mount at $(optenv HUSKY_IMU_XYZ 0.19 0 0.149), no xacro
    # namespace; every command refused it ("is not a list of numbers"), expand said "not a
    # xacro file (nothing to expand)"
    imu = (
        '<link name="imu_link"/>\n<joint name="imu_joint" type="fixed">\n'
        '  <origin rpy="$(optenv XRDF_TEST_UNSET_IMU_RPY 0 0 0)" '
        'xyz="$(optenv XRDF_TEST_UNSET_IMU_XYZ 0.19 0 0.149)"/>\n'
        '  <parent link="base"/><child link="imu_link"/>\n</joint>\n'
    )
    urdf = tmp_path / "r.urdf"
    urdf.write_text(ARM.format(attr="", extra=imu))
    expanded = tmp_path / "expanded.urdf"
    code, text = _run(runner, "expand", urdf, "-o", expanded)
    assert code == 0, text
    assert 'xyz="0.19 0 0.149"' in expanded.read_text()
    out = tmp_path / "r.xrdf"
    code, text = _run(runner, "convert", urdf, "--tool-frame", "imu_link", "-o", out)
    assert code == 0, text
    assert load_xrdf(out).tool_frames == ("imu_link",)


def test_a_dollar_sign_that_is_no_substitution_leaves_a_urdf_plain(tmp_path: Path) -> None:
    from xrdf_tools.robot.xacro_source import is_xacro

    urdf = tmp_path / "r.urdf"
    urdf.write_text(
        ARM.format(
            attr="", extra='<!-- $(find x) -->\n<material name="$5"/>\n<material name="${m}"/>\n'
        )
    )
    assert not is_xacro(urdf)
    urdf.write_text(ARM.format(attr="", extra='<material name="m_$(arg tint)"/>\n'))
    assert is_xacro(urdf)


def test_a_urdf_written_by_xacro_with_a_macro_call_commented_out_is_plain(
    runner: CliRunner, tmp_path: Path
) -> None:
    """Talos' talos_full_v2.urdf keeps xacro's namespace and a ``<xacro:...>`` call inside a
    comment: it is a plain URDF, and ``export curobo`` names it, not an expanded copy."""
    from xrdf_tools.robot.xacro_source import is_xacro

    urdf = tmp_path / "r.urdf"
    text = ARM.format(attr="", extra="<!-- <xacro:transmission name='${n}'/> -->\n")
    urdf.write_text(text.replace('<robot name="r">', '<robot name="r" xmlns:xacro="x">'))
    assert not is_xacro(urdf)
    xrdf = tmp_path / "r.xrdf"
    code, out = _run(runner, "convert", urdf, "--fit-spheres", "-o", xrdf)
    assert code == 0, out
    # the arm's one pair is adjacent: unmasked, so that cuRobo has a pair to check
    xrdf.write_text(xrdf.read_text().replace("  ignore:\n    base: [arm]\n", "  ignore: {}\n"))
    code, out = _run(runner, "export", "curobo", xrdf, "--urdf", urdf, "-o", tmp_path / "c.yml")
    assert code == 0, out
    assert "export-expanded-urdf" not in out and not (tmp_path / "c_r.urdf").exists()
    assert (
        yaml.safe_load((tmp_path / "c.yml").read_text())["robot_cfg"]["kinematics"]["urdf_path"]
        == "r.urdf"
    )
    urdf.write_text(text.replace("<!-- <xacro:", "<xacro:").replace(" -->", ""))
    assert not is_xacro(urdf)  # no namespace: not xacro's element


def test_a_wrist_joint_held_by_zero_limits_is_named_where_the_cspace_leaves_it_out(
    runner: CliRunner, tmp_path: Path
) -> None:
    # SolidWorks' exporter writes <limit lower="0" upper="0"> for limits never set: a
    # PAROL6-like arm with such a wrist got a 5-joint c-space and no word of the sixth
    links = ["base", "l1", "l2", "l3"]
    held = _joint("j2", "l1", "l2").replace('lower="-1" upper="1"', 'lower="0" upper="0"')
    joints = [_joint("j1", "base", "l1"), held, _joint("j3", "l2", "l3")]
    chosen = default_cspace(_robot_tree(tmp_path, links, joints))
    assert chosen.joints == ("j1", "j3")
    assert chosen.held == ("j2",)
    code, text = _run(runner, "inspect", _tree(tmp_path, links, joints))
    assert code == 0, text
    assert "left out, held still by equal lower and upper limits: j2 (a CAD exporter" in text
    # a chain without such a joint says nothing of it
    free = default_cspace(_robot_tree(tmp_path, links, [_joint("j1", "base", "l1")]))
    assert free.held == () and "held still" not in free.describe()


def test_the_chain_flag_a_message_suggests_runs_as_written_for_names_with_spaces(
    runner: CliRunner, tmp_path: Path
) -> None:
    # onshape-to-robot and Fusion exports name links after CAD parts ("base link", "tip 2")
    links = ["base link", "upper arm", 'tip "2"']
    joints = [
        _joint("shoulder #1", "base link", "upper arm"),
        _joint("tip joint", "upper arm", "tip &quot;2&quot;", "fixed"),
    ]
    urdf = _tree(tmp_path, [name.replace('"', "&quot;") for name in links], joints)
    code, text = _run(runner, "inspect", urdf)
    assert code == 0, text
    (line,) = [t for t in text.splitlines() if "the same with a flag:" in t]
    flag = shlex.split(line.split("the same with a flag:", 1)[1])
    assert flag == ["--chain", 'base link:tip "2"']
    code, text = _run(runner, "convert", urdf, *flag, "-o", tmp_path / "r.xrdf")
    assert code == 0, text
    assert load_xrdf(tmp_path / "r.xrdf").tool_frames == ('tip "2"',)


def test_a_renamed_package_is_named_with_the_package_path_that_finds_its_meshes(
    runner: CliRunner, tmp_path: Path
) -> None:
    # SolidWorks writes package://<assembly name>/meshes/...; the Moveo's package.xml says
    # moveo_urdf while its URDFs name moveo_urdf_4: the error said only "pass --package-path"
    pkg = tmp_path / "arm_description"
    (pkg / "meshes").mkdir(parents=True)
    (pkg / "urdf").mkdir()
    (pkg / "package.xml").write_text("<package><name>arm_description</name></package>")
    (pkg / "meshes" / "arm.STL").write_text(
        "solid a\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 0.1 0 0\n"
        "vertex 0 0.1 0\nendloop\nendfacet\nendsolid a\n"
    )
    urdf = pkg / "urdf" / "arm.urdf"
    mesh = '<mesh filename="package://arm_4/meshes/arm.STL"/>'
    urdf.write_text(ARM.format(attr="", extra="").replace('<box size=".05 .05 .3"/>', mesh))
    out = tmp_path / "o.xrdf"
    code, text = _run(runner, "convert", urdf, "--fit-spheres", "-n", "10", "-o", out)
    assert code == 2, text
    hint = f"package 'arm_description' at {pkg} holds meshes/arm.STL: --package-path arm_4={pkg}"
    assert hint in text
    # the flag it names is the one that finds the mesh
    flag = ["--package-path", f"arm_4={pkg}"]
    code, text = _run(runner, "convert", urdf, *flag, "--fit-spheres", "-n", "10", "-o", out)
    assert "cannot be found" not in text and "cannot find ROS package" not in text, text


def test_a_cspace_joint_held_by_zero_limits_is_a_lint_warning(
    runner: CliRunner, tmp_path: Path
) -> None:
    # a MoveIt config made from a SolidWorks export keeps the [0, 0] wrist in its arm group
    links = ["base", "l1", "l2", "l3"]
    held = _joint("j2", "l1", "l2").replace('lower="-1" upper="1"', 'lower="0" upper="0"')
    urdf = _tree(tmp_path, links, [_joint("j1", "base", "l1"), held, _joint("j3", "l2", "l3")])
    srdf = tmp_path / "r.srdf"
    srdf.write_text(
        '<robot name="r"><group name="arm"><chain base_link="base" tip_link="l3"/></group></robot>'
    )
    out = tmp_path / "r.xrdf"
    code, text = _run(runner, "convert", urdf, "--srdf", srdf, "-o", out)
    assert code == 0, text
    assert load_xrdf(out).cspace.joint_names == ("j1", "j2", "j3")
    code, text = _run(runner, "lint", out, "--urdf", urdf)
    (line,) = [t for t in text.splitlines() if "cspace-joint-held" in t]
    assert "warning cspace-joint-held c-space joint 'j2'" in line and "[0, 0]" in line
    # cuRobo's loader raises on an empty position range: an error for that reader
    code, text = _run(runner, "lint", out, "--urdf", urdf, "--target", "curobo")
    (line,) = [t for t in text.splitlines() if "cspace-joint-held" in t]
    assert code == 1 and "error cspace-joint-held" in line and "loader raises" in line
    # the free joints are no finding, and nothing without the URDF
    code, text = _run(runner, "lint", out)
    assert "cspace-joint-held" not in text
