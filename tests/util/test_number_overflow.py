"""Numbers past float range or the length bound in an XRDF: one-line input errors, never an
overflow; real robots are left alone."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from typer.testing import CliRunner

from tests.cli_checks import copy_replacing, run_cli
from tests.paths import UR10E_URDF, UR10E_XRDF


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        ("center: [0.0, 0.0, 0.0]", "center: [1e308, 1e308, 0.0]", "center[0] is 1e+308"),
        ("center: [0.0, 0.0, 0.0]", "center: [.inf, 0.0, 0.0]", "center[0] is inf; lengths"),
        ("radius: 0.05", "radius: 1e308", "radius is 1e+308"),
    ],
)
def test_huge_sphere_values_are_errors_not_overflows(
    runner: CliRunner, tmp_path: Path, old: str, new: str, message: str
) -> None:
    x = copy_replacing(UR10E_XRDF, tmp_path / "big.xrdf", old, new)
    for args in (
        ["viz", str(x), "--urdf", str(UR10E_URDF), "--png", str(tmp_path / "o.png")],
        ["report", str(x), "--urdf", str(UR10E_URDF), "-n", "10"],
    ):
        code, out = run_cli(runner, *args)
        assert code == 2 and message in out and out.count("\n") == 1, out


def test_math_is_still_finite_for_in_range_values(tmp_path: Path) -> None:
    """The length bound leaves real robots alone: the bundled XRDF loads and lints clean."""
    from xrdf_tools.xrdf.io import load_xrdf

    x = load_xrdf(UR10E_XRDF)
    assert all(math.isfinite(s.radius) for ss in x.world_collision_spheres().values() for s in ss)


@pytest.mark.parametrize(
    ("old", "key"),
    [
        ("radius: 0.05", "radius"),
        ("shoulder_lift_joint: -2.2", "default_joint_positions.shoulder_lift_joint"),
    ],
)
def test_an_integer_beyond_float_range_is_an_input_error(
    runner: CliRunner, tmp_path: Path, old: str, key: str
) -> None:
    """YAML integers have no size limit; a 400-digit one is not finite as a float."""
    text = UR10E_XRDF.read_text()
    assert old in text
    x = tmp_path / "big.xrdf"
    x.write_text(text.replace(old, old.split(":")[0] + ": " + "9" * 400, 1))
    code, out = run_cli(runner, "diff", str(x), str(UR10E_XRDF))
    assert code == 2 and "is about 1e400; " in out, out
    code, out = run_cli(runner, "lint", str(x))
    assert code == 1 and "internal-error" not in out and "is about 1e400; " in out, out


def test_an_integer_format_version_beyond_float_range_is_an_unsupported_version(
    runner: CliRunner, tmp_path: Path
) -> None:
    x = copy_replacing(
        UR10E_XRDF, tmp_path / "big.xrdf", "format_version: 2.0", "format_version: " + "9" * 400
    )
    code, out = run_cli(runner, "lint", str(x))
    assert code != 0 and "Traceback" not in out and "format_version" in out, out
    code, out = run_cli(
        runner, "viz", str(x), "--urdf", str(UR10E_URDF), "--png", str(tmp_path / "o.png")
    )
    assert code == 2 and out.count("\n") == 1 and "big.xrdf:3:" in out, out


def test_a_configuration_value_beyond_float_range_is_a_located_input_error(
    runner: CliRunner, tmp_path: Path
) -> None:
    configs = tmp_path / "configs.yaml"
    configs.write_text("configurations:\n  - [0.0, -1.57, 1.57, -1.57, " + "9" * 400 + ", 0.0]\n")
    code, out = run_cli(
        runner, "report", str(UR10E_XRDF), "--urdf", str(UR10E_URDF), "--configs", str(configs)
    )
    assert code == 2 and "configs.yaml:2: configuration 0: a value is about 1e400" in out, out


def test_a_number_as_a_curobo_key_is_reported_dropped_with_its_line(
    runner: CliRunner, tmp_path: Path
) -> None:
    from tests.paths import FIXTURES

    lula = FIXTURES / "curobo_classic" / "ur10e_lula.yaml"
    text = lula.read_text()
    assert "jerk_limits:" in text
    src = tmp_path / "robot.yaml"
    src.write_text(text.replace("jerk_limits:", "1:", 1))
    line = text[: text.index("jerk_limits:")].count("\n") + 1
    code, out = run_cli(
        runner, "convert", str(UR10E_URDF), "--curobo", str(src), "-o", str(tmp_path / "o.xrdf")
    )
    assert code == 0 and "Traceback" not in out, out
    assert f"robot.yaml:{line}:1: warning convert-dropped-key '1' has no XRDF equivalent" in out, (
        out
    )
