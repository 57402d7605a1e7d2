"""Never silently incomplete, strict where it matters and lenient where it does not.

* A mesh that cannot be found is an input error (exit 2) naming the URI and the directories
  searched, unless ``--allow-missing-meshes``; a mesh that cannot be read leaves its link
  without spheres, which fails the fit (exit 1) naming the link and why.
* A mesh path that is a directory, a FIFO, a symbolic link loop or a name too long says so.
* A defect in a part the command does not use (an SRDF group, a material colour) is a located
  warning; the groups the command uses stay errors.
* A relative ``--package-path`` is taken from the current directory.

Every case runs through the CLI on real robots from example-robot-data where one exists.
"""

from __future__ import annotations

import math
import os
import re
import shutil
import struct
from pathlib import Path

import pytest
from typer.testing import CliRunner

from tests.robots import robot_urdf, robots_dir
from xrdf_tools.cli import app
from xrdf_tools.robot.link_geometry import link_geometry, missing_meshes
from xrdf_tools.robot.xacro_source import load_robot
from xrdf_tools.xrdf.io import load_xrdf


def _run(runner: CliRunner, *args: str | Path) -> tuple[int, str]:
    r = runner.invoke(app, [str(a) for a in args])
    return r.exit_code, r.output


def _ur5_away_from_its_meshes(tmp_path: Path) -> tuple[Path, Path]:
    """The real UR5 URDF and SRDF copied into ``tmp_path``, without the meshes."""
    urdf = robot_urdf("ur5")
    srdf = urdf.parents[1] / "srdf" / "ur5.srdf"
    shutil.copy(urdf, tmp_path / "ur5.urdf")
    shutil.copy(srdf, tmp_path / "ur5.srdf")
    return tmp_path / "ur5.urdf", tmp_path / "ur5.srdf"


# --------------------------------------------------------------------------------------------
# Missing meshes: exit 2, or warnings with --allow-missing-meshes
# --------------------------------------------------------------------------------------------
def test_ur5_away_from_its_meshes_is_an_input_error_naming_uri_and_search(
    runner: CliRunner, tmp_path: Path
) -> None:
    urdf, srdf = _ur5_away_from_its_meshes(tmp_path)
    out = tmp_path / "ur5.xrdf"
    code, text = _run(
        runner, "convert", urdf, "--srdf", srdf, "--fit-spheres", "-n", "200", "-o", out
    )
    assert code == 2, text
    (error,) = [line for line in text.splitlines() if line.startswith("error:")]
    assert f"{urdf}:" in error  # located at the first link whose mesh is missing
    assert "7 mesh file(s) cannot be found" in error
    assert "package://example-robot-data/robots/ur_description/meshes/ur5/collision/base.stl" in (
        error
    )
    assert f"searched for package.xml named 'example-robot-data' in and below: {tmp_path}" in error
    assert "--allow-missing-meshes" in error and "--package-path example-robot-data=DIR" in error
    assert not out.exists()


def test_meshes_from_several_missing_packages_name_each_package(
    runner: CliRunner, tmp_path: Path
) -> None:
    """Husky with two UR5s and Robotiq grippers needs meshes of several packages: the error
    named only the first, so each run found one more --package-path to give. It names every
    package that cannot be found, with its mesh count."""
    links = [("a1", "xrdf_absent_arm"), ("g1", "xrdf_absent_grip"), ("g2", "xrdf_absent_grip")]
    body = "".join(
        f'<link name="{n}"><collision><geometry><mesh filename="package://{pkg}/m/{n}.stl"/>'
        f'</geometry></collision></link><joint name="j{n}" type="fixed"><parent link="base"/>'
        f'<child link="{n}"/></joint>'
        for n, pkg in links
    )
    urdf = tmp_path / "r.urdf"
    urdf.write_text(f'<robot name="r"><link name="base"/>{body}</robot>')
    code, text = _run(runner, "convert", urdf, "--fit-spheres", "-o", tmp_path / "r.xrdf")
    assert code == 2, text
    (error,) = [line for line in text.splitlines() if line.startswith("error:")]
    assert "3 mesh file(s) cannot be found: link 'a1' collision" in error
    assert (
        "packages not found: xrdf_absent_arm (1 mesh(es)), xrdf_absent_grip (2 mesh(es)): pass "
        "--package-path NAME=DIR for each" in error
    )


