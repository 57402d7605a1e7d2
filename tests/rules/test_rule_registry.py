"""One registry of every diagnostic id: each id the code emits is registered and documented,
and SARIF logs describe emitted rules from it."""

from __future__ import annotations

import ast
import re
from pathlib import Path

from typer.testing import CliRunner

from tests.diagnostics.test_sarif_schema import check_sarif
from tests.paths import FIXTURES, REPO, UR10E_URDF
from xrdf_tools.cli import app
from xrdf_tools.diagnostics import sarif_description
from xrdf_tools.rules.registry import all_rules

PACKAGE = REPO / "xrdf_tools"
RULE_ID = re.compile(r"^[a-z][a-z0-9]*(-[a-z0-9]+)+$")
#: Kebab-case strings in calls that are not diagnostic ids.
NOT_IDS = {"utf-8", "isaac-sim", "rerun-sdk", "xrdf-tools", "xrdf-*"}


def _emitted_ids() -> dict[str, str]:
    """Kebab-case string constants passed to calls or bound to ``RULE_*`` names, and the
    constant prefixes of f-string ids (``f"convert-default-{kind}"``) -> where."""
    found: dict[str, str] = {}
    for path in PACKAGE.rglob("*.py"):
        if "diff" in path.relative_to(PACKAGE).parts[0]:
            continue  # xrdf diff's change kinds are not diagnostics
        tree = ast.parse(path.read_text())
        for node in ast.walk(tree):
            values: list[ast.expr] = []
            if isinstance(node, ast.Call):
                values = [*node.args, *(k.value for k in node.keywords)]
            elif isinstance(node, ast.Assign) and any(
                isinstance(t, ast.Name) and t.id.startswith("RULE_") for t in node.targets
            ):
                values = [node.value]
            for v in values:
                where = f"{path.relative_to(REPO)}:{v.lineno}"
                if isinstance(v, ast.Constant) and isinstance(v.value, str):
                    if RULE_ID.match(v.value) and v.value not in NOT_IDS:
                        found[v.value] = where
                elif isinstance(v, ast.JoinedStr) and v.values:
                    head = v.values[0]
                    prefix = str(head.value) if isinstance(head, ast.Constant) else ""
                    if re.match(r"^[a-z]+(-[a-z]+)*-$", prefix) and prefix + "*" not in NOT_IDS:
                        found[prefix + "*"] = where
    return found


def test_every_emitted_id_is_registered() -> None:
    registered = set(all_rules())
    emitted = _emitted_ids()
    assert len(emitted) > 60  # the scan sees the code
    missing = {
        i: w
        for i, w in emitted.items()
        if (i.endswith("*") and not any(r.startswith(i[:-1]) for r in registered))
        or (not i.endswith("*") and i not in registered)
    }
    assert missing == {}


def test_every_registered_id_is_documented() -> None:
    doc = (REPO / "docs" / "rules.md").read_text()
    undocumented = [i for i in all_rules() if f"`{i}`" not in doc]
    assert undocumented == []


def test_convert_sarif_describes_its_rules_from_the_registry(
    runner: CliRunner, tmp_path: Path
) -> None:
    r = runner.invoke(
        app,
        [
            "convert",
            str(UR10E_URDF),
            "--curobo",
            str(FIXTURES / "curobo_classic" / "ur10e_inline.yml"),
            "--format",
            "sarif",
            "-o",
            str(tmp_path / "x.xrdf"),
        ],
    )
    assert r.exit_code == 0, r.output
    sarif = r.output[r.output.index("{") :]
    log = check_sarif(sarif)  # valid against the OASIS schema
    driver = log["runs"][0]["tool"]["driver"]
    assert driver["name"] == "xrdf"
    rules = {x["id"]: x for x in driver["rules"]}
    registry = all_rules()
    level = {"error": "error", "warning": "warning", "info": "note"}
    for rid, rule in rules.items():
        info = registry[rid]
        assert rule["shortDescription"] == sarif_description(info.summary)
        assert "``" not in rule["shortDescription"]["text"]  # no RST shown verbatim
        assert rule["defaultConfiguration"]["level"] == level[info.severity.value]
    assert "convert-unknown-link" in rules and "convert-default-jerk" in rules


def test_lint_report_and_the_registry_share_one_rule_record() -> None:
    from xrdf_tools.diagnostics import RuleInfo
    from xrdf_tools.lint import RULES as LINT_RULES
    from xrdf_tools.report import RULES as REPORT_RULES

    registry = all_rules()
    assert all(type(info) is RuleInfo for info in registry.values())
    for rule in LINT_RULES:
        assert registry[rule.id] == rule.info
        assert (rule.info.producer, rule.info.severity) == ("lint", rule.severity)
    for info in REPORT_RULES:
        assert registry[info.id] is info and info.producer == "report"
