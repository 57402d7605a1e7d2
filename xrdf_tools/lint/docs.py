"""Generate ``docs/rules.md`` from the rule docstrings: ``python -m xrdf_tools.lint.docs``."""

from __future__ import annotations

import inspect
import sys

from . import RULES


def render_rules_md() -> str:
    """The rule reference as Markdown (one section per rule, in registry order)."""
    out = [
        "# `xrdf lint` rules",
        "",
        "Generated from the rule docstrings by `python -m xrdf_tools.lint.docs > docs/rules.md`;",
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
    return "\n".join(out) + "\n"


if __name__ == "__main__":
    sys.stdout.write(render_rules_md())
