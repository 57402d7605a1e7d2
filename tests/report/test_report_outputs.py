"""xrdf report's output files: one path for two outputs is refused, a failed write names the
output, not its temporary file."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from typer.testing import CliRunner

from tests.cli_checks import run_cli
from tests.paths import UR10E_URDF, UR10E_XRDF
from tests.robots import dollar_robot


@pytest.mark.parametrize(
    ("first", "second"), [("-o", "--write-mask"), ("-o", "--plot"), ("--plot", "--write-mask")]
)
def test_report_refuses_one_path_for_two_outputs(
    runner: CliRunner, tmp_path: Path, first: str, second: str
) -> None:
    r = tmp_path / "R"
    code, out = run_cli(
        runner,
        "report",
        str(UR10E_XRDF),
        "--urdf",
        str(UR10E_URDF),
        "-n",
        "10",
        first,
        str(r),
        second,
        str(r),
    )
    assert code == 2 and "given for both" in out
    assert not r.exists()


def test_report_errors_name_the_output_not_the_temporary(
    runner: CliRunner, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import errno

    def full(*_args: object) -> None:
        raise OSError(errno.ENOSPC, "No space left on device", "/somewhere/.mask.tmp")

    monkeypatch.setattr(os, "replace", full)
    mask = tmp_path / "mask.xrdf"
    code, out = run_cli(
        runner,
        "report",
        str(UR10E_XRDF),
        "--urdf",
        str(UR10E_URDF),
        "-n",
        "10",
        "--write-mask",
        str(mask),
    )
    assert code == 2 and f"{mask}: " in out and ".tmp" not in out and "No space left" in out


def test_plot_draws_frame_names_with_dollar_signs_as_written(
    runner: CliRunner, tmp_path: Path
) -> None:
    """Frame names with ``$`` signs are drawn as written on the matrix: matplotlib's math text
    would stop at an unknown command (a traceback) or italicise what lies between two."""
    pytest.importorskip("matplotlib")
    pytest.importorskip("trimesh")
    urdf, _ = dollar_robot(tmp_path)
    xrdf = tmp_path / "r.xrdf"
    code, out = run_cli(
        runner,
        "convert",
        str(urdf),
        "--fit-spheres",
        "--per-link",
        "1",
        "-n",
        "50",
        "-o",
        str(xrdf),
    )
    assert code == 0, out
    png = tmp_path / "matrix.png"
    code, out = run_cli(
        runner, "report", str(xrdf), "--urdf", str(urdf), "-n", "50", "--plot", str(png)
    )
    assert code in (0, 1), out
    assert "Traceback" not in out
    assert png.read_bytes().startswith(b"\x89PNG")
