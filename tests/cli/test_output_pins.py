"""Byte-identical outputs of convert, lint and report on the bundled robots, pinned.

Restructuring the code must not change what users get. Each case runs a command on bundled
inputs and compares its output with a file under ``tests/data/pins/`` (absolute paths
normalised; no output holds a wall time). After an intended change, regenerate with
``XRDF_PINS_UPDATE=1 python -m pytest tests/cli/test_output_pins.py`` and review the diff.
"""

from __future__ import annotations

import os

import pytest
from typer.testing import CliRunner

from tests.paths import FIXTURES, REPO, TEST_DATA

PINS = TEST_DATA / "pins"
DEMO = FIXTURES / "demo_arm"
CLASSIC = FIXTURES / "curobo_classic"

#: name -> command line (paths relative to the repository, run from there)
CASES: dict[str, list[str]] = {
    "convert-ur10e-classic": [
        "convert",
        "fixtures/ur10e/ur10e.urdf",
        "--curobo",
        "fixtures/curobo_classic/ur10e_classic.yml",
    ],
    "convert-ur10e-inline-2.0": [
        "convert",
        "fixtures/ur10e/ur10e.urdf",
        "--curobo",
        "fixtures/curobo_classic/ur10e_inline.yml",
        "--format-version",
        "2.0",
    ],
    "convert-ur10e-lula": [
        "convert",
        "fixtures/ur10e/ur10e.urdf",
        "--curobo",
        "fixtures/curobo_classic/ur10e_lula.yaml",
    ],
    "convert-demo-arm-srdf": [
        "convert",
        "fixtures/demo_arm/demo_arm.urdf",
        "--srdf",
        "fixtures/demo_arm/demo_arm.srdf",
        "--joint-limits",
        "fixtures/demo_arm/joint_limits.yaml",
        "--target",
        "isaac-sim",
    ],
    "lint-seed-curobo": [
        "lint",
        "fixtures/seed/ur10e_seed.xrdf",
        "--urdf",
        "fixtures/ur10e/ur10e.urdf",
        "--target",
        "curobo",
    ],
    "lint-panda-json": ["lint", "fixtures/panda/panda.xrdf", "--format", "json"],
    "lint-ur10e-sarif": ["lint", "fixtures/ur10e/ur10e.xrdf", "--format", "sarif"],
    "report-seed-text": [
        "report",
        "fixtures/seed/ur10e_seed.xrdf",
        "--urdf",
        "fixtures/ur10e/ur10e.urdf",
        "-n",
        "3000",
        "--jobs",
        "1",
    ],
    "report-seed-json": [
        "report",
        "fixtures/seed/ur10e_seed.xrdf",
        "--urdf",
        "fixtures/ur10e/ur10e.urdf",
        "-n",
        "3000",
        "--jobs",
        "1",
        "--format",
        "json",
    ],
    "export-curobo-seed": [
        "export",
        "curobo",
        "fixtures/seed/ur10e_seed.xrdf",
        "--urdf",
        "fixtures/ur10e/ur10e.urdf",
        "--layout",
        "classic",
    ],
}


def _normalise(text: str) -> str:
    """Paths relative to the repository; nothing else is masked (no output holds a time)."""
    return text.replace(str(REPO) + os.sep, "").replace(str(REPO), ".")


@pytest.mark.parametrize("name", sorted(CASES))
def test_output_is_pinned(runner: CliRunner, name: str, monkeypatch: pytest.MonkeyPatch) -> None:
    from xrdf_tools.cli import app

    monkeypatch.chdir(REPO)
    result = runner.invoke(app, CASES[name])
    got = _normalise(f"exit {result.exit_code}\n{result.output}")
    pin = PINS / f"{name}.txt"
    if os.environ.get("XRDF_PINS_UPDATE"):
        pin.parent.mkdir(parents=True, exist_ok=True)
        pin.write_text(got)
    assert pin.exists(), f"no pin for {name}: run with XRDF_PINS_UPDATE=1"
    assert got == pin.read_text()


def test_every_pin_belongs_to_a_case() -> None:
    assert {p.stem for p in PINS.glob("*.txt")} == set(CASES)
