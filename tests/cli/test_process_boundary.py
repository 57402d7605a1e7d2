"""The process boundary through the real ``xrdf`` executable: Ctrl-C and SIGTERM end any
command promptly (workers included) with exit 130/143, no traceback and nothing left behind;
output that cannot reach standard output (closed, full, a closed pipe) is an error, never lost;
``--jobs`` and ``--samples`` are bounded."""

from __future__ import annotations

import contextlib
import io
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from tests.paths import FIXTURES, UR10E_URDF, UR10E_XRDF

XRDF = Path(sys.executable).parent / "xrdf"
#: Generous for a loaded CI machine; the promise (docs/security.md) is about a second.
STOP_WITHIN_S = 5.0
pytestmark = pytest.mark.skipif(sys.platform == "win32", reason="POSIX signals")


def _start(
    args: list[str], cwd: Path, stdout: int | None = subprocess.PIPE
) -> subprocess.Popen[bytes]:
    return subprocess.Popen(
        [str(XRDF), *args],
        cwd=cwd,
        stdout=stdout,
        stderr=subprocess.PIPE,
        start_new_session=True,  # its own process group: a terminal's Ctrl-C reaches them all
        # a test runner may have been started with SIGINT ignored; a terminal has it default
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )


def _group_alive(pgid: int) -> list[str]:
    res = subprocess.run(
        ["ps", "-o", "pid=,stat=", "-g", str(pgid)], capture_output=True, text=True
    )
    return [ln for ln in res.stdout.split("\n") if ln.strip() and "Z" not in ln.split()[-1]]


def _stop(proc: subprocess.Popen[bytes], sig: int, *, group: bool) -> tuple[float, str]:
    start = time.monotonic()
    if group:
        os.killpg(proc.pid, sig)
    else:
        proc.send_signal(sig)
    try:
        _, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
    return time.monotonic() - start, err.decode(errors="replace")


def _wait_for_workers(proc: subprocess.Popen[bytes], n: int, limit_s: float = 60) -> None:
    end = time.monotonic() + limit_s
    while time.monotonic() < end:
        assert proc.poll() is None, proc.communicate()
        workers = [ln for ln in _group_alive(proc.pid) if int(ln.split()[0]) != proc.pid]
        if len(workers) >= n:
            time.sleep(1.0)  # let them start counting
            return
        time.sleep(0.1)
    raise AssertionError("the workers did not start")


@pytest.mark.slow
@pytest.mark.parametrize(
    ("sig", "group", "code"),
    [(signal.SIGINT, True, 130), (signal.SIGTERM, False, 143)],
)
def test_a_signal_stops_report_and_its_workers(
    tmp_path: Path, sig: int, group: bool, code: int
) -> None:
    out = tmp_path / "report.txt"
    proc = _start(
        [
            "report",
            str(UR10E_XRDF),
            "--urdf",
            str(UR10E_URDF),
            "-n",
            "2000000000",
            "-j",
            "2",
            "-o",
            str(out),
        ],
        tmp_path,
    )
    _wait_for_workers(proc, 2)
    took, err = _stop(proc, sig, group=group)
    assert proc.returncode == code, err
    assert took < STOP_WITHIN_S, took
    assert "Traceback" not in err and err.strip() in ("interrupted", "terminated"), err
    time.sleep(0.5)
    assert _group_alive(proc.pid) == []  # no worker left running
    assert list(tmp_path.iterdir()) == []  # no output, no temporary file


def _wait_for_handler(pid: int) -> None:
    """Until ``xrdf`` handles the signals itself (its first statement; before it, the
    interpreter is still starting and Python's own SIGINT handler would print a traceback).
    Python catches SIGINT from its start, SIGTERM only once ``xrdf`` asks: that is the mark."""
    status = Path(f"/proc/{pid}/status")
    end = time.monotonic() + 30
    while status.exists() and time.monotonic() < end:
        caught = next((ln for ln in status.read_text().splitlines() if ln.startswith("SigCgt")), "")
        if caught and int(caught.split()[1], 16) & (1 << (signal.SIGTERM - 1)):
            return
        time.sleep(0.01)


@pytest.mark.parametrize("delay", [0.0, 0.3, 1.0, 2.0])
def test_ctrl_c_at_any_moment_of_start_up(tmp_path: Path, delay: float) -> None:
    """A Ctrl-C while the command imports its libraries (trimesh's import swallows it) or
    starts its workers still ends it."""
    proc = _start(
        ["report", str(UR10E_XRDF), "--urdf", str(UR10E_URDF), "-n", "2000000000", "-j", "2"],
        tmp_path,
    )
    _wait_for_handler(proc.pid)
    time.sleep(delay)
    took, err = _stop(proc, signal.SIGINT, group=True)
    assert proc.returncode == 130 and took < STOP_WITHIN_S, (took, err)
    assert "Traceback" not in err, err


