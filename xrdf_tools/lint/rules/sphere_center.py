"""A sphere's ``center`` does not have exactly 3 coordinates.

``center: [x, y, z]`` is the position of the sphere in its frame, in metres.
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ...yaml.io import YSeq
from ..context import LintContext, Problem, Rule


def check(ctx: LintContext) -> Iterator[Problem]:
    for s in ctx.iter_spheres():
        c = s.field("center")
        if isinstance(c, YSeq) and len(c) != 3:
            yield ctx.problem(
                c,
                f"sphere {s.index} on '{s.frame}' (group '{s.group}'): center must have 3 "
                f"coordinates [x, y, z], found {len(c)}",
                s.key_path + ".center",
            )


RULE = Rule("sphere-center", Severity.ERROR, check, __doc__ or "")
