"""``xrdf export curobo`` writes files a user can commit: paths relative to the output, and a
xacro's expanded URDF beside it (cuRobo cannot load a xacro)."""

from __future__ import annotations

import importlib.util
import os
import re
from pathlib import Path

import pytest
import yaml
from typer.testing import CliRunner

from tests.paths import UR10E_URDF, UR10E_XRDF
from xrdf_tools.cli import app
from xrdf_tools.convert.core import ConvertOptions
from xrdf_tools.convert.pipeline import convert_robot
from xrdf_tools.robot.urdf_source import load_urdf
from xrdf_tools.robot.xacro_source import expand_xacro


def _kinematics(path: Path) -> dict[str, object]:
    data = yaml.safe_load(path.read_text())
    kin = data["robot_cfg"]["kinematics"]
    assert isinstance(kin, dict)
    return kin


def test_paths_relative_to_the_output_by_default(runner: CliRunner, tmp_path: Path) -> None:
    out = tmp_path / "deep" / "cfg" / "ur10e.yml"
    out.parent.mkdir(parents=True)
    args = ["export", "curobo", str(UR10E_XRDF), "--urdf", str(UR10E_URDF), "-o", str(out)]
    r = runner.invoke(app, args)
    assert r.exit_code == 0, r.output
    kin = _kinematics(out)
    urdf_path, root = str(kin["urdf_path"]), str(kin["asset_root_path"])
    assert not os.path.isabs(urdf_path) and not os.path.isabs(root) and "\\" not in urdf_path
    # joined to the output's directory, they name the input URDF and its directory
    assert (out.parent / urdf_path).resolve() == UR10E_URDF.resolve()
    assert (out.parent / root).resolve() == UR10E_URDF.parent.resolve()
    assert "external_asset_path" in out.read_text()  # the header says how cuRobo finds it
    # moved together with the URDF, the pair still fits: nothing names this machine
    assert str(tmp_path) not in out.read_text()


def test_absolute_paths_on_request(runner: CliRunner, tmp_path: Path) -> None:
    out = tmp_path / "ur10e.yml"
    args = ["export", "curobo", str(UR10E_XRDF), "--urdf", str(UR10E_URDF), "-o", str(out)]
    r = runner.invoke(app, [*args, "--absolute-paths"])
    assert r.exit_code == 0, r.output
    kin = _kinematics(out)
    assert kin["urdf_path"] == os.path.abspath(UR10E_URDF)
    assert kin["asset_root_path"] == os.path.dirname(os.path.abspath(UR10E_URDF))
    assert "external_asset_path" not in out.read_text()


