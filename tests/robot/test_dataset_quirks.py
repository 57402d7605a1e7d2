"""URDFs as robot collections ship them: each quirk a real description has, reproduced in a
minimal robot, and read as ROS reads it (a located warning) or refused with a located error."""

from __future__ import annotations

from pathlib import Path

from typer.testing import CliRunner

from xrdf_tools.cli import app
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
