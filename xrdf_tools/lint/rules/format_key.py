"""The document is not an XRDF: it is empty, not a mapping, or lacks ``format: xrdf``.

Every XRDF file (1.0 and 2.0) starts with ``format: xrdf`` and ``format_version``. An XML file
whose text happens to be a YAML string (an SRDF given where the XRDF goes) is named as XML.
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ...yaml.hints import XML_NOT_YAML, looks_like_xml
from ...yaml.io import YScalar, describe_node
from ..context import LintContext, Problem, Rule

#: A URDF or SRDF given to lint: what it is and where it goes.
XML_GIVEN = f"{XML_NOT_YAML}; lint reads XRDF files: give the robot's URDF with --urdf"


def check(ctx: LintContext) -> Iterator[Problem]:
    if ctx.doc is None:
        return
    root = ctx.root
    if root is None:
        yield Problem(1, 1, "the file is empty; an XRDF needs 'format: xrdf' and 'format_version'")
        return
    if isinstance(root, YScalar) and looks_like_xml(root.value):
        yield Problem(1, 1, XML_GIVEN)
        return
    if ctx.top is None:
        yield ctx.problem(root, f"the top level must be a mapping, not {describe_node(root)}")
        return
    fmt = ctx.get("format")
    if not ctx.has("format"):
        yield ctx.problem(ctx.top, "missing required key 'format' (expected 'format: xrdf')")
    elif not (isinstance(fmt, YScalar) and fmt.value == "xrdf"):
        yield ctx.problem(fmt, f"'format' must be 'xrdf', not {describe_node(fmt)}", "format")


RULE = Rule("format-key", Severity.ERROR, check, __doc__ or "")
