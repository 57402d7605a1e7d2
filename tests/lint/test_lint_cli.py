"""`xrdf lint` end to end: formats, exit codes, selection, configuration, real files."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest
from typer.testing import CliRunner

from tests.paths import FIXTURES, SEED_XRDF, UR10E_URDF, UR10E_XRDF, shared_file, shared_xrdfs
from tests.robots import robot_urdf
from xrdf_tools.cli import app
from xrdf_tools.lint import lint, lint_text

BAD = FIXTURES / "lint" / "sphere-radius" / "fail.xrdf"  # 2.0: one error at 35:19
WARN = FIXTURES / "lint" / "curobo-integer" / "fail.xrdf"  # one warning at 16:20


def test_text_output_and_exit_1_on_error(runner: CliRunner) -> None:
    r = runner.invoke(app, ["lint", str(BAD)])
    assert r.exit_code == 1
    # sorted by position: the 2.0 reader warning on format_version, then the error
    first, second = r.output.splitlines()
    assert first.startswith(f"{BAD}:2:17: warning curobo-format-version XRDF 2.0: cuRobo and ")
    assert second.startswith(f"{BAD}:35:19: error sphere-radius ")


def test_warnings_pass_unless_strict(runner: CliRunner) -> None:
    assert runner.invoke(app, ["lint", str(WARN)]).exit_code == 0
    r = runner.invoke(app, ["lint", "--strict", str(WARN)])
    assert r.exit_code == 1 and ":16:20: warning curobo-integer " in r.output


def test_json_schema(runner: CliRunner) -> None:
    r = runner.invoke(
        app, ["lint", "-f", "json", "--target", "cumotion", str(BAD), str(UR10E_XRDF)]
    )
    doc = json.loads(r.output)
    assert doc["version"] == 1 and doc["files"] == [str(BAD), str(UR10E_XRDF)]
    assert doc["summary"] == {"error": 1, "warning": 0, "info": 0}
    (d,) = doc["diagnostics"]
    assert d == {
        "path": str(BAD),
        "line": 35,
        "col": 19,
        "rule": "sphere-radius",
        "severity": "error",
        "message": d["message"],
        "key_path": "geometry.arm_spheres.spheres.upper_arm_link[0].radius",
    }


def test_github_and_sarif(runner: CliRunner) -> None:
    r = runner.invoke(app, ["lint", "-f", "github", "--target", "isaac-sim", str(BAD)])
    assert r.output.startswith(f"::error file={BAD},line=35,col=19,title=sphere-radius::")
    r = runner.invoke(app, ["lint", "-f", "sarif", "--target", "cumotion", str(BAD)])
    log = json.loads(r.output)
    assert log["version"] == "2.1.0"
    run = log["runs"][0]
    rules = {x["id"]: x for x in run["tool"]["driver"]["rules"]}
    assert "radius" in rules["sphere-radius"]["shortDescription"]["text"]
    (res,) = run["results"]
    assert res["ruleId"] == "sphere-radius" and res["level"] == "error"
    assert run["tool"]["driver"]["rules"][res["ruleIndex"]]["id"] == "sphere-radius"
    assert res["locations"][0]["physicalLocation"]["region"] == {"startLine": 35, "startColumn": 19}


def test_select_and_ignore(runner: CliRunner) -> None:
    assert runner.invoke(app, ["lint", "--ignore", "sphere-radius", str(BAD)]).exit_code == 0
    r = runner.invoke(app, ["lint", "--select", "curobo-", "--strict", str(BAD)])
    assert r.exit_code == 1 and r.output.count("\n") == 1 and "curobo-format-version" in r.output
    r = runner.invoke(
        app, ["lint", "--select", "curobo-", "--strict", "--target", "cumotion", str(BAD)]
    )
    assert r.exit_code == 0 and r.output == ""
    r = runner.invoke(app, ["lint", "--select", "sphere-radiu", str(BAD)])
    assert r.exit_code == 2 and "did you mean 'sphere-radius'" in r.output


def test_usage_errors_exit_2(runner: CliRunner, tmp_path: Path) -> None:
    assert runner.invoke(app, ["lint", str(tmp_path / "missing.xrdf")]).exit_code == 2
    r = runner.invoke(app, ["lint", str(UR10E_XRDF), "--urdf", str(tmp_path / "no.urdf")])
    assert r.exit_code == 2 and "Traceback" not in r.output


def test_syntax_errors_and_duplicates_are_findings_not_crashes(
    runner: CliRunner, tmp_path: Path
) -> None:
    f = tmp_path / "x.xrdf"
    f.write_text("format: xrdf\nformat: xrdf\nformat_version: 2.0\ncspace: [\n")
    r = runner.invoke(app, ["lint", str(f)])
    assert r.exit_code == 1 and "yaml-syntax" in r.output and "Traceback" not in r.output
    f.write_text("format: xrdf\nformat: xrdf\nformat_version: 2.0\n")
    assert f"{f}:2:1: error duplicate-key" in runner.invoke(app, ["lint", str(f)]).output


def test_config_changes_levels_and_maps_urdf(
    runner: CliRunner, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    (tmp_path / "robot").mkdir()
    x = tmp_path / "robot" / "arm.xrdf"
    x.write_text(
        (FIXTURES / "lint" / "unknown-frame" / "fail.xrdf").read_text().split("# urdf")[0]
        + (FIXTURES / "lint" / "unknown-frame" / "fail.xrdf").read_text().split("\n", 1)[1]
    )
    (tmp_path / "robot" / "arm.urdf").write_text(UR10E_URDF.read_text())
    monkeypatch.chdir(tmp_path)
    # no config: only the info-level hint, exit 0
    r = runner.invoke(app, ["lint", "robot/arm.xrdf"])
    assert r.exit_code == 0 and "info undefined-frame" in r.output
    (tmp_path / ".xrdf-lint.yaml").write_text(
        'rules:\n  undefined-frame: error\nurdf:\n  "robot/*.xrdf": robot/arm.urdf\n'
    )
    r = runner.invoke(app, ["lint", "robot/arm.xrdf"])
    assert r.exit_code == 1 and "error unknown-frame" in r.output
    assert "did you mean 'forearm_link'" in r.output and "undefined-frame" not in r.output
    (tmp_path / ".xrdf-lint.yaml").unlink()
    (tmp_path / "pyproject.toml").write_text(
        '[tool.xrdf.lint]\nrules = { "undefined-frame" = "error", "curobo-" = "off" }\n'
    )
    r = runner.invoke(app, ["lint", "robot/arm.xrdf"])
    assert r.exit_code == 1 and "error undefined-frame" in r.output
    bad = tmp_path / "bad.yaml"
    bad.write_text("rules:\n  no-such-rule: off\n")
    r = runner.invoke(app, ["lint", "--config", str(bad), "robot/arm.xrdf"])
    assert r.exit_code == 2 and "unknown rule 'no-such-rule'" in r.output


def test_bundled_and_shared_examples_have_no_errors() -> None:
    files = [UR10E_XRDF, SEED_XRDF, FIXTURES / "panda" / "panda.xrdf", *shared_xrdfs()]
    errors = [d for d in lint(files) if d.severity.value == "error"]
    assert errors == []


def test_seed_and_ur10e_against_the_urdf() -> None:
    diags = lint([UR10E_XRDF, SEED_XRDF], urdf=UR10E_URDF)
    assert [d for d in diags if d.severity.value == "error"] == []
    # the seed's tool0 placeholder sphere is flagged, and every frame it names exists
    assert any(d.rule == "sphere-radius" and d.path == str(SEED_XRDF) for d in diags)
    assert not any(d.rule == "unknown-frame" for d in diags)


def test_shared_reference_against_its_urdf() -> None:
    x = shared_file("reference", "curobo-2.0", "ur10e.xrdf")
    u = shared_file("reference", "curobo-2.0", "ur10e.urdf")
    assert [d for d in lint([x], urdf=u) if d.severity.value == "error"] == []


def test_panda_against_example_robot_data() -> None:
    diags = lint([FIXTURES / "panda" / "panda.xrdf"], urdf=robot_urdf("panda"))
    assert [d for d in diags if d.severity.value == "error"] == []


def test_lint_with_urdf_reads_and_parses_the_urdf_once(
    runner: CliRunner, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Issue 15: ``xrdf lint FILE --urdf URDF`` reads the URDF file once and parses and
    validates it once, whatever its rules look at (joints, frames, collision geometry)."""
    import xrdf_tools.robot.urdf_source as urdf_source
    import xrdf_tools.util.fileio as fileio
    from xrdf_tools.lint.rules import sphere_outside_geometry

    urdf = robot_urdf("panda")
    reads: list[str] = []
    parses: list[str] = []
    read_capped, parse_bytes = fileio._read_capped, urdf_source._parse_bytes

    def counting_read(fh: Any, path: str, *args: Any) -> bytes:
        reads.append(path)
        return read_capped(fh, path, *args)

    def counting_parse(data: bytes, path: str, **kwargs: Any) -> Any:
        parses.append(path)
        return parse_bytes(data, path, **kwargs)

    monkeypatch.setattr(fileio, "_read_capped", counting_read)
    monkeypatch.setattr(urdf_source, "_parse_bytes", counting_parse)
    # no boxes kept from an earlier test: the collision geometry is loaded in this run
    monkeypatch.setattr(sphere_outside_geometry, "_CACHE", {})
    xrdf = FIXTURES / "panda" / "panda.xrdf"
    r = runner.invoke(app, ["lint", str(xrdf), "--urdf", str(urdf), "--target", "cumotion"])
    assert r.exit_code == 0, r.output
    assert sphere_outside_geometry._CACHE, "the collision geometry was not looked at"
    assert parses == [str(urdf)]
    assert [p for p in reads if p == str(urdf)] == [str(urdf)]


