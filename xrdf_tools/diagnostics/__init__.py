"""One diagnostic type for lint findings, conversion fallbacks and report findings.

Renderers turn a list of diagnostics into text, JSON, GitHub annotations or SARIF 2.1.0. They
return strings; only the CLI prints them.
"""

from __future__ import annotations

import functools
import re
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from enum import Enum
from pathlib import Path, PurePath
from typing import Any
from urllib.parse import quote

from ..util.errors import one_line


class Severity(str, Enum):
    """How bad a finding is. Ordered: error > warning > info."""

    ERROR = "error"
    WARNING = "warning"
    INFO = "info"

    @property
    def rank(self) -> int:
        return {"error": 2, "warning": 1, "info": 0}[self.value]


@functools.total_ordering
@dataclass(frozen=True)
class Diagnostic:
    """A finding about an input file.

    Sorts by file, line, column, rule, message (:func:`sort_key`; no position sorts first).
    ``line``/``col`` are 1-based and ``None`` when the finding has no position (e.g. a value
    that was not in the input at all). ``key_path`` is the dotted path of the YAML node
    (``self_collision.ignore.panda_link1``).
    """

    path: str
    line: int | None
    col: int | None
    rule: str
    severity: Severity = field(compare=False)
    message: str = field(compare=False)
    key_path: str = field(default="", compare=False)

    def __lt__(self, other: object) -> bool:
        if not isinstance(other, Diagnostic):
            return NotImplemented
        return sort_key(self) < sort_key(other)

    def location(self) -> str:
        parts: list[str] = [self.path or "<input>"]
        if self.line is not None:
            parts.append(str(self.line))
            if self.col is not None:
                parts.append(str(self.col))
        return ":".join(parts)

    def to_dict(self) -> dict[str, Any]:
        return {
            "path": self.path,
            "line": self.line,
            "col": self.col,
            "rule": self.rule,
            "severity": self.severity.value,
            "message": self.message,
            "key_path": self.key_path,
        }


@dataclass(frozen=True)
class RuleInfo:
    """One diagnostic id: its default severity, a one-line summary and the command that emits
    it. The one rule record: a lint rule carries one (``xrdf_tools.lint.Rule.info``), the
    report's findings and every other command's notes are declared as one, the registry
    (:mod:`xrdf_tools.rules.registry`) collects them and SARIF describes its rules with them."""

    id: str
    severity: Severity
    summary: str
    producer: str


def sort_key(d: Diagnostic) -> tuple[str, int, int, str, str]:
    return (d.path, d.line or 0, d.col or 0, d.rule, d.message)


def count_by_severity(diagnostics: Iterable[Diagnostic]) -> dict[str, int]:
    counts = {s.value: 0 for s in Severity}
    for d in diagnostics:
        counts[d.severity.value] += 1
    return counts


def render_text(diagnostics: Sequence[Diagnostic]) -> str:
    """``path:line:col: severity rule-id message`` one per line."""
    return "".join(
        one_line(f"{d.location()}: {d.severity.value} {d.rule} {d.message}") + "\n"
        for d in sorted(diagnostics, key=sort_key)
    )


JSON_SCHEMA_VERSION = 1


def render_json(diagnostics: Sequence[Diagnostic], **extra: Any) -> str:
    """Stable JSON: ``{"version": 1, "diagnostics": [...], "summary": {...}}``.

    See ``docs/json-output.md`` for the schema.
    """
    ordered = sorted(diagnostics, key=sort_key)
    doc: dict[str, Any] = {
        "version": JSON_SCHEMA_VERSION,
        "diagnostics": [d.to_dict() for d in ordered],
        "summary": count_by_severity(ordered),
    }
    doc.update(extra)
    import json  # here: text output, the usual one, does without it

    return json.dumps(doc, indent=2, sort_keys=False) + "\n"


def _gh_escape(value: str, *, prop: bool = False) -> str:
    value = value.replace("%", "%25").replace("\r", "%0D").replace("\n", "%0A")
    if prop:
        value = value.replace(":", "%3A").replace(",", "%2C")
    return value