def test_a_relative_mesh_path_is_found_in_a_parent_of_the_urdfs_directory(
    runner: CliRunner, tmp_path: Path
) -> None:
    """A URDF in ``robot/urdf/`` naming ``meshes/arm.stl`` that lies in ``robot/meshes/``
    (cuRobo's tm12): found there, as yourdfpy (and cuRobo through it) finds it, instead of a
    missing mesh; a path found nowhere is still an input error naming where it was looked
    for."""
    import trimesh

    robot = tmp_path / "robot"
    (robot / "urdf").mkdir(parents=True)
    (robot / "meshes").mkdir()
    trimesh.creation.box(extents=[0.05, 0.05, 0.3]).export(robot / "meshes" / "arm.stl")
    urdf = robot / "urdf" / "r.urdf"
    text = (
        '<robot name="r"><link name="base"/><link name="arm"><collision><geometry>'
        '<mesh filename="meshes/{}.stl"/></geometry></collision></link>'
        '<joint name="j" type="revolute"><parent link="base"/><child link="arm"/>'
        '<axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>'
        "</robot>"
    )
    urdf.write_text(text.format("arm"))
    out = tmp_path / "r.xrdf"
    code, output = _run(runner, "convert", urdf, "--fit-spheres", "-n", "200", "-o", out)
    assert code == 0, output
    assert load_xrdf(out).world_collision_spheres()["arm"]
    urdf.write_text(text.format("nowhere"))
    code, output = _run(runner, "convert", urdf, "--fit-spheres", "-n", "200", "-o", out)
    assert code == 2 and str(robot / "urdf" / "meshes" / "nowhere.stl") in output, output


def test_allow_missing_meshes_goes_on_with_a_warning_per_mesh(
    runner: CliRunner, tmp_path: Path
) -> None:
    urdf, srdf = _ur5_away_from_its_meshes(tmp_path)
    out = tmp_path / "ur5.xrdf"
    code, text = _run(
        runner,
        "convert",
        urdf,
        "--srdf",
        srdf,
        "--fit-spheres",
        "-n",
        "200",
        "--allow-missing-meshes",
        "-o",
        out,
    )
    assert code == 0, text
    warned = re.findall(r"warning spheres-mesh-unreadable link '(\w+)' collision: (\S+):", text)
    assert len(warned) == 7 and {uri.rsplit("/", 1)[-1] for _, uri in warned} == {
        "base.stl",
        "shoulder.stl",
        "upperarm.stl",
        "forearm.stl",
        "wrist1.stl",
        "wrist2.stl",
        "wrist3.stl",
    }
    spheres = load_xrdf(out).world_collision_spheres()
    assert [link for link, s in spheres.items() if s] == ["ee_link"]  # the only box


def test_lint_for_a_planner_calls_moved_links_without_spheres_errors(
    runner: CliRunner, tmp_path: Path
) -> None:
    urdf, srdf = _ur5_away_from_its_meshes(tmp_path)
    out = tmp_path / "ur5.xrdf"
    assert _run(runner, "convert", urdf, "--srdf", srdf, "-o", out)[0] == 0
    code, text = _run(runner, "lint", out, "--urdf", urdf, "--target", "curobo")
    assert code == 1
    errors = set(re.findall(r"error mesh-without-spheres link '(\w+)'", text))
    assert errors == {
        "shoulder_link",
        "upper_arm_link",
        "forearm_link",
        "wrist_1_link",
        "wrist_2_link",
        "wrist_3_link",
    }
    # the base no joint moves stays a warning, and so does ee_link, a 1 cm placeholder box;
    # without a planning target all are warnings
    assert "warning mesh-without-spheres link 'base_link'" in text
    assert re.search(r"warning mesh-without-spheres link 'ee_link'.*placeholder, 17 mm", text)
    code, text = _run(runner, "lint", out, "--urdf", urdf)
    assert code == 0 and "error" not in text and text.count("mesh-without-spheres") == 8


