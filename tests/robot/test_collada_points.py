"""The COLLADA vertex reader gives the box trimesh gives (the sphere fitter's reading), or
gives up; hostile files are a give-up with a line, never a hang."""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
import pytest

from tests.robots import robots_dir
from xrdf_tools.robot.collada_points import ColladaNotRead, collada_vertices
from xrdf_tools.robot.mesh_files import load_mesh_scene

#: A unit cube's corners, and a ninth vertex far away that no triangle uses.
_POSITIONS = "0 0 0 1 0 0 1 1 0 0 1 0 0 0 1 1 0 1 1 1 1 0 1 1 50 50 50"
_TRIANGLES = "0 1 2 0 2 3 4 5 6 4 6 7 0 1 5 0 5 4 2 3 7 2 7 6"


def dae(
    scene: str,
    *,
    unit: str = '<unit name="meter" meter="1"/>',
    up: str = "Z_UP",
    library_nodes: str = "",
    primitive: str = "",
    positions: str = _POSITIONS,
    prolog: str = "",
) -> bytes:
    """A COLLADA document with one geometry ``g`` (a cube; ``primitive`` in place of its
    triangles), a material ``m`` and ``scene`` as the nodes of its visual scene."""
    primitive = primitive or (
        f'<triangles count="8" material="s"><input semantic="VERTEX" source="#g-v" '
        f'offset="0"/><p>{_TRIANGLES}</p></triangles>'
    )
    count = len(positions.split())
    return f"""<?xml version="1.0"?>{prolog}
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset>{unit}<up_axis>{up}</up_axis></asset>
  <library_effects><effect id="e"><profile_COMMON><technique sid="c"><phong>
    <diffuse><color>1 0 0 1</color></diffuse></phong></technique></profile_COMMON></effect>
  </library_effects>
  <library_materials><material id="m"><instance_effect url="#e"/></material>
  </library_materials>
  <library_geometries><geometry id="g"><mesh>
    <source id="g-p"><float_array id="g-a" count="{count}">{positions}</float_array>
      <technique_common><accessor source="#g-a" count="{count // 3}" stride="3">
        <param name="X" type="float"/><param name="Y" type="float"/>
        <param name="Z" type="float"/></accessor></technique_common></source>
    <vertices id="g-v"><input semantic="POSITION" source="#g-p"/></vertices>
    {primitive}
  </mesh></geometry></library_geometries>
  <library_nodes>{library_nodes}</library_nodes>
  <library_visual_scenes><visual_scene id="s">{scene}</visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#s"/></scene>
</COLLADA>""".encode()


GEOMETRY = (
    '<instance_geometry url="#g"><bind_material><technique_common>'
    '<instance_material symbol="s" target="#m"/></technique_common></bind_material>'
    "</instance_geometry>"
)


def trimesh_box(data: bytes, tmp_path: Path) -> np.ndarray:
    path = tmp_path / "m.dae"
    path.write_bytes(data)
    meshes = [m for m in load_mesh_scene(path).dump() if len(m.vertices)]
    every = np.concatenate([np.asarray(m.vertices) for m in meshes])
    return np.array([every.min(axis=0), every.max(axis=0)])


def our_box(data: bytes) -> np.ndarray:
    v = collada_vertices(data)
    return np.array([v.min(axis=0), v.max(axis=0)])


def assert_same_box(data: bytes, tmp_path: Path) -> np.ndarray:
    expected = trimesh_box(data, tmp_path)
    got = our_box(data)
    np.testing.assert_allclose(got, expected, rtol=0, atol=1e-6 * np.abs(expected).max())
    return got


@pytest.mark.parametrize(
    "scene",
    [
        f'<node id="a"><matrix>0 -1 0 0.5 1 0 0 0.2 0 0 1 -3 0 0 0 1</matrix>{GEOMETRY}</node>',
        f'<node id="a"><translate>1 2 3</translate><rotate>0 0 1 30</rotate>'
        f"<scale>2 0.5 1</scale>{GEOMETRY}</node>",
        f'<node id="a"><rotate>1 1 0 45</rotate><node id="b"><translate>0 0 1</translate>'
        f"<rotate>0 1 0 -90</rotate>{GEOMETRY}</node>{GEOMETRY}</node>",
        '<node id="a"><translate>5 0 0</translate><instance_node url="#lib"/></node>',
    ],
    ids=["matrix", "translate-rotate-scale", "nested-twice-instanced", "instance-node"],
)
def test_node_transforms_give_trimesh_s_box(scene: str, tmp_path: Path) -> None:
    lib = f'<node id="lib"><rotate>0 0 1 90</rotate>{GEOMETRY}</node>'
    assert_same_box(dae(scene, library_nodes=lib), tmp_path)


def test_a_vertex_no_triangle_uses_is_not_in_the_box(tmp_path: Path) -> None:
    got = assert_same_box(dae(f'<node id="a">{GEOMETRY}</node>'), tmp_path)
    np.testing.assert_allclose(got, [[0, 0, 0], [1, 1, 1]])


def test_the_unit_scales_to_metres_and_the_up_axis_is_not_applied(tmp_path: Path) -> None:
    scene = f'<node id="a"><translate>10 0 0</translate>{GEOMETRY}</node>'
    mm = assert_same_box(dae(scene, unit='<unit name="mm" meter="0.001"/>'), tmp_path)
    np.testing.assert_allclose(mm, [[0.01, 0, 0], [0.011, 0.001, 0.001]])
    y_up = assert_same_box(dae(scene, up="Y_UP"), tmp_path)
    np.testing.assert_allclose(y_up, [[10, 0, 0], [11, 1, 1]])


