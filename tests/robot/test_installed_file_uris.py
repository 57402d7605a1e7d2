"""``file://`` meshes of a URDF expanded on another machine: an install space's ``share/PKG/``.

Reachy 2's published URDF names its meshes
``file:///home/reachy/reachy_ws/install/arm_description/share/arm_description/meshes/…``, what
``$(find arm_description)`` expanded to on the robot's computer (and URDFs generated against a
ROS install name ``/opt/ros/DISTRO/share/PKG/…``). Elsewhere every such mesh was "not found"
and no option could point at the package: only editing the URDF helped. A missing path in a
``share/PKG/`` folder is now read from package ``PKG`` as found here (``--package-path`` or the
nearby search), as ``package://PKG/…`` would be.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from typer.testing import CliRunner

from xrdf_tools.cli import app
from xrdf_tools.robot.packages import PackageResolver
from xrdf_tools.util.errors import SourceError


def _box(path: Path, size: float = 0.1) -> None:
    import trimesh

    path.parent.mkdir(parents=True, exist_ok=True)
    trimesh.creation.box((size, size, size)).export(path)


def _package(folder: Path, name: str) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "package.xml").write_text(f"<package><name>{name}</name></package>\n")
    _box(folder / "meshes" / "hand.stl")
    return folder


def _installed_uri(tmp_path: Path, name: str = "robo") -> str:
    """A path in another machine's install space: nothing is there on this one."""
    gone = tmp_path / "elsewhere" / "ws" / "install" / name / "share" / name
    return f"file://{gone}/meshes/hand.stl"


def test_a_missing_install_path_is_read_from_the_given_package(tmp_path: Path) -> None:
    pkg = _package(tmp_path / "src" / "robo_description", "robo")
    resolver = PackageResolver(tmp_path / "urdf" / "r.urdf", {"robo": str(pkg)})
    assert resolver.resolve_uri(_installed_uri(tmp_path)) == pkg / "meshes" / "hand.stl"


def test_a_missing_install_path_is_read_from_the_package_found_nearby(tmp_path: Path) -> None:
    pkg = _package(tmp_path / "robo", "robo")
    resolver = PackageResolver(tmp_path / "r.urdf", {})
    assert resolver.resolve_uri(_installed_uri(tmp_path)) == pkg / "meshes" / "hand.stl"


def test_a_path_that_exists_or_names_no_package_is_kept(tmp_path: Path) -> None:
    _package(tmp_path / "robo", "robo")
    here = tmp_path / "share" / "robo" / "meshes" / "hand.stl"  # it exists: read as written
    _box(here)
    resolver = PackageResolver(tmp_path / "r.urdf", {})
    assert resolver.resolve_uri(f"file://{here}") == here
    plain = tmp_path / "gone" / "meshes" / "hand.stl"  # no share/PKG/: the path as written
    assert resolver.resolve_uri(f"file://{plain}") == plain


def test_a_package_not_found_names_the_option(tmp_path: Path) -> None:
    resolver = PackageResolver(tmp_path / "r.urdf", {})
    with pytest.raises(SourceError) as e:
        resolver.resolve_uri(_installed_uri(tmp_path, "nowhere_pkg"))
    assert "nor in package 'nowhere_pkg' here" in e.value.message
    assert "--package-path nowhere_pkg=DIR" in e.value.message


def test_spheres_fits_a_mesh_named_by_an_install_path(tmp_path: Path) -> None:
    pkg = _package(tmp_path / "pkgs" / "robo_description", "robo")
    urdf = tmp_path / "r.urdf"
    urdf.write_text(
        '<robot name="r"><link name="hand"><collision><geometry>'
        f'<mesh filename="{_installed_uri(tmp_path)}"/></geometry></collision></link></robot>\n'
    )
    out = tmp_path / "out.xrdf"
    args = ["spheres", str(urdf), "-o", str(out), "--package-path", f"robo={pkg}"]
    result = CliRunner().invoke(app, args)
    assert result.exit_code == 0, result.output
    assert "hand:" in out.read_text()


def test_dot_dot_is_taken_as_on_the_machine_that_wrote_the_path(tmp_path: Path) -> None:
    """``share/robo/../arm/…`` is package arm's file (it was read from robo's folder + '../arm'),
    and ``share/robo/../../x/…`` names no package: never a file above robo's folder here."""
    robo = _package(tmp_path / "src" / "robo", "robo")
    arm = _package(tmp_path / "elsewhere" / "arm_description", "arm")
    _box(tmp_path / "x" / "meshes" / "hand.stl")  # where robo/../../x/… lands on this machine
    resolver = PackageResolver(tmp_path / "r.urdf", {"robo": str(robo), "arm": str(arm)})
    gone = tmp_path / "gone" / "install" / "share"
    got = resolver.resolve_uri(f"file://{gone}/robo/../arm/meshes/hand.stl")
    assert got == arm / "meshes" / "hand.stl"
    above = f"{gone}/robo/../../x/meshes/hand.stl"
    assert resolver.resolve_uri(f"file://{above}") == Path(above)


def test_a_windows_install_path_is_read_from_the_package(tmp_path: Path) -> None:
    pkg = _package(tmp_path / "robo", "robo")
    resolver = PackageResolver(tmp_path / "r.urdf", {"robo": str(pkg)})
    for uri in (
        "file:///C:/dev/ws/install/share/robo/meshes/hand.stl",
        "file:///C:\\dev\\ws\\install\\share\\robo\\meshes\\hand.stl",
    ):
        assert resolver.resolve_uri(uri) == pkg / "meshes" / "hand.stl", uri