def test_allowed_missing_meshes_leave_a_planner_target_with_warnings(
    runner: CliRunner, tmp_path: Path
) -> None:
    """--allow-missing-meshes says the meshes are expected to be absent: a link whose only
    collision geometry is such a mesh is a warning saying so for a planner target too, and
    convert --target curobo finishes (Kinova MOVO without its gripper meshes); a link whose
    geometry is at hand stays an error."""
    urdf, srdf = _ur5_away_from_its_meshes(tmp_path)
    out = tmp_path / "ur5.xrdf"
    args = ["--srdf", srdf, "--fit-spheres", "-n", "200", "--allow-missing-meshes"]
    code, text = _run(runner, "convert", urdf, *args, "--target", "curobo", "-o", out)
    # only ee_link's box is at hand, so one frame carries spheres: cuRobo's self-collision
    # set-up has no pair to check and its loader raises; that is the one error
    assert code == 1 and re.findall(r"error ([\w-]+)", text) == ["curobo-no-pair"], text
    code, text = _run(runner, "convert", urdf, *args, "-o", out)
    assert code == 0, text
    code, text = _run(
        runner, "lint", out, "--urdf", urdf, "--target", "curobo", "--allow-missing-meshes"
    )
    assert code == 1 and re.findall(r"error ([\w-]+)", text) == ["curobo-no-pair"], text
    warned = re.findall(r"warning mesh-without-spheres link '(\w+)'.*--allow-missing-meshes", text)
    assert len(warned) == 7 and "wrist_3_link" in warned
    # a box at hand, not a placeholder: without its spheres it is an error still (ee_link's
    # 1 cm box made a 5 cm one)
    urdf.write_text(urdf.read_text().replace('size="0.01 0.01 0.01"', 'size="0.05 0.05 0.05"'))
    x = out.read_text()
    stripped = tmp_path / "stripped.xrdf"
    stripped.write_text(re.sub(r"(?m)^      ee_link:\n(?:        .*\n)+", "", x, count=1))
    assert "ee_link:" not in stripped.read_text().split("geometry:")[-1]
    code, text = _run(
        runner, "lint", stripped, "--urdf", urdf, "--target", "curobo", "--allow-missing-meshes"
    )
    assert code == 1 and "error mesh-without-spheres link 'ee_link'" in text, text


def test_viz_stops_on_meshes_it_cannot_find_unless_allowed(
    runner: CliRunner, tmp_path: Path
) -> None:
    pytest.importorskip("mcap")
    urdf, srdf = _ur5_away_from_its_meshes(tmp_path)
    xrdf = tmp_path / "ur5.xrdf"
    assert _run(runner, "convert", urdf, "--srdf", srdf, "-o", xrdf)[0] == 0
    out = tmp_path / "ur5.mcap"
    code, text = _run(runner, "viz", xrdf, "--urdf", urdf, "--mcap", out)
    assert code == 2 and "visual/base.dae" in text and not out.exists()
    code, text = _run(runner, "viz", xrdf, "--urdf", urdf, "--mcap", out, "--allow-missing-meshes")
    assert code == 0, text
    assert text.count("warning mesh-not-loaded") == 7 and out.stat().st_size > 0


# --------------------------------------------------------------------------------------------
# Meshes found but unreadable, and paths that are no mesh file
# --------------------------------------------------------------------------------------------
ROBOT = """<robot name="r">
  <link name="base"><collision><geometry><box size="0.2 0.2 0.1"/></geometry></collision></link>
  <link name="arm">{arm}</link>
  <joint name="j" type="revolute"><parent link="base"/><child link="arm"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>
"""
MESH = '<collision><geometry><mesh filename="{}"/></geometry></collision>'
BOX = '<collision><geometry><box size="0.05 0.05 0.3"/></geometry></collision>'


def _bad_meshes(d: Path) -> dict[str, Path]:
    """A garbage file, a truncated ASCII STL and a binary STL whose header claims 2^31
    triangles."""
    files = {
        "garbage": d / "garbage.stl",
        "truncated": d / "truncated.stl",
        "huge": d / "huge.stl",
    }
    files["garbage"].write_bytes(bytes(range(256)) * 3)
    files["truncated"].write_text("solid t\n facet normal 0 0 1\n  outer loop\n   vertex 0 0")
    files["huge"].write_bytes(b"\0" * 80 + struct.pack("<I", 2**31) + b"\0" * 100)
    return files


