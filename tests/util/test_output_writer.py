"""The one output writer (util.fileio): symlinks kept, devices and FIFOs refused, no temporary
file left on an interrupt, SIGTERM or a full disk, errors naming the requested path."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest
from typer.testing import CliRunner

from tests.cli_checks import posix_only, run_cli
from tests.paths import REPO, UR10E_URDF
from xrdf_tools.util.errors import OutputError
from xrdf_tools.util.fileio import atomic_output, write_atomic


@posix_only
def test_writing_through_a_symlink_keeps_the_link(tmp_path: Path) -> None:
    target = tmp_path / "real.xrdf"
    target.write_text("old")
    target.chmod(0o640)
    link = tmp_path / "link.xrdf"
    link.symlink_to(target.name)
    write_atomic(link, "new")
    assert link.is_symlink() and target.read_text() == "new"
    assert (target.stat().st_mode & 0o777) == 0o640
    assert sorted(p.name for p in tmp_path.iterdir()) == ["link.xrdf", "real.xrdf"]


@posix_only
def test_devices_and_fifos_are_refused_as_outputs(runner: CliRunner, tmp_path: Path) -> None:
    fifo = tmp_path / "out.xrdf"
    os.mkfifo(fifo)
    for path in (fifo, Path("/dev/null")):
        with pytest.raises(OutputError, match="not a regular file; refusing to replace it") as e:
            write_atomic(path, "x")
        assert e.value.path == str(path)
        code, out = run_cli(runner, "convert", str(UR10E_URDF), "-o", str(path))
        assert code == 2 and f"{path}: is a" in out
    assert fifo.exists() and not fifo.is_file()
    with pytest.raises(OutputError, match="is a directory"):
        write_atomic(tmp_path, "x")


@posix_only
def test_a_file_nobody_may_write_is_not_replaced(runner: CliRunner, tmp_path: Path) -> None:
    """`chmod a-w robot.xrdf` protects a file; the rename of an atomic write replaced it anyway
    (even as root). Every command now refuses, exit 2, and leaves it as it was; the file's
    directory is left with nothing new in it."""
    out = tmp_path / "robot.xrdf"
    out.write_text("protected")
    out.chmod(0o444)
    with pytest.raises(OutputError, match=r"is read-only .*: refusing to replace it"):
        write_atomic(out, "x")
    code, said = run_cli(runner, "convert", str(UR10E_URDF), "-o", str(out))
    assert code == 2 and f"{out}: is read-only (no write permission)" in said
    assert out.read_text() == "protected" and [p.name for p in tmp_path.iterdir()] == [out.name]
    out.chmod(0o644)  # writable by its owner only is writable
    write_atomic(out, "new")
    assert out.read_text() == "new"


def test_temporary_file_is_removed_on_interrupt(tmp_path: Path) -> None:
    out = tmp_path / "out.txt"
    with pytest.raises(KeyboardInterrupt), atomic_output(out) as tmp:
        tmp.write_text("partial")
        raise KeyboardInterrupt
    assert list(tmp_path.iterdir()) == []


def test_write_errors_name_the_requested_path(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import errno

    def full(*_args: object) -> None:
        raise OSError(errno.ENOSPC, "No space left on device", str(tmp_path / ".out.x.tmp"))

    monkeypatch.setattr(os, "replace", full)
    out = tmp_path / "out.xrdf"
    with pytest.raises(OutputError) as e:
        write_atomic(out, "data")
    assert str(e.value) == f"{out}: cannot write: No space left on device"
    assert isinstance(e.value, OSError) and e.value.filename == str(out)
    assert list(tmp_path.iterdir()) == []


@posix_only
def test_sigterm_removes_the_temporary_file(tmp_path: Path) -> None:
    script = (
        "import os, signal, sys\n"
        "from xrdf_tools.cli import _on_signal\n"
        "from xrdf_tools.util.fileio import atomic_output\n"
        "signal.signal(signal.SIGTERM, _on_signal)\n"
        f"with atomic_output({str(tmp_path / 'out.txt')!r}) as tmp:\n"
        "    tmp.write_text('partial')\n"
        "    os.kill(os.getpid(), signal.SIGTERM)\n"
        "    signal.pause()\n"
    )
    env = {**os.environ, "PYTHONPATH": str(REPO)}
    res = subprocess.run([sys.executable, "-c", script], env=env, timeout=60, check=False)
    assert res.returncode == 128 + 15
    assert list(tmp_path.iterdir()) == []