def test_a_crashing_rule_becomes_an_internal_error() -> None:
    from xrdf_tools.diagnostics import Severity
    from xrdf_tools.lint.context import Rule

    def boom(ctx: object) -> object:
        raise RuntimeError("bug")

    out = lint_text(UR10E_XRDF.read_text(), rules=(Rule("boom", Severity.INFO, boom, "x"),))  # type: ignore[arg-type]
    assert [(d.rule, d.severity.value) for d in out] == [("internal-error", "error")]


#: Never imported by ``xrdf lint FILE`` (no ``--urdf``): URDF, mesh and plotting libraries, and
#: the XRDF model with its strict reader and writer (lint reads the YAML tree; issue 13).
HEAVY = (
    "trimesh",
    "yourdfpy",
    "rerun",
    "mcap",
    "matplotlib",
    "lxml",
    "numpy",
    "xrdf_tools.diff",
    "xrdf_tools.xrdf.model",
    "xrdf_tools.xrdf.read",
    "xrdf_tools.xrdf.write",
)
#: Not imported either by the console entry point, which runs ``xrdf lint`` without typer.
TYPER_AND_WRITERS = ("typer", "pydantic", "rich", "tempfile", "difflib", "json", "zipfile")

_RUNS = {
    "typer-app": (
        "from xrdf_tools.cli import app\n"
        "from typer.testing import CliRunner\n"
        f"r = CliRunner().invoke(app, ['lint', {str(SEED_XRDF)!r}])\n"
        "assert r.exit_code == 0, r.output\n"
    ),
    "entry-point": (
        "from xrdf_tools.cli import main\n"
        f"sys.argv = ['xrdf', 'lint', {str(SEED_XRDF)!r}]\n"
        "try:\n"
        "    main()\n"
        "except SystemExit as e:\n"
        "    assert e.code == 0, e.code\n"
    ),
}


