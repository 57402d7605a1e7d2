"""The fast start-up path of ``xrdf lint`` (issue 13): it reads only command lines it reads
exactly as typer does, and then prints, exits and fails exactly as the Typer command does."""

from __future__ import annotations

import io
import re
import subprocess
import sys
from pathlib import Path

import pytest
from typer.testing import CliRunner

from tests.paths import FIXTURES, REPO, SEED_XRDF, UR10E_URDF, UR10E_XRDF
from xrdf_tools.cli import app
from xrdf_tools.cli.commands.lint_core import LintArgs, fast_main, parse_fast
from xrdf_tools.cli.commands.plain import OutputFormat

LINT = FIXTURES / "lint"
URDF_LINE = re.compile(r"^# urdf: (.+)$", re.M)


def _with_urdf() -> list[list[str]]:
    """Every lint fixture that names its URDF, linted against it."""
    out = []
    for x in sorted(LINT.glob("*/*.xrdf")):
        m = URDF_LINE.search(x.read_text())
        if m:
            out.append(["lint", str(x), "--urdf", str((x.parent / m.group(1)).resolve())])
    return out


#: Command lines the fast path runs, compared with the Typer command.
CASES: list[list[str]] = [
    ["lint", str(SEED_XRDF)],
    ["lint", str(UR10E_XRDF), "--urdf", str(UR10E_URDF)],
    ["lint", *map(str, sorted(LINT.glob("*/fail*.xrdf")))],
    ["lint", *map(str, sorted(LINT.glob("*/pass*.xrdf"))), "--strict"],
    ["lint", "--format", "json", str(SEED_XRDF), str(UR10E_XRDF)],
    ["lint", "--format=sarif", "--target", "cumotion", str(LINT / "sphere-radius" / "fail.xrdf")],
    ["lint", "-fgithub", str(LINT / "sphere-radius" / "fail.xrdf")],
    ["lint", "-qf", "json", str(LINT / "curobo-integer" / "fail.xrdf"), "--strict"],
    ["lint", "--select", "curobo-,sphere-radius", "--ignore=curobo-integer", str(SEED_XRDF)],
    ["lint", "--target", "curobo", "--", str(SEED_XRDF)],
    ["lint", "--target", "no-such-reader", str(SEED_XRDF)],  # exit 2
    ["lint", "--select", "no-such-rule", str(SEED_XRDF)],  # exit 2
    ["lint", str(FIXTURES / "no-such-file.xrdf")],  # exit 2
    ["lint", "-", "-"],  # standard input twice: exit 2
    ["lint", str(SEED_XRDF), "--xacro-arg", "a:=1"],  # without --urdf: exit 2
    ["lint", str(SEED_XRDF), "--urdf", str(FIXTURES / "no-such.urdf")],  # exit 2
    ["lint", str(SEED_XRDF), "--config", str(FIXTURES / "no-such.yaml")],  # exit 2
    *_with_urdf(),
]


@pytest.mark.parametrize("argv", CASES, ids=lambda a: " ".join(Path(w).name for w in a[1:])[:80])
def test_the_fast_path_prints_and_exits_as_the_typer_command(
    runner: CliRunner, argv: list[str], capsys: pytest.CaptureFixture[str]
) -> None:
    assert parse_fast(argv) is not None, "the fast path should run this command line"
    code = fast_main(argv)
    fast = capsys.readouterr()
    r = runner.invoke(app, argv)
    assert r.exception is None or isinstance(r.exception, SystemExit), r.exception
    assert (fast.out, fast.err, code) == (r.stdout, r.stderr, r.exit_code)