@pytest.mark.parametrize("kind", ["garbage", "truncated", "huge"])
def test_an_unreadable_mesh_fails_the_fit_naming_the_link(
    runner: CliRunner, tmp_path: Path, kind: str
) -> None:
    mesh = _bad_meshes(tmp_path)[kind]
    urdf, line = _not_covered(runner, tmp_path, mesh)
    assert f"{urdf}:3: error" in line and "link 'arm' has geometry but got no spheres" in line
    assert mesh.name in line and "cannot read mesh" in line


def _not_covered(runner: CliRunner, tmp_path: Path, mesh: Path) -> tuple[Path, str]:
    """`xrdf spheres` on a one-link robot whose mesh is ``mesh``: it fails (exit 1, nothing
    written); the URDF and the line that says the link got no spheres."""
    urdf = tmp_path / "r.urdf"
    urdf.write_text(ROBOT.format(arm=MESH.format(mesh.name)))
    out = tmp_path / "r.xrdf"
    code, text = _run(runner, "spheres", urdf, "--per-link", "2", "-o", out)
    assert code == 1, text
    assert not out.exists()  # nothing written
    (line,) = [t for t in text.splitlines() if "spheres-link-not-covered" in t]
    return urdf, line


@pytest.mark.parametrize(
    "name, text",
    [
        ("bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 999999\n"),  # a face past the vertices
        ("bad.dae", "<COLLADA><asset><unit meter='abc'/></asset></COLLADA>"),  # no scene
    ],
)
def test_a_mesh_the_reader_trips_over_is_called_malformed(
    runner: CliRunner, tmp_path: Path, name: str, text: str
) -> None:
    """The reader's own slip ("'NoneType' object has no attribute 'nodes'", an index out of
    bounds) says nothing about the file: the message says the file is malformed."""
    mesh = tmp_path / name
    mesh.write_text(text)
    _, line = _not_covered(runner, tmp_path, mesh)
    kind = name.split(".")[1].upper()
    assert f"{name}: cannot read mesh (a malformed {kind} file" in line, line
    assert "NoneType" not in line and "out of bounds" not in line


@pytest.mark.parametrize("suffix", ["stl", "obj", "dae"])
def test_a_git_lfs_pointer_in_place_of_a_mesh_says_so(
    runner: CliRunner, tmp_path: Path, suffix: str
) -> None:
    """A repository cloned without git-lfs holds a three-line text file where each mesh
    should be: the message says what it is and how to get the mesh."""
    mesh = tmp_path / f"long_U.{suffix}"
    mesh.write_text(
        "version https://git-lfs.github.com/spec/v1\n"
        "oid sha256:c3150095267a94d0df530167b9bb22d22d00ec74918969fdbf33aa83f77ca63b\n"
        "size 5144484\n"
    )
    _, line = _not_covered(runner, tmp_path, mesh)
    assert f"{mesh.name}: cannot read mesh (a Git LFS pointer, not the mesh" in line
    assert "git lfs pull" in line


def test_a_link_with_one_unreadable_part_of_two_fails_too(
    runner: CliRunner, tmp_path: Path
) -> None:
    mesh = _bad_meshes(tmp_path)["garbage"]
    urdf = tmp_path / "r.urdf"
    urdf.write_text(ROBOT.format(arm=BOX + MESH.format(mesh.name)))
    code, text = _run(
        runner, "convert", urdf, "--fit-spheres", "-n", "100", "-o", tmp_path / "r.xrdf"
    )
    assert code == 1, text
    assert "link 'arm' got spheres for only part of its geometry" in text
    assert "garbage.stl: cannot read mesh" in text