def test_polylists_and_polygons_give_trimesh_s_box(tmp_path: Path) -> None:
    quads = '<input semantic="VERTEX" source="#g-v" offset="0"/>'
    polylist = f'<polylist count="2">{quads}<vcount>4 4</vcount><p>0 1 2 3 4 5 6 7</p></polylist>'
    polygons = f'<polygons count="2">{quads}<p>0 1 2 3</p><p>4 5 6</p></polygons>'
    for primitive in (polylist, polygons):
        scene = f'<node id="a"><rotate>1 0 0 20</rotate>{GEOMETRY}</node>'
        assert_same_box(dae(scene, primitive=primitive), tmp_path)


@pytest.mark.parametrize(
    ("scene", "primitive", "why"),
    [
        (f'<node id="a"><lookat>0 0 1 0 0 0 0 1 0</lookat>{GEOMETRY}</node>', "", "<lookat>"),
        (f'<node id="a"><skew>45 0 1 0 1 0 0</skew>{GEOMETRY}</node>', "", "<skew>"),
        ('<node id="a"><instance_geometry url="#nothing"/></node>', "", "not followed"),
        (
            f'<node id="a">{GEOMETRY.replace("#m", "#nomaterial")}</node>',
            "",
            "'#nomaterial' not loaded",
        ),
        (
            f'<node id="a">{GEOMETRY}</node>',
            '<tristrips count="1"><input semantic="VERTEX" source="#g-v" offset="0"/>'
            "<p>0 1 2 3</p></tristrips>",
            "<tristrips>",
        ),
        ('<node id="a"><instance_node url="#loop"/></node>', "", "cycle"),
    ],
    ids=["lookat", "skew", "missing-geometry", "missing-material", "tristrips", "cycle"],
)
def test_what_it_does_not_handle_it_gives_up_on(scene: str, primitive: str, why: str) -> None:
    loop = '<node id="loop"><instance_node url="#loop"/></node>'
    with pytest.raises(ColladaNotRead, match=why):
        collada_vertices(dae(scene, primitive=primitive, library_nodes=loop))


def test_hostile_files_are_a_located_give_up_not_a_hang() -> None:
    scene = f'<node id="a">{GEOMETRY}</node>'
    bomb = (
        '<!DOCTYPE COLLADA [<!ENTITY a "1 1 1 1 1 1 1 1 1 1"><!ENTITY b "&a;&a;&a;&a;&a;&a;'
        '&a;&a;&a;&a;"><!ENTITY c "&b;&b;&b;&b;&b;&b;&b;&b;&b;&b;"><!ENTITY d "&c;&c;&c;&c;'
        '&c;&c;&c;&c;&c;&c;"><!ENTITY e "&d;&d;&d;&d;&d;&d;&d;&d;&d;&d;"><!ENTITY f "&e;&e;'
        '&e;&e;&e;&e;&e;&e;&e;&e;"><!ENTITY g "&f;&f;&f;&f;&f;&f;&f;&f;&f;&f;">]>'
    )
    start = time.perf_counter()
    with pytest.raises(ColladaNotRead, match="entity amplification") as bombed:
        collada_vertices(dae(scene, positions="&g;", prolog=bomb))
    assert bombed.value.line is not None
    # a small entity is not substituted either: the numbers are not read through it
    small = '<!DOCTYPE COLLADA [<!ENTITY a "0 0 0 1 0 0 1 1 0">]>'
    with pytest.raises(ColladaNotRead, match="child nodes") as entity:
        collada_vertices(dae(scene, positions=f"&a; {_POSITIONS}", prolog=small))
    assert entity.value.line is not None
    with pytest.raises(ColladaNotRead, match="does not parse") as bad:
        collada_vertices(dae(scene, positions=_POSITIONS.replace("50 50", "5O 50")))
    assert bad.value.line == 10 and str(bad.value).startswith("10: ")
    with pytest.raises(ColladaNotRead, match="not well-formed") as broken:
        collada_vertices(dae(scene)[:-20])
    assert broken.value.line is not None
    # a count attribute is never trusted for an allocation
    huge = dae(scene).replace(b'count="27"', b'count="999999999999"')
    np.testing.assert_allclose(our_box(huge), [[0, 0, 0], [1, 1, 1]])
    assert time.perf_counter() - start < 5.0


def _collada_robots() -> list[str]:
    root = robots_dir()
    if root is None:
        return []
    return sorted({p.relative_to(root).parts[0] for p in root.rglob("*.[dD][aA][eE]")})


@pytest.mark.slow
@pytest.mark.parametrize("robot", _collada_robots())
def test_every_example_robot_dae_gives_trimesh_s_box(robot: str, tmp_path: Path) -> None:
    root = robots_dir()
    assert root is not None
    for path in sorted((root / robot).rglob("*.[dD][aA][eE]")):
        meshes = [m for m in load_mesh_scene(path).dump() if len(m.vertices)]
        try:
            ours = collada_vertices(path.read_bytes())
        except ColladaNotRead:
            # only where trimesh reads nothing either (a material pycollada cannot load)
            assert not meshes, path
            continue
        expected = np.concatenate([np.asarray(m.vertices) for m in meshes])
        box = np.array([expected.min(axis=0), expected.max(axis=0)])
        got = np.array([ours.min(axis=0), ours.max(axis=0)])
        np.testing.assert_allclose(
            got, box, rtol=0, atol=1e-6 * np.abs(box).max(), err_msg=str(path)
        )
