"""xacro expansion is bounded in wall time and memory (``XRDF_XACRO_TIMEOUT``,
``XRDF_XACRO_MEMORY``): an endless expression, a macro fan-out or a memory bomb is one
located line and exit 2, never a hang; a real xacro expands to the same text, warnings,
included files and located errors as in the calling process."""

from __future__ import annotations

import os
import subprocess
import sys
import threading
from pathlib import Path

import pytest
from typer.testing import CliRunner

from tests.cli_checks import run_cli
from tests.paths import FIXTURES
from xrdf_tools.diagnostics import Diagnostic
from xrdf_tools.robot.xacro_child import XacroBoundError
from xrdf_tools.robot.xacro_source import expand_xacro
from xrdf_tools.util.errors import SourceError

ARM = FIXTURES / "fuzz" / "arm.urdf.xacro"
REPO = Path(__file__).resolve().parents[2]
#: Far more than the one-second bound below needs, on a loaded machine; the old code never ends.
HANG_S = 60
HEAD = '<?xml version="1.0"?>\n<robot name="bomb" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
#: A macro calling itself twice per level: 2**40 calls.
FAN_OUT = """  <xacro:macro name="f" params="n">
    <xacro:if value="${n > 0}">
      <xacro:f n="${n-1}"/>
      <xacro:f n="${n-1}"/>
    </xacro:if>
  </xacro:macro>
  <link name="base"/>
  <xacro:f n="40"/>
"""
UNBOUNDED = {"XRDF_XACRO_TIMEOUT": "0", "XRDF_XACRO_MEMORY": "0"}


def _xacro(tmp_path: Path, body: str, name: str = "bomb.urdf.xacro") -> Path:
    path = tmp_path / name
    path.write_text(HEAD + body + "</robot>\n", encoding="utf-8")
    return path


def _expand_cli(path: Path, **env: str) -> subprocess.CompletedProcess[str]:
    """``xrdf expand PATH`` as a fresh process (the old code would never return: cut off)."""
    return subprocess.run(
        [sys.executable, "-m", "xrdf_tools", "expand", path.name],
        cwd=path.parent,
        env={**os.environ, **env},
        capture_output=True,
        text=True,
        timeout=HANG_S,
    )