@pytest.mark.parametrize("run", sorted(_RUNS))
def test_lint_without_urdf_imports_no_heavy_library(run: str) -> None:
    banned = HEAVY + (TYPER_AND_WRITERS if run == "entry-point" else ())
    code = (
        "import sys\n"
        + _RUNS[run]
        + f"print(','.join(m for m in {banned!r} if m in sys.modules), file=sys.stderr)\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stderr.strip() == "", f"imported: {out.stderr}"


def test_the_cli_repeats_the_diff_tolerance_it_does_not_import() -> None:
    from xrdf_tools.cli.commands.diff import DEFAULT_TOLERANCE as cli_default
    from xrdf_tools.diff import DEFAULT_TOLERANCE

    assert cli_default == DEFAULT_TOLERANCE


_IGNORES = """format: xrdf
format_version: 1.0
cspace:
  joint_names: [j1]
  acceleration_limits: [10.0]
  jerk_limits: [1000.0]
collision:
  geometry: g
self_collision:
  geometry: g
  ignore:
    base: [upper, forarm, wrist]
    upper: [forarm, wrist]
    forarm: [wrist]
geometry:
  g:
    spheres:
{spheres}
"""


def test_undefined_frames_are_one_finding_each_and_one_for_a_group_without_spheres(
    runner: CliRunner, tmp_path: Path
) -> None:
    """An XRDF converted from an SRDF without --fit-spheres has ignore pairs and no spheres:
    `xrdf lint` without --urdf said undefined-frame for every name of every entry (Baxter: 250
    lines). A frame is now said once, with its count, and an empty group once."""
    f = tmp_path / "arm.xrdf"
    sphere = "        - center: [0.0, 0.0, 0.0]\n          radius: 0.05\n"
    f.write_text(
        _IGNORES.format(
            spheres="".join(f"      {n}:\n{sphere}" for n in ("base", "upper", "forearm"))
        )
    )
    r = runner.invoke(app, ["lint", str(f), "--format", "json"])
    found = [d for d in json.loads(r.stdout)["diagnostics"] if d["rule"] == "undefined-frame"]
    assert [(d["line"], d["message"]) for d in found] == [
        (
            12,
            "self_collision.ignore names frame 'forarm' (and in 2 more entries), which has no "
            "spheres in group 'g' and is not added by add_frame; did you mean 'forearm'?; lint "
            "with --urdf to check it exists",
        ),
        (
            12,
            "self_collision.ignore names frame 'wrist' (and in 2 more entries), which has no "
            "spheres in group 'g' and is not added by add_frame; lint with --urdf to check it "
            "exists",
        ),
    ]
    f.write_text(
        _IGNORES.format(spheres="      {}").replace("    spheres:\n      {}", "    spheres: {}")
    )
    r = runner.invoke(app, ["lint", str(f), "--format", "json"])
    found = [d for d in json.loads(r.stdout)["diagnostics"] if d["rule"] == "undefined-frame"]
    assert [(d["line"], d["col"], d["message"]) for d in found] == [
        (
            12,
            5,
            "group 'g' holds no spheres, so the 4 frame(s) its buffer and ignore entries name "
            "(base, upper, forarm, wrist) cannot be checked without the URDF; lint with --urdf "
            "to check they exist",
        )
    ]


@pytest.mark.parametrize("name", ["demo_arm.urdf", "demo_arm.srdf"])
def test_a_urdf_given_to_lint_is_named_and_sent_to_urdf(runner: CliRunner, name: str) -> None:
    """`xrdf lint robot.urdf` (the URDF where the XRDF goes) said 'YAML syntax error: mapping
    values are not allowed here' at some line inside, or for the SRDF 'the top level must be
    a mapping, not the string '<?xml ...''; it says what the file is and where it goes."""
    path = FIXTURES / "demo_arm" / name
    r = runner.invoke(app, ["lint", str(path)])
    assert r.exit_code == 1
    assert r.output.endswith(
        ":1:1: error yaml-syntax an XML document (a URDF, xacro or SRDF?), not YAML; lint "
        "reads XRDF files: give the robot's URDF with --urdf\n"
    ) or r.output.endswith(
        ":1:1: error format-key an XML document (a URDF, xacro or SRDF?), not YAML; lint "
        "reads XRDF files: give the robot's URDF with --urdf\n"
    ), r.output
    assert len(r.output.splitlines()) == 1


def test_verbose_lint_says_what_it_checked_also_when_it_found_nothing(
    runner: CliRunner, tmp_path: Path
) -> None:
    """A clean lint printed nothing even with -v (only timings): a user could not tell a
    pass from a run that read no file. -v now counts the files and the findings by kind;
    without -v a clean lint stays silent, as a pre-commit hook should."""
    clean = tmp_path / "clean.xrdf"
    clean.write_text(UR10E_XRDF.read_text())  # a 2.0 file: clean for cuMotion
    quiet = runner.invoke(app, ["lint", str(clean), "--target", "cumotion"])
    assert quiet.exit_code == 0 and quiet.stdout == "" and quiet.stderr == "", quiet.output
    r = runner.invoke(app, ["lint", str(clean), "--target", "cumotion", "-v"])
    assert r.exit_code == 0 and "1 file(s) checked: 0 error(s), 0 warning(s)" in r.stderr
    r = runner.invoke(app, ["lint", str(UR10E_XRDF), str(SEED_XRDF), "-v", "-f", "json"])
    found = json.loads(r.stdout)["diagnostics"]
    errors = sum(d["severity"] == "error" for d in found)
    assert f"2 file(s) checked: {errors} error(s)" in r.stderr, r.stderr
