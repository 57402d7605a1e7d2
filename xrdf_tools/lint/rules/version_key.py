"""A key that exists in only one XRDF version is used in the other, or both spellings of the
world-collision section are present.

* 1.0 spells the world-collision section ``collision``; 2.0 spells it ``world_collision`` and
  rejects ``collision``. A file may not contain both.
* ``clone`` (geometry groups built from other groups) and the ``remove_mimic_attributes``
  modifier exist only in 2.0.

Fix: change ``format_version``, or rename the key (``xrdf export xrdf FILE --format-version
2.0`` does it).
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ...xrdf.shape import DOCUMENT, GROUP, MODIFIERS, exists_in
from ...yaml.io import YMap
from ..context import LintContext, Problem, Rule


def check(ctx: LintContext) -> Iterator[Problem]:
    top = ctx.top
    if top is None or ctx.version is None:
        return
    v = ctx.version
    if "collision" in top and "world_collision" in top:
        yield ctx.problem(
            top.key_node("world_collision" if v == "1.0" else "collision"),
            "both 'collision' and 'world_collision' are present; XRDF "
            f"{v} uses '{ctx.world_key()}' only",
        )
    elif "collision" in top and not exists_in(DOCUMENT, "collision", v):
        yield ctx.problem(
            top.key_node("collision"),
            "'collision' is the XRDF 1.0 spelling; format_version 2.0 requires 'world_collision'",
            "collision",
        )
    elif "world_collision" in top and not exists_in(DOCUMENT, "world_collision", v):
        yield ctx.problem(
            top.key_node("world_collision"),
            "'world_collision' is XRDF 2.0; format_version 1.0 spells it 'collision'",
            "world_collision",
        )
    for gname, gnode in ctx.groups.items():
        if isinstance(gnode, YMap) and "clone" in gnode and not exists_in(GROUP, "clone", v):
            yield ctx.problem(
                gnode.key_node("clone"),
                f"geometry group '{gname}' uses 'clone', which XRDF 1.0 does not have; list the "
                "spheres in the group or use format_version 2.0",
                f"geometry.{gname}.clone",
            )
    for i, kind, knode, _ in ctx.modifier_items:
        sub = MODIFIERS.get(kind)
        if sub is not None and sub.versions and v not in sub.versions:
            yield ctx.problem(
                knode,
                f"modifier '{kind}' is XRDF {' and '.join(sub.versions)} only",
                f"modifiers[{i}]",
            )


RULE = Rule("version-key", Severity.ERROR, check, __doc__ or "")
