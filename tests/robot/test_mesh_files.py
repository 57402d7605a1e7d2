"""COLLADA meshes read as ROS reads them (:mod:`xrdf_tools.robot.mesh_files`): the file's
``<unit meter>`` applied, and a node bound to a material the file does not define kept.

Both come from real robot descriptions (a hobby cobot's CAD export: a wrist link in millimetres
whose every node binds an undefined material read as "no triangles").
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from xrdf_tools.cli import app
from xrdf_tools.robot import link_geometry as lg
from xrdf_tools.robot.mesh_files import load_mesh_scene, without_broken_material_bindings
from xrdf_tools.robot.xacro_source import load_robot

# a cube of side 2 * HALF in the file's units, its 12 triangles
_CORNERS = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], float)
_FACES = [
    (0, 1, 3), (0, 3, 2), (4, 6, 7), (4, 7, 5), (0, 4, 5), (0, 5, 1),
    (2, 3, 7), (2, 7, 6), (0, 2, 6), (0, 6, 4), (1, 5, 7), (1, 7, 3),
]  # fmt: skip


def _cube_dae(half: float, unit_meter: float, material_target: str) -> str:
    positions = " ".join(f"{v:g}" for v in (_CORNERS * half).ravel())
    indices = " ".join(str(i) for face in _FACES for i in face)
    return f"""<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit meter="{unit_meter:g}" name="u"/><up_axis>Z_UP</up_axis></asset>
  <library_effects><effect id="fx"><profile_COMMON><technique sid="c"><lambert/></technique>
  </profile_COMMON></effect></library_effects>
  <library_materials><material id="grey"><instance_effect url="#fx"/></material>
  </library_materials>
  <library_geometries><geometry id="cube"><mesh>
    <source id="p"><float_array id="pa" count="24">{positions}</float_array>
      <technique_common><accessor source="#pa" count="8" stride="3">
        <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
      </accessor></technique_common></source>
    <vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
    <triangles count="12" material="m"><input semantic="VERTEX" source="#v" offset="0"/>
      <p>{indices}</p></triangles>
  </mesh></geometry></library_geometries>
  <library_visual_scenes><visual_scene id="s"><node id="n">
    <instance_geometry url="#cube"><bind_material><technique_common>
      <instance_material symbol="m" target="#{material_target}"/>
    </technique_common></bind_material></instance_geometry>
  </node></visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#s"/></scene>
</COLLADA>
"""


def _robot_with_mesh(tmp_path: Path, dae: str) -> Path:
    (tmp_path / "part.dae").write_text(dae)
    urdf = tmp_path / "r.urdf"
    urdf.write_text(
        '<robot name="r"><link name="a"><collision><geometry><mesh filename="part.dae"/>'
        "</geometry></collision></link></robot>"
    )
    return urdf


def _extent(tmp_path: Path, dae: str) -> float:
    robot = load_robot(_robot_with_mesh(tmp_path, dae))
    part = lg.link_geometry(robot, "collision")["a"]
    assert not part.failures, [f.reason for f in part.failures]
    (only,) = part.parts
    return float(np.ptp(only.mesh.vertices, axis=0).max())


@pytest.mark.parametrize(("half", "unit"), [(50.0, 0.001), (0.05, 1.0), (5.0, 0.01)])
def test_a_collada_unit_is_applied(tmp_path: Path, half: float, unit: float) -> None:
    """A 100 mm cube written in millimetres, metres or centimetres is 0.1 m in every case."""
    assert _extent(tmp_path, _cube_dae(half, unit, "grey")) == pytest.approx(0.1)


def test_a_binding_to_an_undefined_material_keeps_the_geometry(tmp_path: Path) -> None:
    dae = _cube_dae(50.0, 0.001, "not-in-the-file")
    assert _extent(tmp_path, dae) == pytest.approx(0.1)
    repaired = without_broken_material_bindings(dae.encode())
    assert repaired is not None and b"not-in-the-file" not in repaired
    assert without_broken_material_bindings(_cube_dae(50.0, 0.001, "grey").encode()) is None
    assert without_broken_material_bindings(b"not xml") is None
    (tmp_path / "good.dae").write_text(_cube_dae(50.0, 0.001, "grey"))
    good = load_mesh_scene(tmp_path / "good.dae")
    assert good.units == "meters" and len(good.geometry) == 1


def test_spheres_of_a_millimetre_collada_part_are_in_metres(
    runner: CliRunner, tmp_path: Path
) -> None:
    urdf = _robot_with_mesh(tmp_path, _cube_dae(50.0, 0.001, "not-in-the-file"))
    out = tmp_path / "s.xrdf"
    r = runner.invoke(app, ["spheres", str(urdf), "--format", "json", "-o", str(out)])
    assert r.exit_code == 0, r.output
    import yaml

    spheres = yaml.safe_load(out.read_text())["geometry"]
    radii = [s["radius"] for g in spheres.values() for s in g["spheres"]["a"]]
    assert radii and max(radii) <= 0.1
