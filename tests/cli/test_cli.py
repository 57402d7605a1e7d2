from __future__ import annotations

import subprocess
import sys

from typer.testing import CliRunner

from tests.paths import UR10E_XRDF
from xrdf_tools import __version__
from xrdf_tools.cli import app


def test_help_lists_the_five_subcommands(runner: CliRunner) -> None:
    result = runner.invoke(app, ["--help"])
    assert result.exit_code == 0
    for name in ("convert", "lint", "diff", "report", "viz"):
        assert name in result.output


def test_version(runner: CliRunner) -> None:
    result = runner.invoke(app, ["--version"])
    assert result.exit_code == 0 and __version__ in result.output


def test_python_dash_m_entry_point() -> None:
    out = subprocess.run(
        [sys.executable, "-m", "xrdf_tools", "--version"],
        capture_output=True,
        text=True,
        check=False,
    )
    assert out.returncode == 0 and "xrdf-tools" in out.stdout


def test_bad_file_is_one_line_error_not_traceback(runner: CliRunner, tmp_path: object) -> None:
    from pathlib import Path

    bad = Path(str(tmp_path)) / "bad.xrdf"
    bad.write_text("format: xrdf\nformat_version: 2.0\ncspace: [\n")
    result = runner.invoke(app, ["lint", str(bad)])
    assert result.exit_code != 0
    assert "Traceback" not in result.output
    assert f"{bad}:" in result.output


def test_lint_bundled_example_is_clean(runner: CliRunner) -> None:
    result = runner.invoke(app, ["lint", str(UR10E_XRDF)])
    assert result.exit_code == 0, result.output
