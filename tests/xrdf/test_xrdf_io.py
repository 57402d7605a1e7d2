from __future__ import annotations

from pathlib import Path

import pytest

from tests.paths import SEED_XRDF, UR10E_XRDF, shared_file, shared_xrdf_params
from xrdf_tools.util.errors import GeometryGroupError, SchemaError
from xrdf_tools.util.frozen import FrozenMap
from xrdf_tools.xrdf.io import dump_xrdf, format_float, load_xrdf, parse_xrdf
from xrdf_tools.xrdf.model import (
    AddFrame,
    CollisionSection,
    CSpace,
    GeometryGroup,
    Orientation,
    RemoveMimicAttributes,
    SelfCollisionSection,
    SetBaseFrame,
    Sphere,
    Xrdf,
    clone_order,
    resolve_group,
)
from xrdf_tools.yaml.io import parse_yaml, to_python


def roundtrip_is_stable(path: Path) -> None:
    x = load_xrdf(path)
    text = dump_xrdf(x)
    y = parse_xrdf(text, "dumped")
    assert y == x, f"load(dump(m)) != m for {path}"
    assert dump_xrdf(y) == text, f"dump not idempotent for {path}"


def test_seed_example_roundtrip() -> None:
    roundtrip_is_stable(SEED_XRDF)


def test_fixture_roundtrip() -> None:
    roundtrip_is_stable(UR10E_XRDF)


def test_shared_reference_ur10e_roundtrip() -> None:
    roundtrip_is_stable(shared_file("reference", "curobo-2.0", "ur10e.xrdf"))


@pytest.mark.parametrize("path", shared_xrdf_params())
def test_every_shared_xrdf_roundtrips(path: Path) -> None:
    roundtrip_is_stable(path)


def _plain_equal_modulo_numbers(a: object, b: object) -> bool:
    if isinstance(a, dict) and isinstance(b, dict):
        return a.keys() == b.keys() and all(_plain_equal_modulo_numbers(a[k], b[k]) for k in a)
    if isinstance(a, list) and isinstance(b, list):
        return len(a) == len(b) and all(
            _plain_equal_modulo_numbers(x, y) for x, y in zip(a, b, strict=False)
        )
    if isinstance(a, (int, float)) and isinstance(b, (int, float)):
        return float(a) == float(b)
    return a == b


def test_seed_dump_loses_no_field() -> None:
    original = to_python(parse_yaml(SEED_XRDF.read_text()).root)
    dumped = to_python(parse_yaml(dump_xrdf(load_xrdf(SEED_XRDF))).root)
    assert _plain_equal_modulo_numbers(original, dumped)


def test_seed_model_content() -> None:
    x = load_xrdf(SEED_XRDF)
    assert x.format_version == "1.0"
    assert x.modifiers == (SetBaseFrame("base_link"),)
    assert x.cspace is not None and len(x.cspace.joint_names) == 6
    assert x.cspace.acceleration_limits == (12.0,) * 6
    assert x.tool_frames == ("tool0",)
    assert x.world_collision is not None
    assert x.world_collision.buffer_distance["camera_mount"] == 0.01
    assert x.self_collision is not None
    assert x.self_collision.is_ignored("tool0", "camera_mount")
    assert x.self_collision.is_ignored("camera_mount", "tool0")
    assert not x.self_collision.is_ignored("shoulder_link", "tool0")
    spheres = x.self_collision_spheres()
    assert len(spheres["upper_arm_link"]) == 7
    assert spheres["tool0"] == (Sphere((0.0, 0.0, 0.12), -0.01),)
    # positions are kept for diagnostics
    assert x.source.position("geometry.ur10e_collision_spheres.spheres.tool0[0].radius")[0] == 103


def test_dump_writes_floats_and_canonical_order() -> None:
    x = load_xrdf(SEED_XRDF)
    text = dump_xrdf(x)
    assert "center: [0.0, 0.0, 0.0]" in text
    assert "center: [0.0, 0.11, -0.01]" in text
    keys = [line.split(":")[0] for line in text.splitlines() if line and line[0].isalpha()]
    assert keys == [
        "format",
        "format_version",
        "modifiers",
        "default_joint_positions",
        "cspace",
        "tool_frames",
        "collision",
        "self_collision",
        "geometry",
    ]
    # read back by PyYAML (YAML 1.1, what cuRobo uses): every number is a float
    import yaml

    data = yaml.safe_load(text)
    assert all(isinstance(v, float) for v in data["cspace"]["jerk_limits"])
    sph = data["geometry"]["ur10e_collision_spheres"]["spheres"]["forearm_link"][6]
    assert isinstance(sph["center"][1], float) and sph["center"][1] == -1.19904e-17


@pytest.mark.parametrize(
    ("value", "text"),
    [
        (0, "0.0"),
        (-0.0, "0.0"),
        (1.5, "1.5"),
        (1e-5, "1.0e-05"),
        (1.19904e-17, "1.19904e-17"),
        (2e16, "2.0e+16"),
        (float("inf"), ".inf"),
    ],
)
def test_format_float(value: float, text: str) -> None:
    assert format_float(value) == text
    import yaml

    assert yaml.safe_load(f"v: {text}")["v"] == float(value)


def test_quoted_names_survive_yaml11_readers() -> None:
    x = Xrdf(
        format_version="2.0",
        cspace=CSpace(("on", "no", "joint 1"), (1.0, 1.0, 1.0), (2.0, 2.0, 2.0)),
    )
    text = dump_xrdf(x)
    import yaml

    assert yaml.safe_load(text)["cspace"]["joint_names"] == ["on", "no", "joint 1"]
    assert parse_xrdf(text) == x


