"""``acceleration_limits`` or ``jerk_limits`` does not have one value per c-space joint.

The i-th limit applies to the i-th entry of ``cspace.joint_names``; a list that is too short,
too long or empty (with joints present) is invalid.
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ...yaml.io import YMap, YSeq
from ..context import LintContext, Problem, Rule, is_null


def check(ctx: LintContext) -> Iterator[Problem]:
    cs = ctx.get("cspace")
    if not isinstance(cs, YMap):
        return
    names = cs.get("joint_names")
    if isinstance(names, YSeq):
        n = len(names)
    elif is_null(names) and "joint_names" in cs:
        n = 0
    else:
        return
    for key in ("acceleration_limits", "jerk_limits"):
        node = cs.get(key)
        if key not in cs:
            continue
        count = len(node) if isinstance(node, YSeq) else (0 if is_null(node) else None)
        if count is not None and count != n:
            yield ctx.problem(
                node if node is not None else cs,
                f"cspace.{key} has {count} value{'s' if count != 1 else ''} but there "
                f"{'is' if n == 1 else 'are'} {n} c-space joint{'s' if n != 1 else ''}",
                f"cspace.{key}",
            )


RULE = Rule("limits-length", Severity.ERROR, check, __doc__ or "")
