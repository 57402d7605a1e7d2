"""The expanded URDF ``export curobo`` writes names ``file://`` meshes by their plain paths
(:func:`xrdf_tools.export.curobo_assets.with_plain_file_names`): the rewritten attribute reads
back, through an XML parser, as exactly the path the robot loader resolved, and the document
stays well-formed, whatever the name holds."""

from __future__ import annotations

from pathlib import Path

import pytest
import trimesh
from lxml import etree
from typer.testing import CliRunner

from xrdf_tools.cli import app
from xrdf_tools.export.curobo_assets import with_plain_file_names
from xrdf_tools.robot.packages import PackageResolver


@pytest.mark.parametrize(
    "attribute, path",
    [
        ('filename="file:///m/a%20b.stl"', "/m/a b.stl"),
        ('filename="file:///m/a&amp;b%26c.stl"', "/m/a&b&c.stl"),
        ('filename="file:///m/a&#32;b.stl"', "/m/a b.stl"),  # was written '&amp;#32;'
        ('filename="file:///m/it\'s.stl"', "/m/it's.stl"),  # was left as file://
        ("filename='file:///m/say \"hi\".stl'", '/m/say "hi".stl'),
        ('filename="file:///m/a&quot;b.stl"', '/m/a"b.stl'),
        ('filename="file:///m/line%0Abreak.stl"', "/m/line\nbreak.stl"),  # was read as a space
        ('filename="file:///m/tab%09.stl"', "/m/tab\t.stl"),
        ('filename="file:///m/x/%2e%2e/%2Fy.stl"', "/m/x/..//y.stl"),
        ('filename="file:///m/split\n  over.stl"', "/m/split   over.stl"),  # as XML reads it
    ],
)
def test_the_plain_name_reads_back_as_the_path_the_loader_resolved(
    attribute: str, path: str
) -> None:
    text = f'<robot name="r"><link name="l"><visual><geometry><mesh {attribute}/>'
    text += "</geometry></visual></link></robot>"
    loaded = etree.fromstring(text.encode()).find(".//mesh").get("filename")
    assert str(PackageResolver(Path("/r.urdf"), {}).resolve_uri(loaded)) == str(Path(path))
    plain, count = with_plain_file_names(text)
    assert count == 1
    assert etree.fromstring(plain.encode()).find(".//mesh").get("filename") == path


@pytest.mark.parametrize(
    "attribute",
    [
        'filename="file:///m/nul%00.stl"',  # was written as a NUL: not XML any more
        'filename="file:///m/bell%07.stl"',
        'filename="file:///m/&undefined;.stl"',
    ],
)
def test_a_name_no_xml_can_hold_is_left_as_it_was(attribute: str) -> None:
    text = f"<robot><mesh {attribute}/></robot>"
    assert with_plain_file_names(text) == (text, 0)


def test_export_writes_a_well_formed_urdf_naming_every_mesh_the_loader_read(
    tmp_path: Path,
) -> None:
    """Through ``export curobo`` on a xacro: a name with an apostrophe, an escaped space and
    an escaped NUL; the NUL one is no file (said where the robot is read) and stays as it was."""
    meshes = tmp_path / "m"
    meshes.mkdir()
    for name in ("it's a.stl", "b.stl"):
        trimesh.creation.box(extents=(0.05, 0.05, 0.05)).export(meshes / name)
    uris = [f"file://{meshes}/it's%20a.stl", f"file://{meshes}/b%00.stl"]
    links = "".join(
        f'<link name="l{i}"><visual><geometry><mesh filename="{u}"/></geometry></visual></link>'
        f'<joint name="j{i}" type="revolute"><parent link="base"/><child link="l{i}"/>'
        '<axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>'
        for i, u in enumerate(uris)
    )
    xacro = tmp_path / "r.urdf.xacro"
    xacro.write_text(
        '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro"><link name="base"/>'
        f"{links}</robot>"
    )
    runner = CliRunner()
    xrdf = tmp_path / "r.xrdf"
    r = runner.invoke(app, ["convert", str(xacro), "-q", "-o", str(xrdf)])
    assert r.exit_code == 0, r.output
    out = tmp_path / "cfg" / "r.yml"
    r = runner.invoke(app, ["export", "curobo", str(xrdf), "--urdf", str(xacro), "-o", str(out)])
    assert r.exit_code == 0 and "Traceback" not in r.output, r.output
    assert "its 1 file:// mesh name(s) written as plain paths" in r.output
    names = [m.get("filename") for m in etree.parse(out.with_suffix(".urdf")).iter("mesh")]
    assert names == [f"{meshes}/it's a.stl", uris[1]]
    assert Path(names[0]).is_file()
