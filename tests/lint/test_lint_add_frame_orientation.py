"""``add-frame``: an orientation quaternion of zeros is no rotation (a reader normalising it
divides by 0); the identity, a non-unit quaternion and Euler angles are not findings here."""

from __future__ import annotations

import pytest

from tests.paths import FIXTURES, UR10E_URDF
from xrdf_tools.lint import lint_text

PASS = (FIXTURES / "lint" / "add-frame" / "pass.xrdf").read_text()
IDENTITY = "orientation: {w: 1.0, xyz: [0.0, 0.0, 0.0]}"


def _findings(orientation: str) -> list[tuple[int | None, str]]:
    assert IDENTITY in PASS
    text = PASS.replace(IDENTITY, orientation)
    return [(d.line, d.message) for d in lint_text(text, "f.xrdf") if d.rule == "add-frame"]


@pytest.mark.parametrize(
    "orientation",
    [
        "orientation: {w: 0.0, xyz: [0.0, 0.0, 0.0]}",
        "orientation: {w: 0, xyz: [0, -0.0, 0]}",
        "orientation: {quaternion: [0.0, 0.0, 0.0, 0.0]}",
    ],
)
def test_a_quaternion_of_zeros_is_an_error_at_its_line(orientation: str) -> None:
    ((line, message),) = _findings(orientation)
    assert line == 12 and "quaternion of zeros" in message


@pytest.mark.parametrize(
    "orientation",
    [
        IDENTITY,
        "orientation: {w: 5.0, xyz: [0.0, 0.0, 0.0]}",
        "orientation: {quaternion: [0.0, 0.0, 0.0, 1.0]}",
        "orientation: {euler_rpy: [0.0, 0.0, 0.0]}",
    ],
)
def test_other_orientations_are_no_finding_of_this_rule(orientation: str) -> None:
    assert _findings(orientation) == []


def test_a_moving_added_frame_is_said_once_also_with_the_urdf() -> None:
    """cuRobo's own XRDF writer turns its G1 config's floating base into add_frames of joint
    type X_PRISM … Z_ROT: ``add-frame`` says so at each; building the robot from the URDF
    fails on the first of them, which ``urdf-modifiers`` must not say a second time."""
    fail = FIXTURES / "lint" / "add-frame" / "fail.xrdf"
    text = fail.read_text()
    diags = lint_text(text, str(fail), urdf=UR10E_URDF)
    at_joint_type = [d.rule for d in diags if "joint_type must be FIXED" in d.message]
    assert at_joint_type == ["add-frame"], diags
    # a modifier the URDF refuses for another reason is still urdf-modifiers' finding
    broken = text.replace("joint_type: revolute", "joint_type: FIXED").replace(
        "parent_frame_name: tool0", "parent_frame_name: tool9"
    )
    (d,) = [d for d in lint_text(broken, str(fail), urdf=UR10E_URDF) if d.rule == "urdf-modifiers"]
    assert "tool9" in d.message and "did you mean 'tool0'" in d.message
