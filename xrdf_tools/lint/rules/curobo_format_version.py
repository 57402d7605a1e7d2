"""An XRDF 2.0 file: cuRobo and Isaac ROS cuMotion load it with no collision spheres.

cuRobo (0.7.x and main) and Isaac ROS cuMotion, which loads XRDF through cuRobo's reader, read
only XRDF 1.0. On a 2.0 file they log a warning and read ``collision``, never
``world_collision``: the robot loads with **zero** collision spheres and both world and self
collision avoidance are silently off. The cuMotion library and Isaac Sim load 2.0 as written.
Write 1.0 for cuRobo (``xrdf convert`` does by default), or lint with ``--target cumotion`` or
``--target isaac-sim`` when those are the readers.
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ...xrdf.readers import dropping_readers
from ..context import LintContext, Problem, Rule


def check(ctx: LintContext) -> Iterator[Problem]:
    if ctx.version != "2.0":
        return
    readers = " and ".join(t.label for t in dropping_readers("2.0"))
    yield ctx.problem(
        ctx.get("format_version"),
        f"XRDF 2.0: {readers} read only 1.0; they ignore world_collision and load this robot "
        "with NO collision spheres (collision avoidance disabled). Write 1.0 for them, or pass "
        "--target cumotion / isaac-sim if those are the readers",
        "format_version",
    )


RULE = Rule("curobo-format-version", Severity.WARNING, check, __doc__ or "", reader="curobo")