@pytest.mark.parametrize("kind", ["garbage", "truncated", "huge"])
def test_lint_and_viz_say_an_unreadable_mesh(runner: CliRunner, tmp_path: Path, kind: str) -> None:
    mesh = _bad_meshes(tmp_path)[kind]
    urdf = tmp_path / "r.urdf"
    urdf.write_text(ROBOT.format(arm=MESH.format(mesh.name)))
    xrdf = tmp_path / "r.xrdf"
    xrdf.write_text(
        "format: xrdf\nformat_version: 1.0\ncspace:\n  joint_names: [j]\n"
        "  acceleration_limits: [10.0]\n  jerk_limits: [500.0]\ntool_frames: [arm]\n"
        "collision:\n  geometry: g\nself_collision:\n  geometry: g\n  ignore:\n"
        "    base: [arm]\ngeometry:\n  g:\n    spheres:\n"
        "      base:\n        - center: [0.0, 0.0, 0.0]\n          radius: 0.05\n"
        "      arm:\n        - center: [0.0, 0.0, 0.1]\n          radius: 0.03\n"
    )
    for allow in ([], ["--allow-missing-meshes"]):
        code, text = _run(runner, "lint", xrdf, "--urdf", urdf, *allow)
        assert code == 0
        assert "warning sphere-outside-geometry" in text and "cannot be read" in text
        assert mesh.name in text
    code, text = _run(runner, "viz", xrdf, "--urdf", urdf, "--png", tmp_path / "r.png")
    assert code == 0 and "the PNG draws spheres only (meshes not read)" in text


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs here")
def test_a_mesh_path_that_is_no_file_says_what_it_is(runner: CliRunner, tmp_path: Path) -> None:
    (tmp_path / "dir.stl").mkdir()
    os.mkfifo(tmp_path / "fifo.stl")
    os.symlink("loop_b.stl", tmp_path / "loop_a.stl")
    os.symlink("loop_a.stl", tmp_path / "loop_b.stl")
    long_name = "m" * 300 + ".stl"
    expected = {
        "dir.stl": "a directory, not a mesh file",
        "fifo.stl": "a FIFO (named pipe), not a mesh file",
        "loop_a.stl": "a symbolic link loop, not a mesh file",
        long_name: "file name too long for this file system (304 bytes in one name",
        "absent.stl": "mesh file not found",
    }
    if Path("/dev/null").exists():
        expected["file:///dev/null"] = "a character device, not a mesh file"
    arm = "".join(MESH.format(name) for name in expected)
    urdf = tmp_path / "r.urdf"
    urdf.write_text(ROBOT.format(arm=arm))
    robot = load_robot(urdf)
    reasons = [f.reason for f in missing_meshes(robot, links=["arm"])]
    assert len(reasons) == len(expected)
    for (name, what), reason in zip(expected.items(), reasons, strict=True):
        assert reason.startswith(f"{name}: {what}"), reason
    (parts,) = link_geometry(robot, "collision", links=["arm"]).values()
    assert [f.reason for f in parts.failures] == reasons and all(f.missing for f in parts.failures)
    code, text = _run(runner, "spheres", urdf, "-o", tmp_path / "r.xrdf")
    assert code == 2 and f"{len(expected)} mesh file(s) cannot be found" in text
    assert "dir.stl: a directory, not a mesh file" in text and "Traceback" not in text


# --------------------------------------------------------------------------------------------
# Lenient where it does not matter: SRDF groups, material colours
# --------------------------------------------------------------------------------------------
def test_z1_srdf_with_a_broken_unused_group_converts_with_a_located_warning(
    runner: CliRunner,
    tmp_path: Path,
) -> None:
    urdf = robot_urdf("z1")
    srdf = urdf.parents[1] / "srdf" / "z1.srdf"
    out = tmp_path / "z1.xrdf"
    code, text = _run(runner, "convert", urdf, "--srdf", srdf, "-o", out)
    assert code == 0, text
    assert (
        f"{srdf}:4: warning convert-srdf-unused-group group 'end_effector' does not match the "
        "URDF (unknown chain link 'base'); it is not used for this conversion"
    ) in text
    assert load_xrdf(out).cspace is not None
    code, text = _run(runner, "convert", urdf, "--srdf", srdf, "--group", "end_effector")
    assert code == 2 and "group 'end_effector' (line 4): unknown chain link 'base'" in text


