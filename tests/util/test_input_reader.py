"""The one guarded input reader (util.fileio): FIFOs, devices, directories, links to devices,
the size limit, standard input only where allowed, bytes that are not UTF-8."""

from __future__ import annotations

import io
import os
import sys
import time
from pathlib import Path

import pytest
from typer.testing import CliRunner

from tests.cli_checks import posix_only, run_cli
from tests.paths import UR10E_URDF, UR10E_XRDF
from xrdf_tools.util.errors import InputError, UrdfError, YamlError
from xrdf_tools.util.fileio import ENV_MAX_INPUT, read_input_bytes, read_input_text
from xrdf_tools.yaml.io import load_yaml


@posix_only
@pytest.mark.parametrize("command", ["lint", "diff"])
def test_a_fifo_input_is_refused_without_reading(
    runner: CliRunner, tmp_path: Path, command: str
) -> None:
    fifo = tmp_path / "robot.xrdf"
    os.mkfifo(fifo)
    args = [command, str(fifo)] + ([str(UR10E_XRDF)] if command == "diff" else [])
    start = time.monotonic()
    code, out = run_cli(runner, *args)
    assert code == 2 and "FIFO" in out and f"{fifo}:" in out
    assert time.monotonic() - start < 10


@posix_only
def test_dev_zero_and_directories_are_refused_as_inputs(runner: CliRunner, tmp_path: Path) -> None:
    with pytest.raises(UrdfError, match="character device, not a regular file"):
        read_input_bytes("/dev/zero", what="URDF file", error=UrdfError)
    with pytest.raises(InputError, match=r"is a directory \(file expected\)"):
        read_input_bytes(tmp_path)
    code, out = run_cli(runner, "convert", str(UR10E_URDF), "--srdf", "/dev/zero")
    assert code == 2 and "/dev/zero: is a character device" in out


@posix_only
def test_a_link_to_dev_zero_is_refused(runner: CliRunner, tmp_path: Path) -> None:
    link = tmp_path / "robot.urdf"
    link.symlink_to("/dev/zero")
    code, out = run_cli(runner, "lint", str(UR10E_XRDF), "--urdf", str(link))
    assert code == 2 and "not a regular file" in out


def test_size_limit(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    big = tmp_path / "big.xrdf"
    big.write_text("- 1\n" * 1000)
    monkeypatch.setenv(ENV_MAX_INPUT, "0.001")
    with pytest.raises(YamlError, match=f"input limit; set {ENV_MAX_INPUT}") as e:
        load_yaml(big)
    assert e.value.path == str(big)
    monkeypatch.setenv(ENV_MAX_INPUT, "nonsense")
    with pytest.raises(InputError, match="positive number"):
        read_input_bytes(big)
    monkeypatch.delenv(ENV_MAX_INPUT)
    assert load_yaml(big).root is not None


def test_stdin_only_when_allowed(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(sys, "stdin", io.TextIOWrapper(io.BytesIO(b"a: 1\n")))
    assert read_input_text("-", allow_stdin=True) == "a: 1\n"
    with pytest.raises(InputError, match="not found"):
        read_input_bytes("-")


def test_non_utf8_is_reported_at_its_position(tmp_path: Path) -> None:
    p = tmp_path / "robot.xrdf"
    p.write_bytes(b"format: xrdf\nname: caf\xe9\n")
    with pytest.raises(YamlError, match="not UTF-8") as e:
        load_yaml(p)
    assert (e.value.line, e.value.col) == (2, 10)