def render_github(diagnostics: Sequence[Diagnostic]) -> str:
    """GitHub Actions workflow commands (``::error file=…,line=…,col=…,title=…::message``)."""
    level = {Severity.ERROR: "error", Severity.WARNING: "warning", Severity.INFO: "notice"}
    out = []
    for d in sorted(diagnostics, key=sort_key):
        props = [f"file={_gh_escape(d.path, prop=True)}"]
        if d.line is not None:
            props.append(f"line={d.line}")
        if d.col is not None:
            props.append(f"col={d.col}")
        props.append(f"title={_gh_escape(d.rule, prop=True)}")
        out.append(f"::{level[d.severity]} {','.join(props)}::{_gh_escape(d.message)}\n")
    return "".join(out)


def artifact_uri(path: str) -> str | None:
    """``path`` as a SARIF artifact URI: a relative path percent-encoded (code scanning
    resolves it against the checkout), an absolute one as a ``file://`` URI, and ``None`` for
    a stream or other pseudo-path (``<stdin>``), which has no artifact."""
    if not path or (path.startswith("<") and path.endswith(">")):
        return None
    p = PurePath(path)
    if p.is_absolute():
        return Path(path).as_uri()
    return quote(p.as_posix(), safe="/")


#: A reStructuredText literal in a rule summary: ````format: xrdf````.
_RST_LITERAL = re.compile(r"``(.+?)``")


def sarif_description(summary: str) -> dict[str, str]:
    """A rule summary as a SARIF multiformat message: plain ``text`` (an RST literal
    ````x```` in quotes, as code scanning shows text verbatim) and, when it has literals,
    ``markdown`` with them as code."""
    text = _RST_LITERAL.sub(r"'\1'", summary)
    if text == summary:
        return {"text": summary}
    return {"text": text, "markdown": _RST_LITERAL.sub(r"`\1`", summary)}


def sarif_region(d: Diagnostic) -> dict[str, int]:
    """Where ``d`` is, as a SARIF region. Code scanning shows a result only with a
    ``startLine``: a finding about a whole file (no line) is placed on its first line."""
    if d.line is None:
        return {"startLine": 1}
    if d.col is None:
        return {"startLine": d.line}
    return {"startLine": d.line, "startColumn": d.col}


def render_sarif(
    diagnostics: Sequence[Diagnostic],
    rules: Sequence[RuleInfo] = (),
    *,
    tool_name: str = "xrdf",
    version: str = "",
    information_uri: str = "",
) -> str:
    """SARIF 2.1.0 log with one run. ``rules`` are described first, by their summary and
    default severity (the CLI passes the registry's, :mod:`xrdf_tools.rules.registry`); an
    emitted id missing from them is described by its id and the finding's severity."""
    level = {Severity.ERROR: "error", Severity.WARNING: "warning", Severity.INFO: "note"}
    rule_ids = [r.id for r in rules]
    descr = {r.id: (r.summary, r.severity) for r in rules}
    for d in diagnostics:
        if d.rule not in rule_ids:
            rule_ids.append(d.rule)
            descr[d.rule] = (d.rule, d.severity)
    driver: dict[str, Any] = {
        "name": tool_name,
        "version": version,
        "rules": [
            {
                "id": rid,
                "shortDescription": sarif_description(descr.get(rid, (rid, Severity.WARNING))[0]),
                "defaultConfiguration": {
                    "level": level[descr.get(rid, (rid, Severity.WARNING))[1]]
                },
            }
            for rid in rule_ids
        ],
    }
    if information_uri:
        driver["informationUri"] = information_uri
    results = []
    for d in sorted(diagnostics, key=sort_key):
        result: dict[str, Any] = {
            "ruleId": d.rule,
            "ruleIndex": rule_ids.index(d.rule),
            "level": level[d.severity],
            "message": {"text": d.message},
        }
        uri = artifact_uri(d.path)
        if uri is not None:
            location = {"artifactLocation": {"uri": uri}, "region": sarif_region(d)}
            result["locations"] = [{"physicalLocation": location}]
        results.append(result)
    log = {
        "$schema": "https://json.schemastore.org/sarif-2.1.0.json",
        "version": "2.1.0",
        "runs": [{"tool": {"driver": driver}, "results": results}],
    }
    import json

    return json.dumps(log, indent=2) + "\n"