def test_kinova_with_an_unused_gripper_group_naming_missing_joints(
    runner: CliRunner, tmp_path: Path
) -> None:
    """A Kinova arm with an SRDF written for the arm plus a Robotiq gripper the URDF lacks."""
    urdf = robot_urdf("kinova")
    srdf_text = (urdf.parents[1] / "srdf" / "kinova.srdf").read_text()
    gripper = (
        '    <group name="gripper">\n'
        '        <joint name="robotiq_85_left_knuckle_joint" />\n'
        '        <joint name="robotiq_85_right_knuckle_joint" />\n'
        "    </group>\n"
        '    <group_state name="open" group="gripper">\n'
        '        <joint name="robotiq_85_left_knuckle_joint" value="0" />\n'
        "    </group_state>\n"
        '    <end_effector name="robotiq" parent_link="robotiq_85_base_link" group="gripper" />\n'
        '    <disable_collisions link1="robotiq_85_base_link" link2="j2s6s200_link_6" '
        'reason="Adjacent" />\n'
        '    <passive_joint name="robotiq_85_right_finger_joint" />\n'
        "</robot>"
    )
    srdf = tmp_path / "kinova_robotiq.srdf"
    srdf.write_text(srdf_text.replace("</robot>", gripper))
    line = srdf.read_text().splitlines().index('    <group name="gripper">') + 1
    out = tmp_path / "kinova.xrdf"
    code, text = _run(runner, "convert", urdf, "--srdf", srdf, "--group", "end_effector", "-o", out)
    assert code == 0, text
    assert (
        f"{srdf}:{line}: warning convert-srdf-unused-group group 'gripper' does not match the "
        "URDF (unknown joints 'robotiq_85_left_knuckle_joint', 'robotiq_85_right_knuckle_joint')"
    ) in text
    assert "'robotiq_85_base_link' (disable_collisions link1) is not a link" in text
    assert "passive_joint 'robotiq_85_right_finger_joint' is not a joint of the URDF" in text
    cspace = load_xrdf(out).cspace
    assert cspace is not None and len(cspace.joint_names) == 6
    # the default choice skips the broken group too; using it is an error naming it
    code, text = _run(runner, "convert", urdf, "--srdf", srdf, "-o", out)
    assert code == 0 and "convert-srdf-unused-group" in text
    code, text = _run(runner, "convert", urdf, "--srdf", srdf, "--group", "gripper")
    assert code == 2 and "group 'gripper'" in text and "robotiq_85_left_knuckle_joint" in text


def test_a_five_number_colour_in_a_mobile_manipulator_is_a_located_warning(
    runner: CliRunner,
    tmp_path: Path,
) -> None:
    root = robots_dir()
    tiago = None if root is None else root / "tiago_description" / "robots" / "tiago.urdf"
    if tiago is None or not tiago.is_file():
        pytest.skip("TIAGo is not in this example-robot-data")
    from lxml import etree

    # the colour of a material its visual elements use gets a fifth number
    color = etree.parse(str(tiago)).find("material/color")
    assert color is not None
    at = color.sourceline - 1
    lines = tiago.read_text().splitlines(keepends=True)
    lines[at] = re.sub(r'rgba="([^"]*)"', r'rgba="\1 0.5"', lines[at])
    urdf = tmp_path / "tiago.urdf"
    urdf.write_text("".join(lines))
    out = tmp_path / "tiago.xrdf"
    code, text = _run(
        runner, "convert", urdf, "--chain", "torso_lift_link:arm_tool_link", "-o", out
    )
    assert code == 0, text
    (warning,) = [t for t in text.splitlines() if "urdf-color-ignored" in t]
    assert warning.startswith(f"{urdf}:{at + 1}: warning urdf-color-ignored material '")
    assert "must be 4 numbers; the colour is ignored" in warning
    assert out.is_file()
    # the same URDF through a command loading --urdf says it too
    code, text = _run(runner, "lint", out, "--urdf", urdf)
    assert "urdf-color-ignored" in text


