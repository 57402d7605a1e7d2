"""Patterns seen in public XRDF files (cuMotion test data and shipped robots, Isaac ROS).

The public files are not copied here: each test writes a few lines that reproduce the pattern.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from typer.testing import CliRunner

from xrdf_tools.cli import app
from xrdf_tools.lint import lint_text
from xrdf_tools.xrdf import versions
from xrdf_tools.xrdf.io import dump_xrdf, parse_xrdf

HEADER = "format: xrdf\nformat_version: 2.0\n\n"


def _chain_urdf(tmp_path: Path, n: int, *, mimic: str = "") -> Path:
    """A planar chain of ``n`` continuous joints ``j0..``, links ``l0..`` one metre long."""
    parts = ['<robot name="chain">', '<link name="base"/>']
    parent = "base"
    for i in range(n):
        x = 0.0 if i == 0 else 1.0
        parts += [
            f'<link name="l{i}"/>',
            f'<joint name="j{i}" type="continuous"><parent link="{parent}"/>'
            f'<child link="l{i}"/><origin xyz="{x} 0 0"/><axis xyz="0 0 1"/>'
            + (mimic if i == n - 1 else "")
            + "</joint>",
        ]
        parent = f"l{i}"
    parts.append("</robot>")
    p = tmp_path / "chain.urdf"
    p.write_text("\n".join(parts))
    return p


def _rod(link: str) -> str:
    return f"      {link}:\n" + "".join(
        f"        - center: [{x / 10:.1f}, 0.0, 0.0]\n          radius: 0.1\n" for x in range(11)
    )


def _errors(text: str, urdf: Path | None = None) -> list[str]:
    return [
        f"{d.rule}: {d.message}"
        for d in lint_text(text, "robot.xrdf", urdf=urdf)
        if d.severity.value == "error"
    ]


def test_auxiliary_default_folding_the_arm_is_a_warning_not_an_error(tmp_path: Path) -> None:
    # cuMotion's valid thirty_link_arm_with_aux_cspace: defaults of joints outside the c-space
    # fold the arm onto itself; cuMotion loads it, so this must not fail the file.
    urdf = _chain_urdf(tmp_path, 4)
    text = (
        HEADER
        + "default_joint_positions:\n  j0: 0.0\n  j2: 0.0\n  j3: 3.0\n\n"
        + "cspace:\n  joint_names: [j0, j2]\n  acceleration_limits: [10.0, 10.0]\n"
        + "  jerk_limits: [100.0, 100.0]\n\n"
        + "self_collision:\n  geometry: rods\n  ignore:\n"
        + "    l0: [l1]\n    l1: [l2]\n    l2: [l3]\n\n"
        + "geometry:\n  rods:\n    spheres:\n"
        + "".join(_rod(f"l{i}") for i in range(4))
    )
    found = lint_text(text, "robot.xrdf", urdf=urdf)
    assert _errors(text, urdf) == []
    hits = [d for d in found if d.rule == "default-self-collision"]
    assert hits and {d.severity.value for d in hits} == {"warning"}
    assert any("'l1' and 'l3'" in d.message for d in hits)


def test_unknown_sphere_frame_message_names_group_and_frame(tmp_path: Path) -> None:
    # Isaac ROS ur10e.xrdf puts spheres on 'tcp', a frame some UR URDFs do not have.
    urdf = _chain_urdf(tmp_path, 2)
    text = (
        HEADER
        + "cspace:\n  joint_names: [j0, j1]\n  acceleration_limits: [10.0, 10.0]\n"
        + "  jerk_limits: [100.0, 100.0]\n\n"
        + "geometry:\n  arm_spheres:\n    spheres:\n"
        + "      l1:\n        - center: [0.0, 0.0, 0.0]\n          radius: 0.1\n"
        + "      l11:\n        - center: [0.0, 0.0, 0.0]\n          radius: 0.1\n"
    )
    assert _errors(text, urdf) == [
        "unknown-frame: group 'arm_spheres': sphere frame 'l11' is not a frame of chain.urdf; "
        "did you mean 'l1'?"
    ]


PLACEHOLDER_1_0 = """\
format: xrdf
format_version: 1.0

modifiers:
  - add_frame:
      frame_name: "attached_object"
      parent_frame_name: "l1"
      joint_name: "attach_joint"
      joint_type: FIXED
      fixed_transform:
        position: [0.0, 0.0, 0.0]
        orientation: {w: 1.0, xyz: [0.0, 0.0, 0.0]}

cspace:
  joint_names:
    - "j0"
    - "j1"
  acceleration_limits: [12.0, 12.0]
  jerk_limits: [500.0, 500.0]

tool_frames: ["attached_object"]

collision:
  geometry: "arm"
  buffer_distance:
    l1: 0.01
    attached_object: 0.004

