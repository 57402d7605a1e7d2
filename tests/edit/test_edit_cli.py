"""``xrdf edit`` on the command line: usage errors, the missing extra, serving, Ctrl-C.

The served page itself is tested in a browser by tests/edit/test_edit_browser.py.
"""

from __future__ import annotations

import http.client
import importlib.util
import os
import shutil
import signal
import subprocess
import sys
import time
import urllib.request
from pathlib import Path
from typing import Any

import pytest
from typer.testing import CliRunner

from tests.browser import free_port
from tests.paths import FIXTURES
from tests.robots import robot_urdf
from xrdf_tools.cli import app

PANDA_XRDF = FIXTURES / "panda" / "panda.xrdf"
DEMO = FIXTURES / "demo_arm"
NO_BROWSER = "--no-browser"

needs_viser = pytest.mark.skipif(
    importlib.util.find_spec("viser") is None, reason="xrdf edit needs viser (the edit extra)"
)


def run(runner: CliRunner, *args: str) -> Any:
    return runner.invoke(app, ["edit", *args])


def test_without_the_extra_it_says_which_to_install(
    runner: CliRunner, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setitem(sys.modules, "viser", None)  # an import of viser fails
    r = run(runner, str(PANDA_XRDF), "--urdf", "robot.urdf")
    assert r.exit_code == 2
    assert r.output.strip().splitlines() == [
        "error: xrdf edit needs the 'edit' extra (viser not installed): "
        'pip install "xrdf-tools[edit]"'
    ]


@needs_viser
@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--urdf", "r.urdf"], "give ROBOT.xrdf to edit, or -o NEW.xrdf"),
        ([str(PANDA_XRDF)], "--urdf is required"),
        ([str(PANDA_XRDF), "--urdf", "r.urdf", "--srdf", "r.srdf"], "--srdf is read only"),
        (["-", "--urdf", "r.urdf"], "needs files"),
        (["--urdf", "r.urdf", "-o", str(PANDA_XRDF)], "exists; edit it with"),
    ],
)
def test_usage_errors(runner: CliRunner, args: list[str], message: str) -> None:
    r = run(runner, *args)
    assert r.exit_code == 2, r.output
    assert message in r.output and "Traceback" not in r.output


@needs_viser
def test_output_may_not_be_an_input(runner: CliRunner, tmp_path: Path) -> None:
    r = run(
        runner,
        str(PANDA_XRDF),
        "--urdf",
        str(DEMO / "demo_arm.urdf"),
        "-o",
        str(DEMO / "demo_arm.urdf"),
    )
    assert r.exit_code == 2 and "demo_arm.urdf" in r.output


@needs_viser
def test_output_may_not_be_a_mesh_of_the_robot(tmp_path: Path) -> None:
    """Save would write over the mesh: refused before anything is served."""
    panda = robot_urdf("panda").parents[1]
    shutil.copytree(panda, tmp_path / "robots" / "panda_description")
    urdf = tmp_path / "robots" / "panda_description" / "urdf" / "panda.urdf"
    mesh = urdf.parents[1] / "meshes" / "visual" / "link0.dae"
    args = [str(PANDA_XRDF), "--urdf", str(urdf), "-o", str(mesh), "--port", str(free_port())]
    args += ["--package-path", f"example-robot-data={tmp_path}", NO_BROWSER]
    cli = [sys.executable, "-c", "from xrdf_tools.cli import main; main()", "edit", *args]
    try:  # the page would be served until stopped: a bounded wait
        r = subprocess.run(cli, capture_output=True, text=True, timeout=60)
    except subprocess.TimeoutExpired:
        pytest.fail("xrdf edit served a page that would save over a mesh of the robot")
    assert r.returncode == 2 and f"{mesh}: refusing to overwrite an input" in r.stderr, r.stderr
    assert mesh.read_bytes() == (panda / "meshes" / "visual" / "link0.dae").read_bytes()