def test_a_visual_elements_own_colour_is_lenient_too_and_other_numbers_stay_strict(
    runner: CliRunner,
    tmp_path: Path,
) -> None:
    urdf = tmp_path / "r.urdf"
    visual = (
        '<visual><geometry><box size="0.1 0.1 0.1"/></geometry>'
        '<material name="m"><color rgba="1 0 0"/></material></visual>'
    )
    urdf.write_text(ROBOT.format(arm=visual + BOX))
    code, text = _run(runner, "convert", urdf, "-o", tmp_path / "r.xrdf")
    assert code == 0, text
    assert (
        f"{urdf}:3: warning urdf-color-ignored link 'arm' <visual> <material> <color> "
        "rgba='1 0 0' must be 4 numbers"
    ) in text
    urdf.write_text(ROBOT.format(arm=BOX.replace('size="0.05 0.05 0.3"', 'size="0.05 0.05"')))
    code, text = _run(runner, "convert", urdf, "-o", tmp_path / "r.xrdf")
    assert code == 2 and "must be 3 numbers" in text


def test_a_revolute_limit_of_1e16_reads_as_continuous_and_infinity_stays_an_error(
    runner: CliRunner,
    tmp_path: Path,
) -> None:
    """Exporters write "no limit" as ±1e16 (the quadrotor's rotors here): a located warning,
    the joint turns freely everywhere (inspect, convert, report); a limit that is no finite
    number stays an error at its line."""
    from xrdf_tools.robot.kinematics import build_kinematic_model

    urdf = tmp_path / "r.urdf"
    urdf.write_text(
        ROBOT.format(arm=BOX).replace('lower="-1" upper="1"', 'lower="-1e+16" upper="1e16"')
    )
    code, text = _run(runner, "inspect", urdf)
    assert code == 0, text
    assert (
        f"{urdf}:6: warning urdf-limit-unbounded revolute joint 'j' <limit> lower='-1e+16' "
        "upper='1e16': beyond ±1e+12, so no limit at all; the joint is read as continuous"
    ) in text
    assert "j (continuous" in text
    robot = load_robot(urdf)
    assert robot.joints["j"].type == "continuous"
    kin, _ = build_kinematic_model(robot)
    assert kin.lower.tolist() == [-math.pi] and kin.upper.tolist() == [math.pi]
    out = tmp_path / "r.xrdf"
    code, text = _run(runner, "convert", urdf, "--fit-spheres", "-n", "100", "-o", out)
    assert code == 0 and "urdf-limit-unbounded" in text, text
    code, text = _run(runner, "report", out, "--urdf", urdf, "-n", "200")
    assert code == 0 and "urdf-limit-unbounded" in text, text
    fixed = ROBOT.format(arm=BOX).replace('type="revolute"', 'type="fixed"')
    urdf.write_text(fixed.replace('lower="-1" upper="1"', 'lower="-1e+16" upper="1e16"'))
    code, text = _run(runner, "inspect", urdf)
    assert code == 0 and "urdf-limit-unbounded fixed joint 'j'" in text, text
    assert "ignored (a fixed joint has no position limits)" in text
    urdf.write_text(ROBOT.format(arm=BOX).replace('lower="-1"', 'lower="-inf"'))
    code, text = _run(runner, "inspect", urdf)
    assert code == 2 and f"{urdf}:6:" in text and "must be finite" in text, text


# --------------------------------------------------------------------------------------------
# A relative --package-path is taken from the current directory
# --------------------------------------------------------------------------------------------
PART = """<robot xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:macro name="arm">
    <link name="base"><collision><geometry>
      <mesh filename="package://mypkg/meshes/base.stl"/></geometry></collision></link>
    <link name="tip"/>
    <joint name="j1" type="revolute"><parent link="base"/><child link="tip"/>
      <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  </xacro:macro>
</robot>
"""
TOP = """<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:include filename="$(find mypkg)/urdf/part.xacro"/>
  <xacro:arm/>
</robot>
"""