def test_sigterm_while_writing_leaves_no_temporary_file(tmp_path: Path) -> None:
    demo = FIXTURES / "demo_arm"
    proc = _start(
        [
            "convert",
            str(demo / "demo_arm.urdf"),
            "--srdf",
            str(demo / "demo_arm.srdf"),
            "--fit-spheres",
            "-n",
            "2000000000",
            "-o",
            "out.xrdf",
        ],
        tmp_path,
    )
    time.sleep(3.0)
    took, err = _stop(proc, signal.SIGTERM, group=False)
    assert proc.returncode == 143 and took < STOP_WITHIN_S, (took, err)
    assert "Traceback" not in err, err
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGINT])
def test_a_signal_that_leaves_a_library_half_imported_still_ends_quietly(
    tmp_path: Path, signum: int
) -> None:
    """A signal landing while a library imports can be swallowed by that import, which then
    fails on a name it never bound (scipy.ndimage under a SIGTERM: NameError, exit 1 and a
    traceback). The command still ends as the signal says: 128 + signum, no traceback."""
    (tmp_path / "halfway.py").write_text(
        "import os, time\n"
        "try:\n"
        f"    os.kill(os.getpid(), {int(signum)})\n"
        "    time.sleep(0.2)\n"
        "    bound = 1\n"
        "except BaseException:\n"
        "    pass\n"
        "del bound\n"
    )
    code = (
        "import sys\n"
        "import xrdf_tools.cli as cli\n"
        "def run():\n    import halfway\n"
        "cli._run = run\n"
        "cli.main()\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", code],
        cwd=tmp_path,
        env={**os.environ, "PYTHONPATH": f"{tmp_path}{os.pathsep}{Path.cwd()}"},
        capture_output=True,
        text=True,
        timeout=60,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    assert done.returncode == 128 + signum, done.stderr
    assert "Traceback" not in done.stderr and "NameError" not in done.stderr, done.stderr


# ---------------------------------------------------------------------------------------------
# Standard output
# ---------------------------------------------------------------------------------------------
COMMANDS = {
    "lint-json": ["lint", str(UR10E_XRDF), "-f", "json"],
    "export-curobo": ["export", "curobo", str(UR10E_XRDF), "--urdf", str(UR10E_URDF)],
    "convert": ["convert", str(UR10E_URDF)],
    "report": ["report", str(UR10E_XRDF), "--urdf", str(UR10E_URDF), "-n", "50"],
}


def _run(args: list[str], **kw: object) -> subprocess.CompletedProcess[bytes]:
    return subprocess.run([str(XRDF), *args], capture_output=False, timeout=120, check=False, **kw)  # type: ignore[call-overload, no-any-return]


@pytest.mark.parametrize("name", ["lint-json", "export-curobo"])
def test_a_full_standard_output_is_an_error(name: str) -> None:
    with open("/dev/full", "wb") as full:
        res = _run(COMMANDS[name], stdout=full, stderr=subprocess.PIPE)
    err = res.stderr.decode()
    assert res.returncode == 2 and "Traceback" not in err, err
    assert "standard output: cannot write: No space left on device" in err


@pytest.mark.parametrize("name", list(COMMANDS))
def test_a_closed_standard_output_is_an_error(name: str) -> None:
    res = subprocess.run(
        ["sh", "-c", '"$0" "$@" >&-', str(XRDF), *COMMANDS[name]],
        capture_output=True,
        timeout=120,
        check=False,
    )
    err = res.stderr.decode()
    assert res.returncode == 2 and "standard output is closed" in err, err
    assert "Traceback" not in err


@pytest.mark.parametrize("name", ["lint-json", "export-curobo"])
def test_a_closed_pipe_is_an_error(name: str) -> None:
    read_end, write_end = os.pipe()
    os.close(read_end)  # the reader is gone before anything is written
    try:
        res = _run(COMMANDS[name], stdout=write_end, stderr=subprocess.PIPE)
    finally:
        os.close(write_end)
    err = res.stderr.decode()
    assert res.returncode == 2 and "standard output: cannot write: Broken pipe" in err, err
    assert "Traceback" not in err


def test_output_goes_to_any_text_stream(tmp_path: Path) -> None:
    """In process, with a text stream as standard output (no ``.buffer``)."""
    from xrdf_tools.cli import app

    srdf = FIXTURES / "fuzz" / "ur10e.srdf"
    stream = io.StringIO()
    with contextlib.redirect_stdout(stream), contextlib.suppress(SystemExit):
        app(["export", "srdf", str(UR10E_XRDF), "--urdf", str(UR10E_URDF), "--merge", str(srdf)])
    assert stream.getvalue().lstrip().startswith("<?xml"), stream.getvalue()[:200]


@pytest.mark.parametrize("spelling", ["newdir/", "a/b/"])
def test_an_output_naming_a_missing_directory_is_an_error(tmp_path: Path, spelling: str) -> None:
    res = _run(
        ["convert", str(UR10E_URDF), "-q", "-o", spelling],
        cwd=tmp_path,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
    )
    assert res.returncode == 2 and "ends with '/'" in res.stderr.decode()
    assert list(tmp_path.iterdir()) == []


# ---------------------------------------------------------------------------------------------
# --jobs and --samples
# ---------------------------------------------------------------------------------------------
def test_samples_past_the_ceiling_are_a_usage_error() -> None:
    res = _run(
        ["report", str(UR10E_XRDF), "--urdf", str(UR10E_URDF), "-n", "9" * 23],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
    )
    err = res.stderr.decode()
    assert res.returncode == 2 and "10000000000" in err and "Traceback" not in err, err


def test_jobs_beyond_the_cores_are_clamped_with_a_note() -> None:
    from xrdf_tools.selfcollision.engine import default_jobs

    res = _run(
        ["report", str(UR10E_XRDF), "--urdf", str(UR10E_URDF), "-n", "100", "-j", "999"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
    )
    err = res.stderr.decode()
    assert res.returncode == 0, err
    assert f"--jobs 999: this process may use {default_jobs()} core(s)" in err
