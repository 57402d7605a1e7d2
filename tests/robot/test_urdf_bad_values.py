"""URDF values no reader can use (limits, non-finite numbers, mimic offsets, geometry sizes):
one-line input errors naming the URDF, a finding for lint."""

from __future__ import annotations

from pathlib import Path

import pytest
from typer.testing import CliRunner

from tests.cli_checks import MIMIC_URDF, MIMIC_XRDF, copy_replacing, run_cli
from tests.paths import UR10E_URDF, UR10E_XRDF


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        ('lower="-6.283185307179586"', 'lower="-inf"', "lower='-inf': numbers must be finite"),
        ('lower="-6.283185307179586"', 'lower="nan"', "lower='nan': numbers must be finite"),
        (
            '<origin rpy="0 0 0" xyz="0 0 0.1807"/>',
            '<origin rpy="0 0 0" xyz="0 0 inf"/>',
            "must be finite",
        ),
    ],
)
def test_bad_urdf_limits_are_input_errors(
    runner: CliRunner, tmp_path: Path, old: str, new: str, message: str
) -> None:
    urdf = copy_replacing(UR10E_URDF, tmp_path / "bad.urdf", old, new)
    for args in (
        ["report", str(UR10E_XRDF), "--urdf", str(urdf), "-n", "10"],
        ["viz", str(UR10E_XRDF), "--urdf", str(urdf), "--png", str(tmp_path / "o.png")],
    ):
        code, out = run_cli(runner, *args)
        assert code == 2 and message in out and f"{urdf}:" in out, (args, out)
    # lint checks the XRDF against the URDF: no reader loads it with this one, a finding
    code, out = run_cli(runner, "lint", str(UR10E_XRDF), "--urdf", str(urdf))
    assert code == 1 and "urdf-invalid" in out and message in out and f"{urdf}:" in out, out


def test_mimic_offset_inf(runner: CliRunner, tmp_path: Path) -> None:
    urdf = copy_replacing(MIMIC_URDF, tmp_path / "m.urdf", 'offset="0.1"', 'offset="inf"')
    code, out = run_cli(runner, "convert", str(urdf))
    assert code == 2 and "<mimic> offset='inf': numbers must be finite" in out


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        ('<box size="0.25 0.06 0.06"/>', '<box size="1 2"/>', "<box> size='1 2' must be 3 numbers"),
        ('<sphere radius="0.02"/>', '<sphere radius="-1"/>', "must not be negative"),
        ('<cylinder radius="0.08" length="0.1"/>', '<cylinder radius="0.08"/>', "no 'length'"),
    ],
)
def test_bad_geometry_is_an_input_error(
    runner: CliRunner, tmp_path: Path, old: str, new: str, message: str
) -> None:
    urdf = copy_replacing(MIMIC_URDF, tmp_path / "g.urdf", old, new)
    code, out = run_cli(runner, "report", str(MIMIC_XRDF), "--urdf", str(urdf), "-n", "10")
    assert code == 2 and message in out


def test_a_bad_value_in_a_tag_written_one_attribute_a_line_is_located_at_its_attribute(
    runner: CliRunner, tmp_path: Path
) -> None:
    # SolidWorks' exporter writes each attribute on a line of its own (CRLF line ends); the
    # parser places an element where its start tag ends, so the error pointed at rpy's line
    lines = [
        '<robot name="r">',
        '  <link name="base"><visual>',
        "    <origin",
        '      xyz="0 0 abc"',
        '      rpy="0 0 0" />',
        '    <geometry><box size="0.1 0.1 0.1"/></geometry></visual></link>',
        '  <link name="tip"><visual><geometry><box size="0.1 0.1 0.1"/></geometry>',
        '    <material name="m"><color',
        '      rgba="1 1 1 1 1" /></material></visual></link>',
        '  <joint name="j" type="fixed"><parent link="base"/><child link="tip"/></joint>',
        "</robot>",
    ]
    urdf = tmp_path / "r.urdf"
    urdf.write_bytes("\r\n".join(lines).encode())
    code, out = run_cli(runner, "inspect", str(urdf))
    assert code == 2, out
    assert f"{urdf}:4: link 'base' <visual> xyz='0 0 abc' is not a list of numbers" in out
    # a warning about such a tag too: the colour's rgba line
    urdf.write_bytes("\r\n".join(lines).replace("0 0 abc", "0 0 0").encode())
    code, out = run_cli(runner, "inspect", str(urdf))
    assert code == 0, out
    assert f"{urdf}:9: warning urdf-color-ignored" in out


@pytest.mark.parametrize(
    ("root", "said"),
    [
        ('<sdf version="1.6"><model name="m"/></sdf>', "an SDF model (Gazebo, pybullet)"),
        ('<mujoco model="m"><worldbody/></mujoco>', "an MJCF model (MuJoCo)"),
    ],
)
def test_a_simulator_model_given_as_the_robot_says_what_it_is(
    runner: CliRunner, tmp_path: Path, root: str, said: str
) -> None:
    # pybullet ships kuka_with_gripper2.sdf beside model.urdf; onshape-to-robot writes MJCF
    model = tmp_path / "robot.xml"
    model.write_text(f'<?xml version="1.0"?>\n{root}\n')
    code, out = run_cli(runner, "convert", str(model), "-o", str(tmp_path / "o.xrdf"))
    assert code == 2, out
    assert f"{model}:2: the root element must be <robot>" in out and said in out


def test_a_xacro_whose_root_is_not_a_robot_is_located(runner: CliRunner, tmp_path: Path) -> None:
    """A xacro file holding a lone <link> (the fuzzer cut arm.urdf.xacro so): the error
    named the file without a line, since the expansion's lines are not the file's."""
    xacro = tmp_path / "part.urdf.xacro"
    xacro.write_text(
        '<?xml version="1.0"?>\n<!-- a part -->\n'
        "<link name='y'><collision><geometry><sphere radius='0.1'/></geometry></collision></link>\n"
    )
    code, out = run_cli(runner, "convert", str(xacro), "-o", str(tmp_path / "o.xrdf"))
    assert code == 2 and f"{xacro}:3: the root element must be <robot>, not <link>" in out, out
