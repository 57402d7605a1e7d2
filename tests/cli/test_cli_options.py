"""One option table per fast command: the Typer command and the fast start-up path of ``xrdf
lint`` and ``xrdf report`` accept the same options, and ``xrdf report`` without typer prints,
writes and exits exactly as the Typer command does."""

from __future__ import annotations

import io
import sys
from pathlib import Path
from typing import Any

import pytest
import typer.main
from typer.testing import CliRunner

from tests.paths import FIXTURES, UR10E_URDF, UR10E_XRDF
from xrdf_tools.cli import app
from xrdf_tools.cli.commands import lint_core, report_core
from xrdf_tools.cli.commands.options import OptionTable, parse_command_line

TABLES = {
    "lint": (lint_core.LINT_OPTIONS, lint_core.LintArgs),
    "report": (report_core.REPORT_OPTIONS, report_core.ReportArgs),
}


def _typer_options(command: str) -> dict[str, dict[str, Any]]:
    """The options of the Typer command ``command`` as click sees them, by parameter name."""
    cmd = typer.main.get_command(app).commands[command]  # type: ignore[attr-defined]
    out = {}
    for p in cmd.params:
        if p.param_type_name != "option":
            continue
        kind = p.type
        choices = list(getattr(kind, "choices", []) or [])
        out[p.name] = {
            "flags": sorted(p.opts),
            "multiple": p.multiple,
            "flag": p.is_flag,
            "bounds": (getattr(kind, "min", None), getattr(kind, "max", None)),
            "choices": [getattr(c, "value", c) for c in choices],
            "default": p.default,
        }
    return out


def _table_options(table: OptionTable) -> dict[str, dict[str, Any]]:
    out = {}
    for o in table:
        out[o.name] = {
            "flags": sorted(o.flags),
            "multiple": o.multiple,
            "flag": o.is_flag,
            "bounds": o.bounds,
        }
    return out


@pytest.mark.parametrize("command", sorted(TABLES))
def test_the_typer_command_and_the_fast_path_accept_the_same_options(command: str) -> None:
    table, args_type = TABLES[command]
    typer_opts = _typer_options(command)
    mine = _table_options(table)
    assert sorted(typer_opts) == sorted(mine)
    for name, seen in typer_opts.items():
        want = mine[name]
        assert (seen["flags"], seen["multiple"], seen["flag"]) == (
            want["flags"],
            want["multiple"],
            want["flag"],
        ), name
        assert seen["bounds"] == want["bounds"], name
        if seen["choices"]:  # every choice typer offers is read on the fast path
            convert = table[name].convert
            assert convert is not None
            assert [convert(c).value for c in seen["choices"]] == seen["choices"], name
    # the fast path's arguments hold every option but -q/-v, with the Typer command's defaults
    fields = args_type.__dataclass_fields__
    assert set(typer_opts) - {"quiet", "verbose"} <= set(fields)
    import dataclasses

    for name, seen in typer_opts.items():
        default = fields[name].default if name in fields else dataclasses.MISSING
        if default is not dataclasses.MISSING and default is not None:
            assert default == seen["default"], name


@pytest.mark.parametrize("command", sorted(TABLES))
def test_every_spelling_of_every_option_is_read_on_the_fast_path(command: str) -> None:
    table, _ = TABLES[command]
    samples = {"--format": "json", "-f": "json", "--sampler": "halton", "--mask-policy": "proven"}
    samples |= {"--only": "findings", "--output": "o.txt", "-o": "o.txt"}
    for opt in table:
        for flag in opt.flags:
            words = [command, "a.xrdf", "--urdf", "u.urdf"] if flag != "--urdf" else [command]
            if opt.is_flag:
                words.append(flag)
            else:
                words += [flag, samples.get(flag, "1")]
            if flag == "--urdf":
                words.append("a.xrdf")
            line = parse_command_line(table, words, command)
            assert (line is not None) is opt.fast, words


URDF = ["--urdf", str(UR10E_URDF)]
#: Command lines the fast path runs, compared with the Typer command.
CASES: list[list[str]] = [
    ["report", str(UR10E_XRDF), *URDF, "-n", "200", "-j", "1"],
    ["report", str(UR10E_XRDF), *URDF, "-n", "200", "-q", "-f", "json", "--seed", "3"],
    ["report", str(UR10E_XRDF), *URDF, "-n200", "-fgithub", "--strict"],
    ["report", str(UR10E_XRDF), *URDF, "-n", "200", "--format=sarif"],
    ["report", str(UR10E_XRDF), *URDF, "-n", "300", "--only", "pairs", "--min-rate", "0.05"],
    ["report", str(UR10E_XRDF), *URDF, "-n", "200", "--sampler", "halton", "-f", "markdown"],
    ["report", str(UR10E_XRDF), *URDF, "-n", "200", "--write-mask", "-", "-o", "{tmp}/r.html"],
    ["report", str(UR10E_XRDF), *URDF, "-n", "200", "--jobs", "64", "--clearance-margin", "0"],
    ["report", *URDF, "-n", "100", "--", str(UR10E_XRDF)],
    ["report", str(UR10E_XRDF), *URDF, "--plot", "-"],  # exit 2
    ["report", str(UR10E_XRDF), *URDF, "-o", str(UR10E_XRDF)],  # an input: exit 2
    ["report", str(UR10E_XRDF), "--urdf", str(FIXTURES / "no-such.urdf")],  # exit 2
    ["report", str(UR10E_XRDF), *URDF, "--configs", str(FIXTURES / "no-such.csv")],  # exit 2
    ["report", "-", *URDF, "--configs", "-"],  # standard input twice: exit 2
]


