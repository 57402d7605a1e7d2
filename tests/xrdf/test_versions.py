from __future__ import annotations

import pytest

from tests.paths import SEED_XRDF
from xrdf_tools.util.errors import ConversionError
from xrdf_tools.xrdf.io import dump_xrdf, load_xrdf, parse_xrdf
from xrdf_tools.xrdf.versions import to_1_0, to_2_0, to_version


def test_seed_to_2_0_drops_placeholder_and_renames_collision() -> None:
    x = load_xrdf(SEED_XRDF)
    y, diags = to_2_0(x)
    assert y.format_version == "2.0"
    text = dump_xrdf(y)
    assert "\nworld_collision:\n" in text and "\ncollision:" not in text
    assert y.geometry is not None
    assert "tool0" not in y.geometry["ur10e_collision_spheres"].spheres
    assert [d.rule for d in diags] == ["dropped-nonpositive-sphere"]
    assert diags[0].line == 103  # points at the radius in the seed file
    assert "tool0" in diags[0].message


def test_to_1_0_flattens_clones_and_round_trips() -> None:
    text = """format: xrdf
format_version: 2.0
cspace: {joint_names: [a], acceleration_limits: [1.0], jerk_limits: [2.0]}
world_collision: {geometry: all}
self_collision: {geometry: all}
geometry:
  all:
    clone: [arm]
    spheres:
      hand: [{center: [0, 0, 0], radius: 0.05}]
  arm:
    spheres:
      hand: [{center: [0, 0, 1], radius: 0.1}]
      link: [{center: [0, 0, 0], radius: 0.1}]
"""
    x = parse_xrdf(text)
    y, diags = to_1_0(x)
    assert y.format_version == "1.0"
    assert y.geometry is not None
    assert all(not g.clone for g in y.geometry.values())
    assert [s.radius for s in y.geometry["all"].spheres["hand"]] == [0.05, 0.1]
    assert "flattened-clone" in [d.rule for d in diags]
    z, _ = to_2_0(y)
    assert z.self_collision_spheres() == x.self_collision_spheres()


def test_to_1_0_warns_at_each_2_0_radius_that_is_not_positive() -> None:
    """2.0 forbids radius ≤ 0; written into 1.0 as it is, the sphere means something there
    (a slot, a buffered sphere), so each is warned at its radius; a clone's spheres once."""
    text = """format: xrdf
format_version: 2.0
world_collision: {geometry: all}
geometry:
  all:
    clone: [arm]
    spheres:
      hand: [{center: [0, 0, 0], radius: 0.05}, {center: [0, 0, 0], radius: -10}]
  arm:
    spheres:
      link: [{center: [0, 0, 0], radius: 0.0}]
"""
    _, diags = to_1_0(parse_xrdf(text, "robot.xrdf"))
    bad = [d for d in diags if d.rule == "invalid-radius-written"]
    assert [(d.line, d.col) for d in bad] == [(8, 77), (11, 42)]
    assert "sphere 1 on 'hand' has radius -10" in bad[0].message
    assert "attached-object slot" in bad[0].message
    assert "sphere 0 on 'link' has radius 0" in bad[1].message


def test_remove_mimic_cannot_go_to_1_0() -> None:
    x = parse_xrdf(
        "format: xrdf\nformat_version: 2.0\nmodifiers:\n  - remove_mimic_attributes:\n"
        "      joint_name: f2\n      position_limits: [0, 0.04]\n      velocity_limits: 0.2\n"
    )
    with pytest.raises(ConversionError, match="remove_mimic_attributes"):
        to_version(x, "1.0")


def test_different_groups_warned_on_1_0() -> None:
    x = parse_xrdf(
        "format: xrdf\nformat_version: 2.0\nworld_collision: {geometry: a}\n"
        "self_collision: {geometry: b}\ngeometry: {a: {spheres: {}}, b: {spheres: {}}}\n"
    )
    _, diags = to_1_0(x)
    assert "different-collision-groups" in [d.rule for d in diags]


def test_same_version_is_identity() -> None:
    x = load_xrdf(SEED_XRDF)
    assert to_version(x, "1.0") == (x, [])


def test_world_collision_only_says_what_curobo_needs_on_1_0() -> None:
    """cuMotion's two_link_arm.xrdf (2.0) has world_collision and no self_collision; written as
    1.0 for cuRobo, whose loader raises 'self_collision key not found' once collision is there,
    the missing section was not mentioned (missing tool_frames and defaults were)."""
    text = (
        "format: xrdf\nformat_version: 2.0\n"
        "default_joint_positions: {j: 0.0}\n"
        "cspace: {joint_names: [j], acceleration_limits: [1.0], jerk_limits: [1.0]}\n"
        "tool_frames: [tip]\n"
        "world_collision:\n  geometry: g\n"
        "geometry:\n  g:\n    spheres:\n      link: [{center: [0.0, 0.0, 0.0], radius: 0.1}]\n"
    )
    out, diags = to_1_0(parse_xrdf(text, "arm.xrdf"))
    assert out.self_collision is None and out.world_collision is not None
    assert [(d.rule, d.line, d.key_path) for d in diags] == [
        ("missing-for-curobo", 7, "world_collision")
    ]
    assert "self_collision" in diags[0].message
