"""A URDF whose root holds the robot by a floating or planar joint (a humanoid's 'world' to
'pelvis', a mobile base's 'odom' to 'base_footprint'): no reader moves that joint and cuRobo
cannot load a robot whose base is above it, so the XRDF's base is the link below it."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.convert.test_one_command import BOXES
from xrdf_tools.convert.core import ConvertOptions
from xrdf_tools.convert.pipeline import FitOptions, MaskOptions, convert_robot
from xrdf_tools.export.curobo import to_curobo
from xrdf_tools.xrdf.model import SetBaseFrame


def _held(tmp_path: Path, kind: str) -> Path:
    """BOXES hung from 'world' by a joint of ``kind`` (through a fixed 'mount')."""
    held = (
        '<link name="world"/><link name="mount"/>'
        '<joint name="mount_joint" type="fixed"><parent link="world"/><child link="mount"/>'
        "</joint>"
        f'<joint name="world_joint" type="{kind}"><parent link="mount"/><child link="base"/>'
        "</joint>"
    )
    p = tmp_path / f"{kind}.urdf"
    p.write_text(BOXES.replace("</robot>", held + "</robot>"))
    return p


@pytest.mark.parametrize("kind", ["floating", "planar"])
def test_the_base_is_the_link_the_joint_holds(tmp_path: Path, kind: str) -> None:
    urdf = _held(tmp_path, kind)
    result = convert_robot(
        urdf, ConvertOptions(), fit=FitOptions(per_link=2), mask=MaskOptions(samples=200)
    )
    x = result.xrdf
    assert x.modifiers == (SetBaseFrame("base"),)
    found = [d for d in result.diagnostics if d.rule == "convert-floating-base"]
    assert len(found) == 1
    assert f"'world_joint' is a {kind} joint" in found[0].message
    assert "base is 'base'" in found[0].message and "without world, mount" in found[0].message
    assert x.cspace.joint_names == ("j1", "j2")
    assert set(x.world_collision_spheres()) == {"base", "upper", "lower"}
    assert result.lint_errors == []
    # cuRobo's config builds the robot from the base below the joint
    text, _ = to_curobo(x, result.robot)
    assert "base_link: base\n" in text


def test_a_fixed_root_keeps_the_urdf_root(tmp_path: Path) -> None:
    urdf = _held(tmp_path, "fixed")
    result = convert_robot(urdf, ConvertOptions(), mask=MaskOptions(samples=100))
    assert result.xrdf.modifiers == ()
    assert not [d for d in result.diagnostics if d.rule == "convert-floating-base"]