def test_a_relative_package_path_is_taken_from_the_current_directory(
    runner: CliRunner, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import trimesh

    pkg = tmp_path / "pkgs" / "mypkg"
    (pkg / "urdf").mkdir(parents=True)
    (pkg / "meshes").mkdir()
    (pkg / "urdf" / "part.xacro").write_text(PART)
    trimesh.creation.box(extents=[0.1, 0.1, 0.1]).export(pkg / "meshes" / "base.stl")
    (tmp_path / "top").mkdir()
    (tmp_path / "top" / "robot.urdf.xacro").write_text(TOP)
    monkeypatch.chdir(tmp_path)
    robot = Path("top/robot.urdf.xacro")
    code, text = _run(runner, "expand", robot, "--package-path", "mypkg=pkgs/mypkg")
    assert code == 0, text
    assert '<joint name="j1" type="revolute">' in text
    out = tmp_path / "r.xrdf"
    code, text = _run(
        runner,
        "convert",
        robot,
        "--package-path",
        "mypkg=pkgs/mypkg",
        "--fit-spheres",
        "-n",
        "50",
        "-o",
        out,
    )
    assert code == 0, text
    assert load_xrdf(out).world_collision_spheres()["base"]


@pytest.mark.parametrize("victim", ["urdf/part.xacro", "urdf/props.xacro", "meshes/base.stl"])
def test_expand_never_writes_over_a_file_the_robot_is_read_from(
    runner: CliRunner, tmp_path: Path, victim: str
) -> None:
    """An included file (with links, or only properties) or a mesh is an input of the
    expansion: ``-o`` on it is refused and the file kept."""
    pkg = tmp_path / "mypkg"
    (pkg / "urdf").mkdir(parents=True)
    (pkg / "meshes").mkdir()
    (pkg / "urdf" / "part.xacro").write_text(PART)
    (pkg / "urdf" / "props.xacro").write_text(
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro"><xacro:property name="r" '
        'value="r"/></robot>'
    )
    (pkg / "meshes" / "base.stl").write_bytes(b"solid x\nendsolid x\n")
    top = tmp_path / "robot.urdf.xacro"
    top.write_text(
        TOP.replace(
            "<xacro:arm/>",
            '<xacro:include filename="$(find mypkg)/urdf/props.xacro"/>\n  <xacro:arm/>',
        )
    )
    out = pkg / victim
    before = out.read_bytes()
    code, text = _run(runner, "expand", top, "--package-path", f"mypkg={pkg}", "-o", out)
    assert code == 2 and f"{out}: refusing to overwrite an input" in text, text
    assert out.read_bytes() == before


def test_a_package_name_or_package_path_too_long_is_a_clear_input_error(
    runner: CliRunner, tmp_path: Path
) -> None:
    name = "p" * 300
    urdf = tmp_path / "r.urdf"
    urdf.write_text(ROBOT.format(arm=MESH.format(f"package://{name}/x.stl")))
    code, text = _run(runner, "spheres", urdf)
    assert code == 2 and f"cannot find ROS package '{name}'" in text and "Traceback" not in text
    code, text = _run(runner, "spheres", urdf, "--package-path", f"{name}={name}")
    assert code == 2 and "cannot be used: File name too long" in text and "Traceback" not in text


@pytest.mark.parametrize("command", ["convert", "expand", "spheres"])
def test_a_package_path_that_is_no_directory_is_an_input_error_even_if_unused(
    runner: CliRunner, tmp_path: Path, command: str
) -> None:
    """A mistyped --package-path is said at once (exit 2), also when the robot turns out not
    to use that package; it was accepted without a word."""
    urdf = tmp_path / "r.urdf.xacro"
    xacro = 'xmlns:xacro="http://www.ros.org/wiki/xacro" name="r"'
    urdf.write_text(ROBOT.format(arm="").replace('name="r"', xacro, 1))
    code, text = _run(runner, command, urdf, "--package-path", f"unused={tmp_path / 'nope'}")
    assert code == 2 and "--package-path unused=" in text and "no such directory" in text
    code, text = _run(runner, command, urdf, "--package-path", f"unused={urdf}")
    assert code == 2 and "not a directory" in text and "Traceback" not in text


def test_lint_fast_path_reads_allow_missing_meshes() -> None:
    from xrdf_tools.cli.commands.lint_core import parse_fast

    args = parse_fast(["lint", "a.xrdf", "--urdf", "u.urdf", "--allow-missing-meshes"])
    assert args is not None and args.allow_missing_meshes
    args = parse_fast(["lint", "a.xrdf", "--urdf", "u.urdf"])
    assert args is not None and not args.allow_missing_meshes
