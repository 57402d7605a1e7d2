"""Collision geometry that is not where the visual geometry is: warned when spheres are fitted
(Flexiv's Rizon 10 ships every collision STL turned -90° about x)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pytest
import trimesh
from typer.testing import CliRunner

from tests.robots import robots_dir
from xrdf_tools.cli import app
from xrdf_tools.diagnostics import Diagnostic
from xrdf_tools.robot.element_bounds import Box, elements_bounds
from xrdf_tools.robot.xacro_source import load_robot
from xrdf_tools.spheres.count_policy import CountPolicy
from xrdf_tools.spheres.geometry import load_link_geometry
from xrdf_tools.spheres.robot_fit import fit_robot
from xrdf_tools.spheres.visual_agreement import (
    RULE_MISMATCH,
    RULE_UNCHECKED,
    visual_disagreements,
)

#: An upper arm 100 x 80 x 300 mm standing on its joint at the link origin.
ARM = trimesh.creation.box(
    (0.1, 0.08, 0.3), trimesh.transformations.translation_matrix((0, 0, 0.15))
)
#: The same mesh turned +90° about x, as a CAD export in another frame would hold it.
TURNED = ARM.copy().apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, (1, 0, 0)))


def _urdf(tmp_path: Path, visual: str, collision: str, collision_xyz: str = "0 0 0") -> Path:
    text = f"""<robot name="r">
  <link name="arm">
    <visual>
      <geometry><mesh filename="{visual}"/></geometry>
    </visual>
    <collision>
      <origin xyz="{collision_xyz}" rpy="0 0 0"/>
      <geometry><mesh filename="{collision}"/></geometry>
    </collision>
  </link>
