"""Mesh references of the forms real robot descriptions write besides ``package://`` and a
plain scale: a Gazebo ``model://`` URI, a relative path with URL escapes (``%20`` for a
space), a mirrored part (negative scale)."""

from __future__ import annotations

from pathlib import Path

import pytest

from xrdf_tools.robot import link_geometry as lg
from xrdf_tools.robot.packages import PackageResolver
from xrdf_tools.robot.xacro_source import load_robot
from xrdf_tools.util.errors import XrdfToolsError


def _box_stl(path: Path) -> Path:
    import trimesh

    path.parent.mkdir(parents=True, exist_ok=True)
    trimesh.creation.box((0.1, 0.1, 0.1)).export(path)
    return path


def _robot_with_mesh(urdf: Path, uri: str) -> Path:
    urdf.parent.mkdir(parents=True, exist_ok=True)
    urdf.write_text(
        f'<robot name="r"><link name="base"><collision><geometry><mesh filename="{uri}"/>'
        "</geometry></collision></link></robot>"
    )
    return urdf


def test_a_gazebo_model_uri_is_found_as_a_package_of_that_name(tmp_path: Path) -> None:
    """``model://arm/meshes/base.stl`` (a Gazebo model) reads the folder ``arm`` beside the
    URDF or in a parent, as yourdfpy finds it, or the --package-path directory; a model that
    cannot be found says that model:// names a Gazebo model. It was read as a relative path
    ``model:/arm/...`` below the URDF's folder, not found."""
    mesh = _box_stl(tmp_path / "models" / "arm" / "meshes" / "base.stl")
    urdf = _robot_with_mesh(tmp_path / "models" / "r.urdf", "model://arm/meshes/base.stl")
    assert PackageResolver(urdf).resolve_uri("model://arm/meshes/base.stl") == mesh
    parts = lg.link_geometry(load_robot(urdf), "collision")["base"]
    assert len(parts.parts) == 1 and not parts.failures
    elsewhere = tmp_path / "elsewhere" / "r.urdf"
    given = PackageResolver(elsewhere, {"arm": str(tmp_path / "models" / "arm")})
    assert given.resolve_uri("model://arm/meshes/base.stl") == mesh
    with pytest.raises(XrdfToolsError, match=r"'nope'.*model:// URI names a Gazebo model"):
        PackageResolver(urdf).resolve_uri("model://nope/meshes/base.stl")


def test_a_relative_path_with_url_escapes_is_read_decoded(tmp_path: Path) -> None:
    """``mesh%20dir/base.stl`` names ``mesh dir/base.stl`` (an exporter that writes URIs);
    a file whose name is written with the ``%`` itself is still taken as written."""
    spaced = _box_stl(tmp_path / "mesh dir" / "base.stl")
    urdf = _robot_with_mesh(tmp_path / "r.urdf", "mesh%20dir/base.stl")
    assert PackageResolver(urdf).resolve_uri("mesh%20dir/base.stl") == spaced
    parts = lg.link_geometry(load_robot(urdf), "collision")["base"]
    assert len(parts.parts) == 1 and not parts.failures
    literal = _box_stl(tmp_path / "odd%20name.stl")
    assert PackageResolver(urdf).resolve_uri("odd%20name.stl") == literal
    assert PackageResolver(urdf).resolve_uri("none%20here.stl") == tmp_path / "none%20here.stl"


def test_export_curobo_says_model_uris_are_not_served(tmp_path: Path) -> None:
    """cuRobo strips only ``package://``: a ``model://`` mesh is found from no
    asset_root_path, and export curobo's note counts it."""
    from xrdf_tools.export.curobo_assets import mesh_root

    _box_stl(tmp_path / "arm" / "meshes" / "base.stl")
    urdf = _robot_with_mesh(tmp_path / "r.urdf", "model://arm/meshes/base.stl")
    assert mesh_root(load_robot(urdf)).unserved == ("model://arm/meshes/base.stl",)


def test_a_mirrored_part_is_fitted_mirrored(tmp_path: Path) -> None:
    """A left part written as the right one's millimetre mesh with ``scale="-0.001 0.001
    0.001"`` (the human hand model's left hand) is a closed solid turned outward, spanning the
    mirrored box, and its spheres lie on the mirrored side."""
    import trimesh

    from xrdf_tools.spheres import fit_link_spheres

    mesh = tmp_path / "part.stl"
    trimesh.creation.box((40.0, 20.0, 10.0)).apply_translation((30.0, 0, 0)).export(mesh)
    urdf = tmp_path / "r.urdf"
    urdf.write_text(
        '<robot name="r"><link name="left"><collision><geometry><mesh filename="part.stl" '
        'scale="-0.001 0.001 0.001"/></geometry></collision></link></robot>'
    )
    (part,) = lg.link_geometry(load_robot(urdf), "collision")["left"].parts
    (piece,) = part.pieces
    assert piece.is_watertight and piece.volume > 0
    assert piece.bounds[:, 0].tolist() == pytest.approx([-0.05, -0.01])
    spheres, _ = fit_link_spheres(urdf, per_link=2, seed=0)
    assert all(s.center[0] < 0 for s in spheres["left"])


def test_a_missing_mesh_is_named_without_the_dotdot_of_its_uri(tmp_path: Path) -> None:
    """dex-urdf's UR5e + Shadow hand names ``../../hands/shadow_hand/meshes/collision/
    th_distal_pst.obj``, absent: the path said is the file looked for, not
    ``…/ur5e_shadow/../../hands/…``."""
    urdf = _robot_with_mesh(tmp_path / "a" / "b" / "r.urdf", "../../hands/meshes/none.obj")
    (failure,) = lg.link_geometry(load_robot(urdf), "collision")["base"].failures
    assert f"mesh file not found ({tmp_path / 'hands' / 'meshes' / 'none.obj'})" in failure.reason


def test_a_missing_folder_before_dotdot_is_named_as_looked_for(tmp_path: Path) -> None:
    """'missing/../arm.stl' is not found although arm.stl exists (the system resolves 'x/..'
    only where x exists): the message named 'arm.stl', which exists, as not found."""
    from xrdf_tools.robot.mesh_files import not_a_file

    (tmp_path / "arm.stl").write_bytes(b"solid a\nendsolid a\n")
    why = not_a_file(tmp_path / "missing" / ".." / "arm.stl")
    assert why == f"mesh file not found ({tmp_path / 'missing' / '..' / 'arm.stl'})"
    why = not_a_file(tmp_path / "meshes" / ".." / "gone.stl")  # nothing there: the short name
    assert why == f"mesh file not found ({tmp_path / 'gone.stl'})"
