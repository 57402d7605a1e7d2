"""A scalar ``buffer_distance`` written as an integer, which cuRobo cannot broadcast.

cuRobo broadcasts a scalar buffer to every link only when it is a Python float: ``0`` breaks
its loader where ``0.0`` works. Per-frame buffers (a map) and numbers inside lists (centres,
radii, limits, default positions) are converted fine and are not reported.
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ...yaml.io import YScalar
from ..context import LintContext, Problem, Rule


def check(ctx: LintContext) -> Iterator[Problem]:
    for key, section in ctx.collision_sections():
        buf = section.get("buffer_distance")
        if (
            isinstance(buf, YScalar)
            and isinstance(buf.value, int)
            and not isinstance(buf.value, bool)
        ):
            kp = f"{key}.buffer_distance"
            yield ctx.problem(
                buf,
                f"{kp} is the integer {buf.value}; cuRobo broadcasts only a float here (write "
                f"{buf.value}.0)",
                kp,
            )


RULE = Rule("curobo-integer", Severity.WARNING, check, __doc__ or "", reader="curobo")
