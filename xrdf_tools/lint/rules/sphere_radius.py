"""A sphere radius is not positive.

XRDF 2.0 requires ``radius > 0`` in every group (referenced or not). XRDF 1.0 keeps such
spheres, and they mean something there (an informational note, not a problem): radius ≤ −1 is a
cuRobo attached-object slot (``extra_collision_spheres``; cuMotion's own ``franka_curobo.xrdf``
has four), and a radius in (−1, 0] becomes a real sphere once buffered (cuRobo makes it at least
1 mm). Converting such a file to 2.0 drops them and says so.
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
            meaning = (
                "an attached-object slot (cuRobo fills it when an object is attached)"
                if r <= -1
                else "a sphere that 1.0 readers make real once buffered"
            )
            yield ctx.problem(
                rnode,
                f"{where} has radius {r:g}: {meaning}; XRDF 2.0 cannot express it",
                s.key_path + ".radius",
                Severity.INFO,
            )
        else:
            yield ctx.problem(
                rnode, f"{where} has radius {r:g}; radius must be > 0", s.key_path + ".radius"
            )


RULE = Rule("sphere-radius", Severity.ERROR, check, __doc__ or "")
