"""A scalar ``self_collision.buffer_distance``, which cuRobo's loader cannot take.

cuRobo copies the self-collision buffer as a per-frame map, so a single number there (``0.01``
as much as ``0``) makes its loader raise (``'float' object has no attribute 'copy'``). A scalar
world ``buffer_distance`` is fine when it is a float (see ``curobo-integer``). Write the
self-collision buffer per frame (``xrdf export xrdf`` does).
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ...yaml.io import YMap, YScalar
from ..context import LintContext, Problem, Rule


def check(ctx: LintContext) -> Iterator[Problem]:
    section = ctx.get("self_collision")
    buf = section.get("buffer_distance") if isinstance(section, YMap) else None
    if not isinstance(buf, YScalar):
        return
    if isinstance(buf.value, (int, float)) and not isinstance(buf.value, bool):
        yield ctx.problem(
            buf,
            f"self_collision.buffer_distance is the single number {buf.value}: cuRobo's loader "
            "raises on it (it copies the buffer as a per-frame map); give one per frame",
            "self_collision.buffer_distance",
        )


RULE = Rule("curobo-self-buffer", Severity.WARNING, check, __doc__ or "", reader="curobo")