def test_stdout_paths_are_relative_to_the_current_directory(
    runner: CliRunner, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    r = runner.invoke(app, ["export", "curobo", str(UR10E_XRDF), "--urdf", str(UR10E_URDF)])
    assert r.exit_code == 0, r.output
    kin = yaml.safe_load(r.stdout)["robot_cfg"]["kinematics"]
    assert (tmp_path / kin["urdf_path"]).resolve() == UR10E_URDF.resolve()


def _px150() -> tuple[Path, dict[str, str]]:
    spec = importlib.util.find_spec("rtbdata")
    if spec is None or not spec.submodule_search_locations:
        pytest.skip("rtb-data is not installed")
    root = Path(next(iter(spec.submodule_search_locations))) / "xacro"
    xacro = root / "trossen_descriptions/urdf/px150.urdf.xacro"
    if not xacro.is_file():
        pytest.skip("rtb-data has no px150 xacro")
    return xacro, {"trossen_descriptions": str(root / "trossen_descriptions")}


def test_xacro_gets_its_expanded_urdf_beside_the_output(runner: CliRunner, tmp_path: Path) -> None:
    xacro, packages = _px150()
    converted = convert_robot(xacro, ConvertOptions(), package_paths=packages, lint=False)
    xrdf = tmp_path / "px150.xrdf"
    xrdf.write_text(converted.text)
    out = tmp_path / "cfg" / "px150.yml"
    out.parent.mkdir()
    pkg = [f"--package-path=trossen_descriptions={packages['trossen_descriptions']}"]
    base = ["export", "curobo", str(xrdf), "--urdf", str(xacro), *pkg]
    r = runner.invoke(app, [*base, "-o", str(out)])
    assert r.exit_code == 0, r.output
    expanded = out.parent / "px150.urdf"
    assert f"expanded URDF to {expanded}" in r.output  # named in the message
    assert expanded.read_text() == expand_xacro(xacro, package_paths=packages)
    assert load_urdf(expanded).robot.name == converted.robot.name
    kin = _kinematics(out)
    assert kin["urdf_path"] == "px150.urdf"
    # cuRobo strips package:// from each mesh name and joins it to asset_root_path
    meshes = re.findall(r'filename="([^"]+)"', expanded.read_text())
    assert meshes and all(m.startswith("package://trossen_descriptions/") for m in meshes)
    root = out.parent / kin["asset_root_path"]
    assert all((root / m.replace("package://", "")).is_file() for m in meshes)
    assert "export-mesh-paths" not in r.output
    # an explicit place for it; stdout alone has no "beside": a usage error
    other = tmp_path / "elsewhere.urdf"
    r = runner.invoke(app, [*base, "-o", str(out), "--expanded-urdf", str(other)])
    assert r.exit_code == 0, r.output
    assert other.is_file() and _kinematics(out)["urdf_path"] == "../elsewhere.urdf"
    r = runner.invoke(app, base)
    assert r.exit_code == 2 and "-o FILE" in r.output and "Traceback" not in r.output
    # never over an input
    r = runner.invoke(app, [*base, "-o", str(out), "--expanded-urdf", str(xrdf)])
    assert r.exit_code == 2 and "refusing to overwrite" in r.output


def _workspace_robot(tmp_path: Path, relative_mesh: bool) -> Path:
    """A package ``my_robot`` in ``ws/src``: its URDF names two meshes as
    package://my_robot/…, and (``relative_mesh``) a third relative to the URDF's folder, which
    no directory serves together with the others."""
    import trimesh

    pkg = tmp_path / "ws" / "src" / "my_robot"
    (pkg / "meshes").mkdir(parents=True)
    (pkg / "urdf").mkdir()
    (pkg / "package.xml").write_text("<package><name>my_robot</name></package>")
    for name in ("a.stl", "c.stl"):
        trimesh.creation.box(extents=(0.1, 0.1, 0.1)).export(pkg / "meshes" / name)
    second = '<collision><geometry><mesh filename="package://my_robot/meshes/c.stl"/></geometry>'
    second += "</collision>"
    if relative_mesh:
        second += '<visual><geometry><mesh filename="parts/b.stl"/></geometry></visual>'
        (pkg / "urdf" / "parts").mkdir()
        trimesh.creation.box(extents=(0.1, 0.1, 0.1)).export(pkg / "urdf" / "parts" / "b.stl")
    urdf = pkg / "urdf" / "r.urdf"
    urdf.write_text(
        '<robot name="r"><link name="base"><collision><geometry>'
        '<mesh filename="package://my_robot/meshes/a.stl"/></geometry></collision></link>'
        f'<link name="arm">{second}</link>'
        '<joint name="j" type="revolute"><parent link="base"/><child link="arm"/>'
        '<axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>'
    )
    return urdf


@pytest.mark.parametrize("relative_mesh", [False, True])
def test_asset_root_path_is_where_curobo_finds_the_meshes(
    runner: CliRunner, tmp_path: Path, relative_mesh: bool
) -> None:
    """cuRobo strips package:// from a mesh name and joins the rest to asset_root_path: the
    export names the directory holding the package (ws/src), not the URDF's folder; a mesh no
    one directory serves with the others is said (export-mesh-paths)."""
    urdf = _workspace_robot(tmp_path, relative_mesh)
    xrdf = tmp_path / "r.xrdf"
    xrdf.write_text(convert_robot(urdf, ConvertOptions(), lint=False).text)
    out = tmp_path / "cfg" / "r.yml"
    out.parent.mkdir()
    r = runner.invoke(app, ["export", "curobo", str(xrdf), "--urdf", str(urdf), "-o", str(out)])
    assert r.exit_code == 0, r.output
    root = (out.parent / str(_kinematics(out)["asset_root_path"])).resolve()
    assert root == (tmp_path / "ws" / "src").resolve()
    assert (root / "my_robot/meshes/a.stl").is_file()
    said = [ln for ln in r.output.splitlines() if "export-mesh-paths" in ln]
    if relative_mesh:
        assert len(said) == 1 and "1 mesh file name(s)" in said[0] and "parts/b.stl" in said[0]
    else:
        assert said == []


def test_a_package_in_a_folder_of_another_name_says_how_curobo_finds_its_meshes(
    runner: CliRunner, tmp_path: Path
) -> None:
    """A clone named after its repository (``Universal_Robots_ROS2_Description`` holds
    ``ur_description``) serves no mesh to cuRobo, which joins ``my_robot/meshes/…`` to
    asset_root_path: the warning names the package, its folder and the link that fixes it,
    and following it leaves nothing to say."""
    urdf = _workspace_robot(tmp_path, relative_mesh=False)
    clone = urdf.parent.parent.rename(tmp_path / "ws" / "src" / "My_Robot_Repo")
    urdf = clone / "urdf" / "r.urdf"
    xrdf = tmp_path / "r.xrdf"
    xrdf.write_text(convert_robot(urdf, ConvertOptions(), lint=False).text)
    out = tmp_path / "cfg" / "r.yml"
    export = ["export", "curobo", str(xrdf), "--urdf", str(urdf), "-o", str(out)]
    r = runner.invoke(app, [*export, "--package-path", f"my_robot={clone}"])
    assert r.exit_code == 0, r.output
    said = [ln for ln in r.output.splitlines() if "export-mesh-paths" in ln]
    assert len(said) == 1 and "2 mesh file name(s)" in said[0]
    assert (
        f"Package 'my_robot' is the folder {clone}, which is not named after it, so no "
        f"directory serves its meshes: make a link named 'my_robot' to it (ln -s {clone} "
        "DIR/my_robot) and export again with --package-path my_robot=DIR/my_robot"
    ) in said[0]
    links = tmp_path / "links"
    links.mkdir()
    (links / "my_robot").symlink_to(clone)
    r = runner.invoke(app, [*export, "--package-path", f"my_robot={links / 'my_robot'}"])
    assert r.exit_code == 0 and "export-mesh-paths" not in r.output, r.output
    root = out.parent / str(_kinematics(out)["asset_root_path"])
    assert (root / "my_robot/meshes/a.stl").is_file()


def test_packages_in_two_workspaces_say_how_to_put_them_side_by_side(
    runner: CliRunner, tmp_path: Path
) -> None:
    """A Kinova arm from one checkout with a Robotiq gripper from another: cuRobo reads every
    mesh from one asset_root_path, so the meshes of one package are not found; the warning
    names both packages' folders and the links that put them side by side, and following it
    leaves nothing to say."""
    import trimesh

    urdf = _workspace_robot(tmp_path, relative_mesh=False)
    gripper = tmp_path / "other" / "src" / "my_gripper"
    (gripper / "meshes").mkdir(parents=True)
    (gripper / "package.xml").write_text("<package><name>my_gripper</name></package>")
    for name in ("jaw.stl", "palm.stl", "pad.stl"):
        trimesh.creation.box(extents=(0.05, 0.05, 0.05)).export(gripper / "meshes" / name)
    parts = "".join(
        f'<collision><geometry><mesh filename="package://my_gripper/meshes/{n}"/></geometry>'
        "</collision>"
        for n in ("jaw.stl", "palm.stl", "pad.stl")
    )
    urdf.write_text(
        urdf.read_text().replace(
            "</robot>",
            f'<link name="hand">{parts}</link><joint name="g" type="fixed"><parent link="arm"/>'
            '<child link="hand"/></joint></robot>',
        )
    )
    xrdf = tmp_path / "r.xrdf"
    xrdf.write_text(convert_robot(urdf, ConvertOptions(), lint=False).text)
    out = tmp_path / "cfg" / "r.yml"
    export = ["export", "curobo", str(xrdf), "--urdf", str(urdf), "-o", str(out)]
    robot_pkg = urdf.parent.parent
    r = runner.invoke(app, [*export, "--package-path", f"my_gripper={gripper}"])
    assert r.exit_code == 0, r.output
    said = [ln for ln in r.output.splitlines() if "export-mesh-paths" in ln]
    assert len(said) == 1 and "2 mesh file name(s)" in said[0]  # my_robot's: my_gripper wins
    assert (
        f"The packages are in different folders (my_gripper in {gripper.parent}, my_robot in "
        f"{robot_pkg.parent}): link them side by side (mkdir DIR; ln -s {gripper} {robot_pkg} "
        "DIR/) and export again with --package-path my_gripper=DIR/my_gripper --package-path "
        "my_robot=DIR/my_robot"
    ) in said[0]
    side = tmp_path / "assets"
    side.mkdir()
    for folder in (gripper, robot_pkg):
        (side / folder.name).symlink_to(folder)
    links = [f"--package-path=my_gripper={side / 'my_gripper'}"]
    links.append(f"--package-path=my_robot={side / 'my_robot'}")
    r = runner.invoke(app, [*export, *links])
    assert r.exit_code == 0 and "export-mesh-paths" not in r.output, r.output
    root = out.parent / str(_kinematics(out)["asset_root_path"])
    assert (root / "my_gripper/meshes/jaw.stl").is_file()
    assert (root / "my_robot/meshes/a.stl").is_file()


_URDF_USING_XACRO = """<?xml version="1.0"?>
<robot name="arm" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:property name="reach" value="0.3"/>
  <link name="base"/>
  <link name="tip"/>
  <joint name="j1" type="revolute">
    <parent link="base"/><child link="tip"/><origin xyz="0 0 ${reach}"/><axis xyz="0 1 0"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/>
  </joint>
</robot>
"""


def test_a_urdf_that_uses_xacro_is_said_to_be_one(runner: CliRunner, tmp_path: Path) -> None:
    """Nextage Open's NextageOpen.urdf holds xacro macros and an include: the note said 'cuRobo
    cannot load a xacro' of a file the user had passed as a URDF, without saying why it was
    one."""
    urdf = tmp_path / "arm.urdf"
    urdf.write_text(_URDF_USING_XACRO)
    xrdf = tmp_path / "arm.xrdf"
    r = runner.invoke(app, ["convert", str(urdf), "-q", "-o", str(xrdf)])
    assert r.exit_code == 0, r.output
    out = tmp_path / "cfg" / "arm.yml"
    r = runner.invoke(app, ["export", "curobo", str(xrdf), "--urdf", str(urdf), "-o", str(out)])
    assert r.exit_code == 0, r.output
    assert (
        "info export-expanded-urdf arm.urdf is a xacro (the .urdf uses xacro: macros, includes "
        "or $(...)), which cuRobo cannot load: wrote the expanded URDF to "
        f"{out.with_suffix('.urdf')}"
    ) in r.stderr
    r = runner.invoke(app, ["export", "curobo", str(xrdf), "--urdf", str(urdf)])
    assert r.exit_code == 2
    assert f"{urdf} is a xacro (the .urdf uses xacro" in r.stderr


def _file_uri_robot(tmp_path: Path, suffix: str) -> Path:
    """A robot whose meshes are named ``file://`` + an absolute path with a space (``%20``), as
    ROS 2 xacros write ``file://$(find pkg)/meshes/…``; a xacro when ``suffix`` is
    ``.urdf.xacro``."""
    import trimesh

    meshes = tmp_path / "my robot" / "meshes"
    meshes.mkdir(parents=True)
    trimesh.creation.box(extents=(0.05, 0.05, 0.2)).export(meshes / "a.stl")
    uri = "file://" + str(meshes / "a.stl").replace(" ", "%20")
    robot = tmp_path / f"arm{suffix}"
    robot.write_text(
        '<robot name="arm" xmlns:xacro="http://www.ros.org/wiki/xacro"><link name="base"/>'
        f'<link name="tip"><collision><geometry><mesh filename="{uri}"/></geometry></collision>'
        '</link><joint name="j1" type="revolute"><parent link="base"/><child link="tip"/>'
        '<axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="1" velocity="1"/></joint></robot>'
    )
    return robot


def test_file_uri_meshes_are_plain_paths_in_the_expanded_urdf(
    runner: CliRunner, tmp_path: Path
) -> None:
    """cuRobo strips only package:// from a mesh name and joins the rest to asset_root_path, so
    a file:// name (Neuromeka's Indy xacro: file://$(find indy_description)/meshes/…) is never
    found; the warning said it joins names "to that one directory (package:// stripped)" and
    offered nothing. The expanded URDF that export writes names those meshes by their plain
    paths, which cuRobo reads; a URDF export does not write is warned about, naming file://."""
    xacro = _file_uri_robot(tmp_path, ".urdf.xacro")
    xrdf = tmp_path / "arm.xrdf"
    r = runner.invoke(app, ["convert", str(xacro), "-q", "-o", str(xrdf)])
    assert r.exit_code == 0, r.output
    out = tmp_path / "cfg" / "arm.yml"
    r = runner.invoke(app, ["export", "curobo", str(xrdf), "--urdf", str(xacro), "-o", str(out)])
    assert r.exit_code == 0, r.output
    assert "export-mesh-paths" not in r.output, r.output
    expanded = out.with_suffix(".urdf").read_text()
    assert "file://" not in expanded and "%20" not in expanded
    mesh = str(tmp_path / "my robot" / "meshes" / "a.stl")
    assert f'filename="{mesh}"' in expanded
    assert "its 1 file:// mesh name(s) written as plain paths" in r.output, r.output
    # as cuRobo joins it (os.path.join keeps an absolute name), the mesh is found
    root = out.parent / str(_kinematics(out)["asset_root_path"])
    assert Path(os.path.join(root, mesh)).is_file()
    # a URDF the export does not write: said, with the way out
    urdf = _file_uri_robot(tmp_path / "plain", ".urdf")
    r = runner.invoke(app, ["export", "curobo", str(xrdf), "--urdf", str(urdf), "-o", str(out)])
    (said,) = [ln for ln in r.output.splitlines() if "export-mesh-paths" in ln]
    assert "file://" in said and "cuRobo keeps a file:// name as written" in said, said


def test_asset_root_path_is_the_parent_a_relative_mesh_was_found_in(
    runner: CliRunner, tmp_path: Path
) -> None:
    """A relative mesh name found in a parent of the URDF's folder (IsaacGymEnvs'
    ``assets/urdf/kuka_allegro_description/kuka_allegro.urdf`` names
    ``kuka_allegro_description/meshes/…``, cuRobo's tm12 names ``meshes/…`` from ``urdf/``):
    cuRobo joins the name to asset_root_path as written, so that parent is the root, not the
    URDF's folder, where no such file is."""
    import trimesh

    assets = tmp_path / "assets"
    pkg = assets / "arm_description"
    (pkg / "meshes").mkdir(parents=True)
    trimesh.creation.box(extents=(0.1, 0.1, 0.1)).export(pkg / "meshes" / "a.stl")
    urdf = pkg / "arm.urdf"
    urdf.write_text(
        '<robot name="r"><link name="base"/><link name="arm"><collision><geometry>'
        '<mesh filename="arm_description/meshes/a.stl"/></geometry></collision></link>'
        '<joint name="j" type="revolute"><parent link="base"/><child link="arm"/>'
        '<axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>'
    )
    xrdf = tmp_path / "r.xrdf"
    xrdf.write_text(convert_robot(urdf, ConvertOptions(), lint=False).text)
    out = tmp_path / "cfg" / "r.yml"
    out.parent.mkdir()
    r = runner.invoke(app, ["export", "curobo", str(xrdf), "--urdf", str(urdf), "-o", str(out)])
    assert r.exit_code == 0 and "export-mesh-paths" not in r.output, r.output
    root = (out.parent / str(_kinematics(out)["asset_root_path"])).resolve()
    assert root == assets.resolve()
    assert (root / "arm_description/meshes/a.stl").is_file()
