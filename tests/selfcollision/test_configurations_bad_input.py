"""--configs files that cannot be used: JSON nested too deeply, a YAML bomb, a .npy of the wrong
shape or not an array."""

from __future__ import annotations

from pathlib import Path

from typer.testing import CliRunner

from tests.cli_checks import run_cli, yaml_laughs
from tests.paths import UR10E_URDF, UR10E_XRDF


def test_configs_json_nested_too_deeply(runner: CliRunner, tmp_path: Path) -> None:
    q = tmp_path / "q.json"
    q.write_text("[" * 100_000 + "]" * 100_000)
    code, out = run_cli(
        runner, "report", str(UR10E_XRDF), "--urdf", str(UR10E_URDF), "--configs", str(q)
    )
    assert code == 2 and "nested too deeply" in out


def test_configs_yaml_bomb(runner: CliRunner, tmp_path: Path) -> None:
    q = tmp_path / "q.yaml"
    q.write_text(yaml_laughs())
    code, out = run_cli(
        runner, "report", str(UR10E_XRDF), "--urdf", str(UR10E_URDF), "--configs", str(q)
    )
    assert code == 2 and "aliases expand" in out


def test_npy_of_the_wrong_shape(runner: CliRunner, tmp_path: Path) -> None:
    import numpy as np

    q = tmp_path / "q.npy"
    np.save(q, np.zeros((2, 2, 2)))
    code, out = run_cli(
        runner, "report", str(UR10E_XRDF), "--urdf", str(UR10E_URDF), "--configs", str(q)
    )
    assert code == 2 and "[B, k]" in out
    q.write_bytes(b"\x93NUMPY garbage")
    code, out = run_cli(
        runner, "report", str(UR10E_XRDF), "--urdf", str(UR10E_URDF), "--configs", str(q)
    )
    assert code == 2 and "not a numeric .npy array" in out
