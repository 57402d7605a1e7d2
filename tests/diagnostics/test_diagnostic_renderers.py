"""The diagnostics' one table of renderers: every output format of the commands is in it, and
each entry renders the same findings as its renderer."""

from __future__ import annotations

import json

from xrdf_tools.cli.commands.plain import DIAGNOSTIC_RENDERERS, OutputFormat, render_diagnostics
from xrdf_tools.diagnostics import Diagnostic, Severity


def test_every_output_format_has_one_renderer() -> None:
    assert set(DIAGNOSTIC_RENDERERS) == set(OutputFormat)


def test_each_format_renders_the_findings() -> None:
    ds = [Diagnostic("r.xrdf", 3, 5, "sphere-radius", Severity.ERROR, "radius is negative")]
    text = render_diagnostics(ds, OutputFormat.text)
    assert "r.xrdf:3:5" in text and "sphere-radius" in text
    doc = json.loads(render_diagnostics(ds, OutputFormat.json, files=["r.xrdf"]))
    assert doc["files"] == ["r.xrdf"]
    assert "::error file=r.xrdf,line=3,col=5" in render_diagnostics(ds, OutputFormat.github)
    sarif = json.loads(render_diagnostics(ds, OutputFormat.sarif))
    rules = sarif["runs"][0]["tool"]["driver"]["rules"]
    assert [r["id"] for r in rules] == ["sphere-radius"]
