"""``format_version`` is missing or names a version that does not exist.

Supported versions are ``1.0`` (the published XRDF specification) and ``2.0`` (cuMotion 1.1:
``world_collision``, ``clone``, ``remove_mimic_attributes``). Write the version unquoted.
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ...xrdf.shape import SUPPORTED_VERSIONS, version_string
from ...yaml.io import describe_node
from ..context import LintContext, Problem, Rule


def check(ctx: LintContext) -> Iterator[Problem]:
    if ctx.top is None:
        return
    node = ctx.get("format_version")
    if not ctx.has("format_version"):
        yield ctx.problem(ctx.top, "missing required key 'format_version' (1.0 or 2.0)")
    elif version_string(node) not in SUPPORTED_VERSIONS:
        yield ctx.problem(
            node,
            f"unsupported format_version {describe_node(node)}; supported: "
            + ", ".join(SUPPORTED_VERSIONS),
            "format_version",
        )


RULE = Rule("format-version", Severity.ERROR, check, __doc__ or "")
