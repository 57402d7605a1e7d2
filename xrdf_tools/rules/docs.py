"""Generate ``docs/rules.md`` from the rule docstrings and the registry of every other
diagnostic id: ``python -m xrdf_tools.rules.docs``."""

from __future__ import annotations

import inspect
import sys

from ..lint import RULES


def render_rules_md() -> str:
    """The rule reference as Markdown (one section per rule, in registry order)."""
    out = [
        "# `xrdf lint` rules",
        "",
        "Generated from the rule docstrings by `python -m xrdf_tools.rules.docs > docs/rules.md`;",
        "a test fails when this file is stale. Change a level or turn a rule off in the",
        "configuration (see [lint.md](lint.md)).",
        "",
        "| rule | default | needs `--urdf` | summary |",
        "|---|---|---|---|",
    ]
    for r in RULES:
        out.append(
            f"| [`{r.id}`](#{r.id}) | {r.severity.value} | {'yes' if r.needs_urdf else ''} | "
            f"{r.summary} |"
        )
    for r in RULES:
        out += [
            "",
            f"## {r.id}",
            "",
            f"Default severity: **{r.severity.value}**"
            + (" · runs only with `--urdf`" if r.needs_urdf else ""),
            "",
        ]
        out.append(inspect.cleandoc(r.doc))
        out.append("")
        out.append(f"Fixtures: `fixtures/lint/{r.id}/`.")
    out += _other_diagnostics()
    return "\n".join(out) + "\n"


def _other_diagnostics() -> list[str]:
    """The ids that other commands emit (report findings, conversion notes, ...)."""
    from .registry import all_rules

    out = [
        "",
        "# Diagnostics of the other commands",
        "",
        "`xrdf convert`, `export`, `report`, `spheres` and `viz` report with the same diagnostic",
        "format (`path:line:col: severity id message`, and JSON, GitHub, SARIF). Their ids:",
        "",
        "| id | default | emitted by | summary |",
        "|---|---|---|---|",
    ]
    for info in all_rules().values():
        if info.producer != "lint":
            out.append(
                f"| `{info.id}` | {info.severity.value} | {info.producer} | {info.summary} |"
            )
    return out


if __name__ == "__main__":
    sys.stdout.write(render_rules_md())