</robot>
"""
    (tmp_path / "r.urdf").write_text(text)
    return tmp_path / "r.urdf"


def _said(urdf: Path, **options: Any) -> list[Diagnostic]:
    """The diagnostics of a quick fit (one sphere a link) of ``urdf``."""
    return fit_robot(urdf, counts=CountPolicy(per_link=1), **options).diagnostics


def test_a_collision_mesh_turned_a_quarter_is_warned_at_its_collision_element(
    tmp_path: Path,
) -> None:
    ARM.export(tmp_path / "arm_visual.stl")
    TURNED.export(tmp_path / "arm_collision.stl")
    urdf = _urdf(tmp_path, "arm_visual.stl", "arm_collision.stl")
    result = CliRunner().invoke(
        app, ["spheres", str(urdf), "--per-link", "1", "-o", str(tmp_path / "r.xrdf")]
    )
    assert result.exit_code == 0, result.output
    said = [line for line in result.stderr.splitlines() if RULE_MISMATCH in line]
    assert len(said) == 1
    # the line of <collision>, the link, both boxes and the turn that matches them
    assert said[0].startswith(f"{urdf}:6: warning {RULE_MISMATCH} link 'arm'")
    assert "collision box x -0.05…0.05 y -0.3…0 z -0.04…0.04" in said[0]
    assert "visual box x -0.05…0.05 y -0.04…0.04 z 0…0.3" in said[0]
    assert "turned -90° about x" in said[0]
    assert '<origin xyz="0 0 0" rpy="-1.5708 0 0"/>' in said[0]


def test_the_turn_the_warning_names_makes_them_agree(tmp_path: Path) -> None:
    ARM.export(tmp_path / "arm_visual.stl")
    TURNED.export(tmp_path / "arm_collision.stl")
    urdf = _urdf(tmp_path, "arm_visual.stl", "arm_collision.stl")
    text = urdf.read_text().replace('rpy="0 0 0"', 'rpy="-1.5708 0 0"')
    urdf.write_text(text)
    assert not [d for d in _said(urdf) if d.rule == RULE_MISMATCH]


def test_agreeing_geometry_is_not_warned(tmp_path: Path) -> None:
    # the visual an OBJ, the collision its convex hull, a little larger, as ASCII STL
    (tmp_path / "arm.obj").write_text(trimesh.exchange.obj.export_obj(ARM))
    hull = ARM.copy().apply_scale(1.05)
    (tmp_path / "arm.stl").write_bytes(trimesh.exchange.stl.export_stl_ascii(hull).encode())
    urdf = _urdf(tmp_path, "arm.obj", "arm.stl")
    said = _said(urdf)
    assert not [d for d in said if d.rule in (RULE_MISMATCH, RULE_UNCHECKED)]


def test_a_collision_placed_far_from_the_visual_is_warned(tmp_path: Path) -> None:
    # Alex's nub: the rpy written in the xyz of its collision <origin>
    ARM.export(tmp_path / "arm.stl")
    urdf = _urdf(tmp_path, "arm.stl", "arm.stl", collision_xyz="0 1.57 0")
    said = [d for d in _said(urdf) if d.rule == RULE_MISMATCH]
    assert len(said) == 1
    assert "1.49 m apart, farther than either is across" in said[0].message
    assert "turned" not in said[0].message


def test_millimetre_placeholders_centimetres_apart_are_not_warned(tmp_path: Path) -> None:
    """The youBot's ``base_footprint``: a 2 mm visual box and a 2 mm collision box 49 mm
    apart, farther than either is across but no misplaced part; 20 cm apart they are one."""
    box = '<geometry><box size="0.002 0.002 0.002"/></geometry>'
    for xyz, warned in (("0 0 0.049", False), ("0 0 0.2", True)):
        text = (
            f'<robot name="r"><link name="foot"><visual>{box}</visual><collision>'
            f'<origin xyz="{xyz}"/>{box}</collision></link></robot>\n'
        )
        (tmp_path / "r.urdf").write_text(text)
        said = [d for d in _said(tmp_path / "r.urdf") if d.rule == RULE_MISMATCH]
        assert len(said) == int(warned), (xyz, said)


def test_a_collision_shifted_against_its_visual_is_warned_with_the_origin_that_fixes_it(
    tmp_path: Path,
) -> None:
    """Dobot's M1 Pro: Link4's visual and collision are one STL, but only the visual has
    <origin xyz="0 0 0.08081">; its spline shaft's spheres hung 8 cm below the arm, the boxes
    touching, and no quarter turn matching them: nothing was said."""
    ARM.export(tmp_path / "arm.stl")
    urdf = _urdf(tmp_path, "arm.stl", "arm.stl")
    text = urdf.read_text().replace(
        "<visual>", '<visual>\n      <origin xyz="0 0 0.3" rpy="0 0 0"/>', 1
    )
    urdf.write_text(text)
    (said,) = [d for d in _said(urdf) if d.rule == RULE_MISMATCH]
    assert "shifted by (0, 0, 0.3) m the collision box matches the visual one" in said.message
    assert '<origin xyz="0 0 0.3" rpy="0 0 0"/> in its <collision> moves it' in said.message
    # a shift within the boxes' own overlap is no disagreement
    urdf.write_text(text.replace('xyz="0 0 0.3"', 'xyz="0 0 0.05"', 1))
    assert not [d for d in _said(urdf) if d.rule == RULE_MISMATCH]
    # a collision box of another size is not said to be shifted
    trimesh.creation.box((0.04, 0.04, 0.1)).export(tmp_path / "small.stl")
    head, _, tail = text.rpartition('filename="arm.stl"')  # the collision's, written last
    urdf.write_text(f'{head}filename="small.stl"{tail}')
    assert not [d for d in _said(urdf) if "shifted" in d.message]


def test_geometry_fitted_from_the_visual_is_not_compared_with_itself(tmp_path: Path) -> None:
    ARM.export(tmp_path / "arm_visual.stl")
    TURNED.export(tmp_path / "arm_collision.stl")
    urdf = _urdf(tmp_path, "arm_visual.stl", "arm_collision.stl")
    assert not [d for d in _said(urdf, source="visual") if d.rule == RULE_MISMATCH]
    assert not [d for d in _said(urdf, visual_check="off") if d.rule == RULE_MISMATCH]


def test_a_collada_visual_is_read_by_the_fast_check(tmp_path: Path) -> None:
    (tmp_path / "arm.dae").write_bytes(trimesh.exchange.dae.export_collada(ARM))
    TURNED.export(tmp_path / "arm_collision.stl")
    urdf = _urdf(tmp_path, "arm.dae", "arm_collision.stl")
    for check in ("fast", "all"):
        said = _said(urdf, visual_check=check)
        assert [d for d in said if d.rule == RULE_MISMATCH]
        assert not [d for d in said if d.rule == RULE_UNCHECKED]


def test_a_glb_visual_is_read_by_the_fast_check(tmp_path: Path) -> None:
    """dex-urdf's robots (xArm 7 with an Ability hand, Schunk's SVH, a UR5e with a Shadow hand)
    draw every link with GLB files: the fast check counted them all as not read."""
    (tmp_path / "arm.glb").write_bytes(ARM.export(file_type="glb"))
    TURNED.export(tmp_path / "arm_collision.stl")
    urdf = _urdf(tmp_path, "arm.glb", "arm_collision.stl")
    for check in ("fast", "all"):
        said = _said(urdf, visual_check=check)
        assert [d for d in said if d.rule == RULE_MISMATCH], said
        assert not [d for d in said if d.rule == RULE_UNCHECKED], said
    ARM.export(tmp_path / "arm_collision.stl")  # where the visual is: nothing to say
    assert not [d for d in _said(urdf) if d.rule in (RULE_MISMATCH, RULE_UNCHECKED)]


def test_a_collada_visual_the_reader_gives_up_on_is_counted_unless_all_formats_are_read(
    tmp_path: Path,
) -> None:
    text = trimesh.exchange.dae.export_collada(ARM).decode()
    # a <lookat> node transform: the COLLADA reader gives up on it, trimesh reads it
    text = text.replace('name="node0">', 'name="node0"><lookat>0 0 1 0 0 0 0 1 0</lookat>', 1)
    assert "<lookat>" in text
    (tmp_path / "arm.dae").write_text(text)
    TURNED.export(tmp_path / "arm_collision.stl")
    urdf = _urdf(tmp_path, "arm.dae", "arm_collision.stl")
    fast = _said(urdf)
    assert not [d for d in fast if d.rule == RULE_MISMATCH]
    (note,) = [d for d in fast if d.rule == RULE_UNCHECKED]
    assert note.severity.value == "info"
    assert "1 with .dae visual meshes (arm; --visual-check all reads them" in note.message
    full = _said(urdf, visual_check="all")
    assert not [d for d in full if d.rule == RULE_UNCHECKED]


def test_stl_and_obj_vertices_read_with_numpy_give_trimesh_s_box(tmp_path: Path) -> None:
    turned = TURNED.copy().apply_translation((0.01, 0.02, 0.03))
    (tmp_path / "a.stl").write_bytes(trimesh.exchange.stl.export_stl(turned))
    (tmp_path / "b.stl").write_bytes(trimesh.exchange.stl.export_stl_ascii(turned).encode())
    (tmp_path / "c.obj").write_text(trimesh.exchange.obj.export_obj(turned))
    urdf = tmp_path / "r.urdf"
    parts = "".join(
        f'<link name="{n}"><visual><origin xyz="0 0 1" rpy="0 0 1.5708"/><geometry>'
        f'<mesh filename="{f}" scale="2 1 1"/></geometry></visual></link>'
        for n, f in (("a", "a.stl"), ("b", "b.stl"), ("c", "c.obj"))
    )
    urdf.write_text(f'<robot name="r">{parts}</robot>')
    robot = load_robot(urdf)
    expected = turned.copy().apply_scale((2, 1, 1))
    expected.apply_transform(trimesh.transformations.rotation_matrix(1.5708, (0, 0, 1)))
    expected.apply_translation((0, 0, 1))
    for link in "abc":
        box = elements_bounds(robot, link, "visual", robot.mesh_resolver())
        assert isinstance(box, Box)
        np.testing.assert_allclose([box.low, box.high], expected.bounds, atol=1e-6)


def test_a_turned_cylinder_s_box_is_its_rims(tmp_path: Path) -> None:
    urdf = tmp_path / "r.urdf"
    urdf.write_text(
        '<robot name="r"><link name="l"><visual><origin rpy="1.5708 0 0"/><geometry>'
        '<cylinder radius="0.05" length="0.4"/></geometry></visual></link></robot>'
    )
    robot = load_robot(urdf)
    box = elements_bounds(robot, "l", "visual", robot.mesh_resolver())
    assert isinstance(box, Box)
    np.testing.assert_allclose(box.low, (-0.05, -0.2, -0.05), atol=1e-4)
    np.testing.assert_allclose(box.high, (0.05, 0.2, 0.05), atol=1e-4)


def _robots() -> Path:
    root = robots_dir()
    if root is None:
        pytest.skip("example-robot-data is not installed")
    return root


@pytest.mark.slow
@pytest.mark.parametrize(
    "urdf",
    ["tiago_description/robots/tiago.urdf", "talos_data/robots/talos_full_v2.urdf"],
)
def test_real_robots_whose_geometry_agrees_are_not_warned(urdf: str) -> None:
    robot = load_robot(_robots() / urdf)
    geoms, _ = load_link_geometry(robot, source="collision")
    said = visual_disagreements(robot, geoms, check="all")
    assert len(geoms) > 40
    assert said == []


@pytest.mark.slow
@pytest.mark.parametrize(
    "urdf",
    [
        "panda_description/urdf/panda.urdf",
        "ur_description/urdf/ur5_robot.urdf",
        "tiago_description/robots/tiago.urdf",
    ],
)
def test_real_robots_with_collada_visuals_are_checked_by_default(urdf: str) -> None:
    robot = load_robot(_robots() / urdf)
    geoms, _ = load_link_geometry(robot, source="collision")
    assert visual_disagreements(robot, geoms) == []


def test_alex_s_sake_fingers_collision_without_the_visual_turn_is_warned() -> None:
    # example-robot-data's Alex: the fingers' <collision> lacks the rpy="1.571 0 3.142"
    # of their <visual>, on the same OBJ file
    robot = load_robot(_robots() / "alex_description/urdf/alex_sake_hands.urdf")
    links = ["LeftSakeFingerTip1", "LeftSakeBaseFingerLink1"]
    geoms, _ = load_link_geometry(robot, links=links, source="collision")
    said = visual_disagreements(robot, geoms)
    assert [d.message.split("'")[1] for d in said] == links
    assert all("turned +90° about x" in d.message for d in said)


def test_the_editor_s_refit_shows_the_warning(tmp_path: Path) -> None:
    from xrdf_tools.edit.fit import propose_fit

    ARM.export(tmp_path / "arm_visual.stl")
    TURNED.export(tmp_path / "arm_collision.stl")
    robot = load_robot(_urdf(tmp_path, "arm_visual.stl", "arm_collision.stl"))
    proposal = propose_fit(robot, "arm", (), count=1)
    (warning,) = proposal.warnings
    assert warning.startswith("link 'arm': collision geometry not where its visual geometry is")
    assert "turned -90° about x" in warning