def test_standard_input_on_the_fast_path(
    runner: CliRunner, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    data = SEED_XRDF.read_bytes()
    monkeypatch.setattr(sys, "stdin", io.TextIOWrapper(io.BytesIO(data)))
    code = fast_main(["lint", "-", "--format", "json"])
    fast = capsys.readouterr()
    r = runner.invoke(app, ["lint", "-", "--format", "json"], input=data)
    assert (fast.out, fast.err, code) == (r.stdout, r.stderr, r.exit_code)
    assert '"<stdin>"' in fast.out


def test_the_arguments_are_read_as_typer_reads_them() -> None:
    args = parse_fast(
        ["lint", "a.xrdf", "-qfjson", "--select=x", "--select", "y", "--", "-", "--strict"]
    )
    assert args == LintArgs(
        files=[Path("a.xrdf"), Path("-"), Path("--strict")],
        output_format=OutputFormat.json,
        select=["x", "y"],
    )
    args = parse_fast(["lint", "--urdf", "-", "--config=c.yaml", "b.xrdf", "--strict"])
    assert args == LintArgs(
        files=[Path("b.xrdf")], urdf=Path("-"), config=Path("c.yaml"), strict=True
    )


@pytest.mark.parametrize(
    "argv",
    [
        [],
        ["--version"],
        ["convert", "robot.urdf"],
        ["lint"],  # no FILES: typer's usage error
        ["lint", "--help"],
        ["lint", "a.xrdf", "--help"],
        ["lint", "-v", "a.xrdf"],  # -v prints typer's timings
        ["lint", "-qv", "a.xrdf"],
        ["lint", "-h", "a.xrdf"],
        ["lint", "--verbose", "a.xrdf"],
        ["lint", "--bogus", "a.xrdf"],
        ["lint", "a.xrdf", "--format", "yaml"],
        ["lint", "a.xrdf", "--format", "JSON"],
        ["lint", "a.xrdf", "--urdf"],
        ["lint", "a.xrdf", "-f"],
        ["lint", "a.xrdf", "--urdf", "r.urdf", "--urdf", "s.urdf"],
        ["lint", "a.xrdf", "--urdf="],
        ["lint", "a.xrdf", "--strict=yes"],
        ["lint", "a.xrdf", ""],
        ["lint", "--", ""],
    ],
)
def test_anything_else_is_left_to_typer(argv: list[str]) -> None:
    assert parse_fast(argv) is None


def test_the_fast_path_knows_the_options_of_the_typer_command() -> None:
    """Every option of ``xrdf lint`` but ``-v`` is read on the fast path, with the name, the
    repetition and the field of the Typer command: renaming or adding one there without
    here fails this test (until then the fast path would leave the new spelling to typer)."""
    import typer.main

    from xrdf_tools.cli.commands import lint_core

    command = typer.main.get_command(app).commands["lint"]  # type: ignore[attr-defined]
    typer_opts = {}
    for p in command.params:
        if p.param_type_name == "option" and p.name != "verbose":
            for opt in p.opts:
                typer_opts[opt] = (p.name, p.multiple, p.is_flag)
    fast_opts = {}
    for long, (name, repeatable) in lint_core._VALUED.items():
        fast_opts[long] = (name, repeatable, False)
    for long, name in lint_core._FLAGS.items():
        fast_opts[long] = (name or "quiet", False, True)
    for short, long in lint_core._SHORT.items():
        fast_opts[short] = fast_opts[long]
    assert fast_opts == typer_opts
    assert set(LintArgs.__dataclass_fields__) == {p.name for p in command.params} - {
        "quiet",
        "verbose",
    }


def test_shell_completion_is_left_to_typer(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("_XRDF_COMPLETE", "bash_complete")
    assert parse_fast(["lint", "a.xrdf"]) is None


def _entry(*args: str, **kwargs: object) -> subprocess.CompletedProcess[str]:
    code = "import sys; from xrdf_tools.cli import main; sys.argv[0] = 'xrdf'; main()"
    return subprocess.run(
        [sys.executable, "-c", code, *args],
        cwd=REPO,
        capture_output=True,
        text=True,
        check=False,
        **kwargs,  # type: ignore[call-overload]
    )


def test_the_entry_point_falls_back_to_typer_for_help_and_usage_errors() -> None:
    help_ = _entry("lint", "--help")
    assert help_.returncode == 0 and help_.stdout.startswith("Usage: xrdf lint [OPTIONS]")
    assert "--urdf" in help_.stdout and "--strict" in help_.stdout
    bad = _entry("lint", "--bogus", str(SEED_XRDF))
    assert bad.returncode == 2 and "No such option: --bogus" in bad.stderr


def test_a_closed_standard_output_is_one_line_in_the_fast_path() -> None:
    code = (
        "import os, sys\n"
        "r, w = os.pipe(); os.close(r); os.dup2(w, 1)\n"  # a reader that has gone away
        "from xrdf_tools.cli import main\n"
        f"sys.argv = ['xrdf', 'lint', {str(LINT / 'sphere-radius' / 'fail.xrdf')!r}]\n"
        "main()\n"
    )
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=REPO)
    assert (r.returncode, r.stderr) == (2, "error: standard output: cannot write: Broken pipe\n")