self_collision:
  geometry: "arm"
  ignore:
    l0: ["l1"]

geometry:
  arm:
    spheres:
      l0:
        - center: [0, 0, 0]
          radius: 0.05
      l1:
        - center: [0.5, 0, 0]
          radius: 0.05
      attached_object:
        - center: [0.0, 0.0, 0.0]
          radius: -10.0
        - center: [0.0, 0.0, 0.0]
          radius: -0.01
"""


def test_isaac_ros_1_0_placeholders_lint_clean_round_trip_and_convert(tmp_path: Path) -> None:
    urdf = _chain_urdf(tmp_path, 2)
    assert _errors(PLACEHOLDER_1_0) == []
    assert _errors(PLACEHOLDER_1_0, urdf) == []
    x = parse_xrdf(PLACEHOLDER_1_0, "robot.xrdf")
    out = dump_xrdf(x)
    again = parse_xrdf(out, "dumped.xrdf")
    assert again == x and dump_xrdf(again) == out
    y, notes = versions.to_version(x, "2.0")
    assert notes, "dropping the placeholder spheres must be reported"
    converted = dump_xrdf(y)
    assert _errors(converted) == [] and _errors(converted, urdf) == []


@pytest.mark.parametrize(
    ("mimic", "message"),
    [
        ('<mimic joint="j1"/>', "mimic joints form a loop: j1 -> j1"),
        ('<mimic joint="j8"/>', "joint 'j1' mimics 'j8', which is not a joint"),
    ],
)
def test_invalid_mimic_in_urdf_is_a_finding(
    runner: CliRunner, tmp_path: Path, mimic: str, message: str
) -> None:
    # cuMotion's telescope_invalid_self_mimic / _mimic_parent URDFs with the valid telescope.xrdf:
    # no reader loads the XRDF with that URDF, so it is a finding of the XRDF under test
    # (urdf-invalid, exit 1) naming the URDF's problem; URDF-bound checks are skipped.
    urdf = _chain_urdf(tmp_path, 2, mimic=mimic)
    text = HEADER + "cspace:\n  joint_names: [j0]\n  acceleration_limits: [1.0]\n"
    text += "  jerk_limits: [10.0]\n"
    found = [d for d in lint_text(text, "robot.xrdf", urdf=urdf) if d.severity.value == "error"]
    assert [d.rule for d in found] == ["urdf-invalid"]
    assert message in found[0].message and str(urdf) in found[0].message
    xrdf = tmp_path / "robot.xrdf"
    xrdf.write_text(text)
    r = runner.invoke(app, ["lint", str(xrdf), "--urdf", str(urdf)])
    assert r.exit_code == 1 and "urdf-invalid" in r.output and "Traceback" not in r.output


def test_lint_urdf_with_inverted_limits_is_an_error_only_in_the_cspace(
    runner: CliRunner, tmp_path: Path
) -> None:
    """A joint whose lower limit is above its upper (a vendor's Pioneer LX ptu_pan) is read
    with a located warning: no c-space uses it, so nothing needs a position between them. A
    c-space that holds it is an error at the c-space entry."""
    from tests.paths import FIXTURES

    urdf = tmp_path / "inverted.urdf"
    text = (FIXTURES / "urdf" / "three_link_mimic.urdf").read_text()
    urdf.write_text(text.replace('lower="-2.0" upper="2.0"', 'lower="2.0" upper="-2.0"'))
    xrdf = FIXTURES / "lint" / "urdf-invalid" / "pass.xrdf"  # c-space: joint2, joint3
    r = runner.invoke(app, ["lint", str(xrdf), "--urdf", str(urdf)])
    assert r.exit_code == 0, r.output
    assert f"{urdf}:50: warning urdf-limit-reversed joint 'joint1' <limit> lower=2.0" in r.output
    held = tmp_path / "held.xrdf"
    held.write_text(xrdf.read_text().replace("[joint2, joint3]", "[joint1, joint3]"))
    r = runner.invoke(app, ["lint", str(held), "--urdf", str(urdf)])
    assert r.exit_code == 1 and "Traceback" not in r.output
    assert (
        f"{held}:6:17: error cspace-joint c-space joint 'joint1' has its lower limit 2 above "
        "its upper limit -2 in the URDF: no position fits"
    ) in r.output, r.output
    for args in (["report", "-n", "10"], ["viz", "--png", str(tmp_path / "v.png")]):
        r = runner.invoke(app, [args[0], str(held), "--urdf", str(urdf), *args[1:]])
        assert r.exit_code == 2, r.output
        assert f"error: {held}:6:17: inverted.urdf does not match" in r.output
    r = runner.invoke(app, ["lint", str(xrdf), "--urdf", str(tmp_path / "missing.urdf")])
    assert r.exit_code == 2 and "not found" in r.output