def serve(
    args: list[str], ready: str = " (Ctrl-C stops"
) -> tuple[subprocess.Popen[str], str, float]:
    """Start ``xrdf edit`` and wait for its address line; returns (process, stderr so far,
    seconds until the address was printed)."""
    t0 = time.perf_counter()
    env = {**os.environ, "PYTHONUNBUFFERED": "1", "COLUMNS": "200"}
    proc = subprocess.Popen(
        [
            sys.executable,
            "-c",
            "from xrdf_tools.cli import main; main()",
            "edit",
            *args,
            NO_BROWSER,
        ],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=env,
        # a test runner started in the background has SIGINT ignored, and xrdf keeps an
        # ignored SIGINT ignored (as nohup asks); the user's terminal has it default
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    assert proc.stderr is not None
    seen = ""
    while ready not in seen:
        line = proc.stderr.readline()
        if not line:
            _, err = proc.communicate(timeout=30)
            raise AssertionError(f"xrdf edit ended early ({proc.returncode}): {seen}{err}")
        seen += line
    return proc, seen, time.perf_counter() - t0


def status(port: int, address: str, headers: dict[str, str]) -> int:
    """The HTTP status of the page's index at ``address`` (``headers``: a Host of its own)."""
    conn = http.client.HTTPConnection(address, port, timeout=10)
    try:
        conn.request("GET", "/", headers=headers)
        return conn.getresponse().status
    finally:
        conn.close()


def stop(proc: subprocess.Popen[str]) -> tuple[int, str, str]:
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=30)
    return proc.returncode, out, err


@needs_viser
@pytest.mark.slow
def test_serves_the_page_and_stops_cleanly_on_ctrl_c(tmp_path: Path) -> None:
    target = tmp_path / "panda.xrdf"
    target.write_bytes(PANDA_XRDF.read_bytes())
    port = free_port()
    proc, seen, _ = serve([str(target), "--urdf", str(robot_urdf("panda")), "--port", str(port)])
    try:
        assert f"at http://127.0.0.1:{port} " in seen
        assert "warning" not in seen
        with urllib.request.urlopen(f"http://127.0.0.1:{port}/", timeout=10) as page:
            assert page.status == 200 and b"<html" in page.read().lower()
        for _ in range(2):  # a DNS-rebinding page: refused, and said once
            assert status(port, "127.0.0.1", {"Host": f"evil.example:{port}"}) == 403
    finally:
        code, out, err = stop(proc)
    assert code == 0, err
    assert err.count("warning: refused a request for evil.example") == 1, err
    assert "Traceback" not in err and "KeyboardInterrupt" not in err
    assert out == ""  # viser's own banner is not printed
    assert target.read_bytes() == PANDA_XRDF.read_bytes()  # nothing saved without Save


@needs_viser
@pytest.mark.slow
def test_another_host_warns_that_anyone_can_edit(tmp_path: Path) -> None:
    port = free_port()
    proc, seen, _ = serve(
        [
            str(PANDA_XRDF),
            "--urdf",
            str(robot_urdf("panda")),
            "--port",
            str(port),
            "--host",
            "127.0.0.2",
        ]
    )
    try:  # the page at the address it listens on is served
        assert status(port, "127.0.0.2", {}) == 200
    finally:
        code, _, err = stop(proc)
    assert code == 0
    assert "warning: listening on 127.0.0.2: anyone who can reach port" in seen
    assert "refused" not in err


@needs_viser
@pytest.mark.slow
def test_draft_from_the_urdf_is_not_written_without_save(tmp_path: Path) -> None:
    out = tmp_path / "three_link.xrdf"
    urdf = FIXTURES / "urdf" / "three_link_mimic.urdf"
    args = ["--urdf", str(urdf), "-o", str(out), "--port", str(free_port()), "--samples", "200"]
    proc, seen, _ = serve(args)
    code, _, err = stop(proc)
    assert code == 0, err
    assert f"drafting {out}" in seen
    # the guess's message names convert's options; the page's C-space panel is the way here
    assert "convert-chosen-group" in seen and "change them in the page's C-space panel" in seen
    assert "unsaved changes" in err
    assert not out.exists()
