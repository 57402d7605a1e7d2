"""A sphere radius is not positive.

XRDF 2.0 requires ``radius > 0`` in every group (referenced or not). In XRDF 1.0 files, cuRobo
uses negative radii as placeholders for disabled spheres (e.g. ``attached_object``) and skips
them; those are reported as warnings in 1.0 files, and a zero radius too. ``xrdf convert --to
2.0`` drops them.
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ..context import LintContext, Problem, Rule, finite_number


def check(ctx: LintContext) -> Iterator[Problem]:
    if ctx.version is None:
        return
    for s in ctx.iter_spheres():
        rnode = s.field("radius")
        r = finite_number(rnode)
        if r is None or r > 0:
            continue
        where = f"sphere {s.index} on '{s.frame}' (group '{s.group}')"
        if ctx.version == "1.0":
            yield ctx.problem(
                rnode,
                f"{where} has radius {r:g}: a disabled placeholder that cuRobo skips; XRDF 2.0 "
                "rejects it",
                s.key_path + ".radius",
                Severity.WARNING,
            )
        else:
            yield ctx.problem(
                rnode, f"{where} has radius {r:g}; radius must be > 0", s.key_path + ".radius"
            )


RULE = Rule("sphere-radius", Severity.ERROR, check, __doc__ or "")
