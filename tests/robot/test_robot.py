"""The frozen Robot value: built once by the loader, views cached, accepted by entry points."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest

from tests.paths import UR10E_URDF, UR10E_XRDF
from tests.robots import robot_urdf
from xrdf_tools.export.curobo import to_curobo
from xrdf_tools.lint import lint_text
from xrdf_tools.robot.core import Robot, as_robot
from xrdf_tools.robot.input_files import robot_input_files
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


def _every_real_urdf() -> list[object]:
    from tests.robots import robots_dir

    root = robots_dir()
    if root is None:
        return [pytest.param(None, marks=pytest.mark.skip(reason="example-robot-data absent"))]
    return [pytest.param(p, id=p.stem) for p in sorted(root.rglob("*.urdf"))]


@pytest.mark.slow
def test_the_own_parse_reads_every_real_urdf_as_yourdfpy_does() -> None:
    """Names, order and every joint number (the origin bit for bit) of the Robot's own XML
    parse equal yourdfpy's, on every URDF of example-robot-data that loads."""
    from xrdf_tools.robot.urdf_joints import joint_info
    from xrdf_tools.util.errors import XrdfToolsError

    compared = 0
    for param in _every_real_urdf():
        path = param.values[0]  # type: ignore[attr-defined]
        if path is None:
            pytest.skip("example-robot-data absent")
        try:
            robot = load_robot(path)
        except XrdfToolsError:
            continue
        yourdf = robot.urdf.robot
        assert robot.name == yourdf.name
        assert robot.links == tuple(link.name for link in yourdf.links)
        assert dict(robot.collision_counts) == {
            link.name: len(link.collisions) for link in yourdf.links if link.collisions
        }
        theirs = {j.name: joint_info(j, robot.joint_lines.get(j.name)) for j in yourdf.joints}
        assert list(robot.joints) == list(theirs)
        for name, joint in robot.joints.items():
            assert joint == theirs[name], name  # equality compares the origin's bytes
        compared += 1
    assert compared >= 30


def test_a_command_that_reads_no_geometry_imports_no_geometry_library(tmp_path: Path) -> None:
    """`xrdf report` and `xrdf convert` (without spheres) build the Robot from the project's
    own parse: yourdfpy, trimesh and scipy are never imported (most of a short run's time),
    also when ``-o`` names a file (checked against the robot's mesh files)."""
    import subprocess
    import sys

    out = tmp_path / "ur10e.xrdf"
    code = (
        "import sys\n"
        "from xrdf_tools.cli import main\n"
        f"xrdf, urdf, out = {str(UR10E_XRDF)!r}, {str(UR10E_URDF)!r}, {str(out)!r}\n"
        "for argv in (['report', xrdf, '--urdf', urdf, '--samples', '200', '-q'],\n"
        "             ['convert', urdf, '-q', '-o', '-'], ['convert', urdf, '-q', '-o', out]):\n"
        "    sys.argv = ['xrdf', *argv]\n"
        "    try:\n"
        "        main()\n"
        "    except SystemExit as e:\n"
        "        print('EXIT', e.code)\n"
        "heavy = sorted(m for m in ('yourdfpy', 'trimesh', 'scipy', 'matplotlib', 'shapely')\n"
        "               if m in sys.modules)\n"
        "print('HEAVY', heavy)\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert "HEAVY []" in done.stdout, done.stdout + done.stderr
    assert "EXIT 2" not in done.stdout, done.stdout + done.stderr


@pytest.mark.parametrize("name", ["pr2", "talos"])
def test_input_files_from_the_xml_are_those_yourdfpy_names(name: str) -> None:
    """The mesh files an output is checked against, read from the checked XML tree, are the
    ones of the yourdfpy object (same files, same order), on robots with hundreds of meshes."""
    robot = load_robot(robot_urdf(name))
    bare = load_urdf(robot_urdf(name))
    bare_robot = Robot(prebuilt=bare, path=robot.path, package_paths=robot.package_paths)
    from_xml = robot_input_files(robot)
    assert len(from_xml) > 20 and all(p.is_file() for p in from_xml)
    assert from_xml == robot_input_files(bare_robot)
