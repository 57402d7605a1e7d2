"""A sphere's radius plus its frame's ``buffer_distance`` is not positive.

Each collision section adds its per-frame buffer to the radius of every sphere of that frame
in the group it uses (clones resolved). Negative buffers are allowed, but the buffered radius
must stay > 0 (cuMotion rejects it otherwise). Spheres with a non-positive radius of their own
are left to ``sphere-radius``.
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ...yaml.io import YMap
from ..context import LintContext, Problem, Rule, length_number, name


def check(ctx: LintContext) -> Iterator[Problem]:
    for key, section in ctx.collision_sections():
        buf = section.get("buffer_distance")
        g = ctx.group_name(section)
        if not isinstance(buf, YMap) or g is None:
            continue
        spheres = ctx.resolved_spheres(g)
        if spheres is None:
            continue
        buffers = {
            n: (b, v)
            for k, v in buf.pairs
            if (n := name(k)) and (b := length_number(v)) is not None
        }
        for s in spheres:
            r = length_number(s.field("radius"))
            if r is None or r <= 0 or s.frame not in buffers:
                continue
            b, bnode = buffers[s.frame]
            if r + b <= 0:
                yield ctx.problem(
                    bnode,
                    f"{key} buffer {b:g} on '{s.frame}' makes sphere {s.index} (radius {r:g}, "
                    f"group '{s.group}', line {s.node.line}) {r + b:g} ≤ 0; the buffered radius "
                    "must be > 0",
                    f"{key}.buffer_distance.{s.frame}",
                )


RULE = Rule("buffered-radius", Severity.ERROR, check, __doc__ or "")