def test_equal_models_dump_byte_identical() -> None:
    def build() -> Xrdf:
        return Xrdf(
            format_version="2.0",
            modifiers=(
                AddFrame(
                    "tcp",
                    "tool0",
                    "tcp_joint",
                    (0.0, 0.0, 0.1),
                    Orientation("euler_rpy", (0.0, 0.0, 1.57)),
                ),
                AddFrame(
                    "cam",
                    "tool0",
                    "cam_joint",
                    (0.1, 0.0, 0.0),
                    Orientation("quaternion", (1.0, 0.0, 0.0, 0.0)),
                    "fixed",
                ),
                RemoveMimicAttributes("finger2", (0.0, 0.04), 0.2),
            ),
            cspace=CSpace(("a",), (1.0,), (2.0,)),
            world_collision=CollisionSection("g", FrozenMap({"l": 0.01})),
            self_collision=SelfCollisionSection("h", FrozenMap(), FrozenMap({"l": ("m",)})),
            geometry=FrozenMap(
                {
                    "g": GeometryGroup(FrozenMap({"l": (Sphere((0.0, 0.0, 0.0), 0.1),)})),
                    "h": GeometryGroup(FrozenMap(), ("g",)),
                }
            ),
        )

    a, b = build(), build()
    assert a == b and dump_xrdf(a) == dump_xrdf(b)
    assert parse_xrdf(dump_xrdf(a)) == a


CLONES = """format: xrdf
format_version: 2.0
geometry:
  top:
    clone: [mid, base]
    spheres:
      f: [{center: [0, 0, 0], radius: 0.1}]
  mid:
    clone: [base]
    spheres:
      f: [{center: [1, 0, 0], radius: 0.2}]
  base:
    spheres:
      f: [{center: [2, 0, 0], radius: 0.3}]
      g: [{center: [3, 0, 0], radius: 0.4}]
"""


def test_clone_resolution_order_and_shared_ancestor() -> None:
    x = parse_xrdf(CLONES)
    assert x.geometry is not None
    assert clone_order(x.geometry, "top") == ["top", "mid", "base"]
    merged = resolve_group(x.geometry, "top")
    assert [s.radius for s in merged["f"]] == [0.1, 0.2, 0.3]  # base counted once
    assert [s.radius for s in merged["g"]] == [0.4]


def test_clone_cycle_and_missing_group() -> None:
    x = parse_xrdf(CLONES.replace("    clone: [base]\n", "    clone: [top]\n"))
    assert x.geometry is not None
    with pytest.raises(GeometryGroupError, match="top -> mid -> top"):
        resolve_group(x.geometry, "top")
    y = parse_xrdf(CLONES.replace("clone: [mid, base]", "clone: [mid, nope]"))
    assert y.geometry is not None
    with pytest.raises(GeometryGroupError, match="clones 'nope', which is not defined"):
        resolve_group(y.geometry, "top")
    z = parse_xrdf(CLONES.replace("clone: [base]", "clone: [mid]"))
    assert z.geometry is not None
    with pytest.raises(GeometryGroupError, match="mid -> mid"):
        resolve_group(z.geometry, "mid")


def test_clone_must_be_a_list() -> None:
    with pytest.raises(SchemaError, match="clone must be a list"):
        parse_xrdf(CLONES.replace("clone: [mid, base]", "clone: mid"))


def test_orientation_forms_agree() -> None:
    import math

    q1 = Orientation("euler_rpy", (0.0, 0.0, math.pi / 2)).as_wxyz()
    q2 = Orientation(
        "quaternion", (math.cos(math.pi / 4), 0.0, 0.0, math.sin(math.pi / 4))
    ).as_wxyz()
    assert all(abs(a - b) < 1e-12 for a, b in zip(q1, q2, strict=False))
    rpy = Orientation("euler_rpy", (0.3, -0.2, 0.1)).as_wxyz()
    assert abs(sum(v * v for v in rpy) - 1.0) < 1e-12


@pytest.mark.parametrize(
    ("snippet", "message"),
    [
        ("format: urdf\nformat_version: 2.0\n", "'format' must be 'xrdf'"),
        ("format: xrdf\n", "missing required key 'format_version'"),
        ("format: xrdf\nformat_version: 3.0\n", "unsupported format_version"),
        ("format: xrdf\nformat_version: 2.0\ncspace: [a]\n", "cspace must be a mapping"),
        (
            "format: xrdf\nformat_version: 2.0\ncollision: {geometry: g}\n"
            "world_collision: {geometry: g}\n",
            "both 'collision' and 'world_collision'",
        ),
        (
            "format: xrdf\nformat_version: 2.0\nmodifiers:\n  - rotate_frame: x\n",
            "unknown modifier 'rotate_frame'",
        ),
        (
            "format: xrdf\nformat_version: 2.0\ndefault_joint_positions:\n  a: true\n",
            "must be a number, not the boolean true",
        ),
    ],
)
def test_schema_errors(snippet: str, message: str) -> None:
    with pytest.raises(SchemaError, match=message):
        parse_xrdf(snippet)


def test_quoted_version_and_scalar_buffer_are_accepted() -> None:
    text = (
        'format: xrdf\nformat_version: "1.0"\ncollision:\n  geometry: g\n  buffer_distance: 0.02\n'
        "geometry:\n  g:\n    spheres:\n      a: [{center: [0, 0, 0], radius: 0.1}]\n"
        "      b: [{center: [0, 0, 0], radius: 0.1}]\n"
    )
    x = parse_xrdf(text)
    assert x.format_version == "1.0"
    assert x.world_collision is not None
    assert dict(x.world_collision.buffer_distance) == {"a": 0.02, "b": 0.02}