@pytest.mark.parametrize(
    "body",
    [
        pytest.param('  <link name="${9**9**9}"/>\n', id="endless-expression"),
        pytest.param(FAN_OUT, id="macro-fan-out"),
    ],
)
def test_an_expansion_that_does_not_end_is_one_line_past_the_timeout(
    tmp_path: Path, body: str
) -> None:
    path = _xacro(tmp_path, body)
    done = _expand_cli(path, XRDF_XACRO_TIMEOUT="1")
    assert done.returncode == 2 and done.stdout == ""
    assert done.stderr == (
        "error: bomb.urdf.xacro: xacro expansion did not finish in 1 s (an expression such as "
        "${9**9**9} or a macro fan-out?); raise the limit with XRDF_XACRO_TIMEOUT=SECONDS\n"
    )


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="RLIMIT_AS is Linux's")
def test_a_memory_bomb_is_one_line_naming_the_limit(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    path = _xacro(tmp_path, "  <link name=\"${len('a'*10**11)}\"/>\n")
    monkeypatch.setenv("XRDF_XACRO_MEMORY", "256")
    with pytest.raises(XacroBoundError) as caught:
        expand_xacro(path)
    assert str(caught.value) == (
        f"{path}: xacro expansion needed more than 256 MiB of memory (an expression such as "
        "${'a'*10**11} or a macro fan-out?); raise the limit with XRDF_XACRO_MEMORY=MIB"
    )


def _expanded(path: Path, args: dict[str, str]) -> tuple[str, list[Diagnostic], list[str]]:
    said: list[Diagnostic] = []
    included: list[str] = []
    text = expand_xacro(path, args, data=None, warnings=said, includes=included)
    return text, said, included


def test_a_bounded_expansion_gives_what_one_in_this_process_gives(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The text, xacro's warnings, an unread argument's warning and the included files."""
    (tmp_path / "part.xacro").write_text(
        HEAD.replace('name="bomb" ', "") + '  <link name="part_${2}"/>\n</robot>\n',
        encoding="utf-8",
    )
    ignored = '<xacro:arg name="x" value="1"/>'  # xacro ignores it, with a warning
    path = _xacro(tmp_path, f'  <xacro:include filename="part.xacro">{ignored}</xacro:include>\n')
    args = {"unused": "1"}
    bounded = _expanded(path, args)
    for name, value in UNBOUNDED.items():
        monkeypatch.setenv(name, value)
    assert bounded == _expanded(path, args)
    text, said, included = bounded
    assert 'name="part_2"' in text and included == [str(tmp_path / "part.xacro")]
    assert {d.rule for d in said} == {"xacro-warning", "xacro-arg-unread"}
    assert expand_xacro(ARM) == _expanded(ARM, {})[0]


def test_a_located_error_comes_back_from_the_child_as_it_was(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    path = _xacro(tmp_path, '  <link name="base"/>\n  <link name="${radius * 2}"/>\n')

    def error() -> tuple[type, str, str | None, int | None, int | None]:
        with pytest.raises(SourceError) as caught:
            expand_xacro(path)
        e = caught.value
        return type(e), e.message, e.path, e.line, e.col

    bounded = error()
    for name, value in UNBOUNDED.items():
        monkeypatch.setenv(name, value)
    assert bounded == error()
    assert bounded[3] == 4 and "radius" in bounded[1]


def test_expansions_from_several_threads_each_get_their_own_result(tmp_path: Path) -> None:
    """Another thread running: the children come from the fork server, side by side."""
    other = _xacro(tmp_path, '  <link name="${2 * 21}"/>\n', "other.urdf.xacro")
    want = {ARM: expand_xacro(ARM), other: expand_xacro(other)}
    got: dict[int, tuple[Path, str]] = {}

    def expand(i: int, path: Path) -> None:
        got[i] = path, expand_xacro(path)

    threads = [threading.Thread(target=expand, args=(i, (ARM, other)[i % 2])) for i in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert len(got) == 4 and all(text == want[path] for path, text in got.values())
    assert 'name="42"' in want[other]


@pytest.mark.parametrize("name", ["XRDF_XACRO_TIMEOUT", "XRDF_XACRO_MEMORY"])
def test_a_limit_that_is_no_number_is_an_input_error(
    runner: CliRunner, monkeypatch: pytest.MonkeyPatch, name: str
) -> None:
    monkeypatch.setenv(name, "soon")
    code, out = run_cli(runner, "expand", str(ARM))
    unit = "seconds" if name.endswith("TIMEOUT") else "MiB"
    assert code == 2
    assert out.strip().splitlines()[-1] == (
        f"error: {name}='soon' must be a number of {unit} (0: no limit)"
    )


def test_a_child_that_cannot_start_is_said_at_the_xacro_file(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A process limit or a sandbox that refuses new processes: one located line naming the
    file and how to expand in this process instead, not an error without a place."""
    import multiprocessing.process

    def refuse(_self: object) -> None:
        raise OSError(11, "Resource temporarily unavailable")

    monkeypatch.setattr(multiprocessing.process.BaseProcess, "start", refuse)
    with pytest.raises(SourceError) as caught:
        expand_xacro(ARM)
    assert caught.value.path == str(ARM)
    assert "cannot start the process that expands xacro (Resource temporarily" in str(caught.value)
    assert "XRDF_XACRO_TIMEOUT=0" in caught.value.message


def _script(tmp_path: Path, body: str) -> Path:
    script = tmp_path / "caller.py"
    script.write_text(body, encoding="utf-8")
    return script


def test_a_child_does_not_run_the_callers_script_again(tmp_path: Path) -> None:
    """Another thread running (the fork server): the child imports none of the caller's main
    script, which here has no ``__main__`` guard and says each time it runs."""
    script = _script(
        tmp_path,
        "import sys, threading\nprint('script ran', flush=True)\n"
        "from xrdf_tools.robot.xacro_source import expand_xacro\n"
        "stop = threading.Event()\nthreading.Thread(target=stop.wait).start()\n"
        f"try:\n    print(len(expand_xacro({str(ARM)!r})) > 0)\nfinally:\n    stop.set()\n",
    )
    done = subprocess.run(
        [sys.executable, str(script)],
        cwd=REPO,
        env={**os.environ, "PYTHONPATH": str(REPO)},
        capture_output=True,
        text=True,
        timeout=HANG_S,
    )
    assert (done.returncode, done.stdout, done.stderr) == (0, "script ran\nTrue\n", "")


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="PR_SET_PDEATHSIG is Linux's")
def test_a_child_ends_with_a_parent_killed_outright(tmp_path: Path) -> None:
    """SIGKILL (the OOM killer, a cancelled CI job) gives the parent no time to stop its child:
    the child ends with it, not a minute later by its CPU-time limit."""
    import signal
    import time

    path = _xacro(tmp_path, '  <link name="${9**9**9}"/>\n')
    script = _script(
        tmp_path,
        f"from xrdf_tools.robot.xacro_source import expand_xacro\nexpand_xacro({str(path)!r})\n",
    )
    parent = subprocess.Popen(
        [sys.executable, str(script)], cwd=REPO, env={**os.environ, "PYTHONPATH": str(REPO)}
    )
    try:
        child = _first_child(parent.pid)
    finally:
        parent.kill()
        parent.wait()
    end = time.monotonic() + 5
    while _running(child) and time.monotonic() < end:
        time.sleep(0.05)
    alive = _running(child)
    if alive:
        os.kill(child, signal.SIGKILL)
    assert not alive


def _first_child(pid: int) -> int:
    import time

    end = time.monotonic() + HANG_S
    while time.monotonic() < end:
        found = Path(f"/proc/{pid}/task/{pid}/children").read_text().split()
        if found:
            return int(found[0])
        time.sleep(0.05)
    raise AssertionError("the expansion never started its child")


def _running(pid: int) -> bool:
    """Whether ``pid`` is a live process (a zombie no parent reaps is not)."""
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return False
    return stat.rsplit(")", 1)[1].split()[0] != "Z"