@pytest.mark.parametrize("argv", CASES, ids=lambda a: " ".join(Path(w).name for w in a[1:])[:80])
def test_report_on_the_fast_path_prints_and_exits_as_the_typer_command(
    argv: list[str],
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
    runner: CliRunner,
) -> None:
    argv = [w.replace("{tmp}", str(tmp_path)) for w in argv]
    monkeypatch.setattr(sys, "stdin", io.TextIOWrapper(io.BytesIO(b"")))  # as CliRunner's
    assert report_core.parse_fast(argv) is not None, "the fast path should run this command line"
    written = tmp_path / "r.html"
    code = report_core.fast_main(argv)
    fast = capsys.readouterr()
    fast_file = written.read_text() if written.exists() else None
    written.unlink(missing_ok=True)
    r = runner.invoke(app, argv)
    assert r.exception is None or isinstance(r.exception, SystemExit), r.exception
    typer_file = written.read_text() if written.exists() else None
    assert (fast.out, fast.err, code) == (
        r.stdout,
        r.stderr,
        r.exit_code,
    )
    assert fast_file is not None or typer_file is None
    assert (fast_file or "") == (typer_file or "")


@pytest.mark.parametrize(
    "argv",
    [
        ["report", "a.xrdf"],  # no --urdf: typer's usage error
        ["report", "a.xrdf", "b.xrdf", "--urdf", "u.urdf"],
        ["report", "--urdf", "u.urdf"],
        ["report", "a.xrdf", "--urdf", "u.urdf", "--help"],
        ["report", "a.xrdf", "--urdf", "u.urdf", "-v"],  # -v prints typer's timings
        ["report", "a.xrdf", "--urdf", "u.urdf", "-n", "0"],
        ["report", "a.xrdf", "--urdf", "u.urdf", "-n", "1_000"],
        ["report", "a.xrdf", "--urdf", "u.urdf", "-n", "-5"],
        ["report", "a.xrdf", "--urdf", "u.urdf", "--samples", "20000000000"],
        ["report", "a.xrdf", "--urdf", "u.urdf", "--sampler", "HALTON"],
        ["report", "a.xrdf", "--urdf", "u.urdf", "--min-rate", "2"],
        ["report", "a.xrdf", "--urdf", "u.urdf", "--min-rate", "nan"],
        ["report", "a.xrdf", "--urdf", "u.urdf", "--jobs", "0"],
        ["report", "a.xrdf", "--urdf", "u.urdf", "--seed", "1", "--seed", "2"],
        ["report", "a.xrdf", "--urdf", "u.urdf", "--coverage=yes"],
        ["report", "a.xrdf", "--urdf", "u.urdf", "--bogus"],
        ["report", "a.xrdf", "--urdf", ""],
    ],
)
def test_anything_else_is_left_to_typer(argv: list[str]) -> None:
    assert report_core.parse_fast(argv) is None


def test_a_progress_bar_is_left_to_typer(monkeypatch: pytest.MonkeyPatch) -> None:
    """On a terminal the Typer command draws the bar; with -q there is none to draw."""
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True)
    argv = ["report", str(UR10E_XRDF), *URDF, "-n", "100"]
    assert report_core.fast_main(argv) is None


def test_report_runs_with_one_blas_thread_unless_the_user_chose_a_count() -> None:
    from xrdf_tools.cli import BLAS_THREAD_VARS, one_blas_thread_for

    env: dict[str, str] = {}
    one_blas_thread_for(["report", "a.xrdf", "--urdf", "u.urdf"], env)
    assert env == dict.fromkeys(BLAS_THREAD_VARS, "1")
    env = {"OPENBLAS_NUM_THREADS": "4"}
    one_blas_thread_for(["report", "a.xrdf"], env)
    assert env["OPENBLAS_NUM_THREADS"] == "4" and env["OMP_NUM_THREADS"] == "1"
    env = {}
    one_blas_thread_for(["lint", "a.xrdf"], env)
    one_blas_thread_for(["spheres", "r.urdf"], env)
    assert env == {}


def test_the_report_fast_path_imports_no_numpy_before_its_thread_count_is_set() -> None:
    """numpy reads the BLAS thread count when it is imported: the entry point's own imports
    and the option reading must not import it."""
    import subprocess

    code = (
        "import sys\n"
        "import xrdf_tools.cli, xrdf_tools.cli.commands.report_core as r\n"
        "r.parse_fast(['report', 'a.xrdf', '--urdf', 'u.urdf', '-n', '10'])\n"
        "print('numpy' in sys.modules)\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"
