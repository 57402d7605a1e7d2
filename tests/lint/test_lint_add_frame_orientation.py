"""``add-frame``: an orientation quaternion of zeros is no rotation (a reader normalising it
divides by 0); the identity, a non-unit quaternion and Euler angles are not findings here."""

from __future__ import annotations

import pytest

from tests.paths import FIXTURES
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
