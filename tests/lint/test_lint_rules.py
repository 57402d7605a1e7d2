"""Every rule: registered, documented, with passing and failing fixtures that behave as written.

A fixture is ``fixtures/lint/<rule-id>/{pass,fail}*.xrdf``. Failing fixtures end with
``# expect: LINE:COL SEVERITY`` lines: exactly those findings of that rule must be reported.
Passing fixtures must produce no finding of their rule. ``# urdf: PATH`` (relative to the
fixture) lints against that URDF; ``# target: READER`` lints for that reader.
"""

from __future__ import annotations

import pkgutil
import re
from pathlib import Path

import pytest

from tests.paths import FIXTURES, REPO
from xrdf_tools.lint import RULES, lint_text, rules
from xrdf_tools.rules.docs import render_rules_md

LINT_FIXTURES = FIXTURES / "lint"
EXPECT = re.compile(r"^# expect: (\d+):(\d+) (error|warning|info)$", re.M)
URDF = re.compile(r"^# urdf: (.+)$", re.M)
TARGET = re.compile(r"^# target: (.+)$", re.M)


def _fixtures() -> list[Path]:
    return sorted(LINT_FIXTURES.glob("*/*.xrdf"))


def test_every_rule_module_is_registered_once() -> None:
    modules = {m.name for m in pkgutil.iter_modules(rules.__path__) if not m.name.startswith("_")}
    registered = [r.id.replace("-", "_") for r in RULES]
    assert sorted(registered) == sorted(modules)
    assert len(set(registered)) == len(registered)


@pytest.mark.parametrize("rule", RULES, ids=lambda r: r.id)
def test_rule_is_documented_and_has_both_fixtures(rule: object) -> None:
    from xrdf_tools.lint.context import Rule

    assert isinstance(rule, Rule)
    assert re.fullmatch(r"[a-z0-9]+(-[a-z0-9]+)*", rule.id)
    assert len(rule.doc.strip()) > 40, f"{rule.id} has no real docstring"
    d = LINT_FIXTURES / rule.id
    assert list(d.glob("pass*.xrdf")), f"{rule.id} lacks a passing fixture"
    fails = list(d.glob("fail*.xrdf"))
    assert fails, f"{rule.id} lacks a failing fixture"
    assert any(EXPECT.search(f.read_text()) for f in fails)


def test_fixture_dirs_name_registered_rules() -> None:
    ids = {r.id for r in RULES}
    assert {p.name for p in LINT_FIXTURES.iterdir() if p.is_dir()} <= ids


@pytest.mark.parametrize("path", _fixtures(), ids=lambda p: f"{p.parent.name}/{p.name}")
def test_fixture(path: Path) -> None:
    rule = path.parent.name
    text = path.read_text()
    m = URDF.search(text)
    urdf = (path.parent / m.group(1)).resolve() if m else None
    t = TARGET.search(text)
    found = sorted(
        (d.line, d.col, d.severity.value)
        for d in lint_text(text, str(path), urdf=urdf, target=t.group(1) if t else None)
        if d.rule == rule
    )
    expected = sorted((int(a), int(b), s) for a, b, s in EXPECT.findall(text))
    if path.name.startswith("pass"):
        assert not expected
    else:
        assert expected, "a failing fixture must list its expected findings"
    assert found == expected


def test_rules_md_is_up_to_date() -> None:
    doc = REPO / "docs" / "rules.md"
    assert doc.read_text() == render_rules_md(), (
        "docs/rules.md is stale: run python -m xrdf_tools.rules.docs > docs/rules.md"
    )
    for r in RULES:
        assert f"## {r.id}\n" in doc.read_text()
