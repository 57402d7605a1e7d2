"""An XRDF 2.0 file: cuRobo and Isaac ROS cuMotion cannot load it as written.

cuRobo (0.7.x and main) and Isaac ROS cuMotion, which loads XRDF through cuRobo's reader, read
only XRDF 1.0. On a 2.0 file they log a warning and read ``collision``, never
``world_collision``: cuRobo's robot loader then raises (KeyError ``'collision_spheres'``), and
code that calls its XRDF converter alone gets a robot with **zero** collision spheres, world
and self collision avoidance silently off. The cuMotion library and Isaac Sim load 2.0 as
written.
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
        f"XRDF 2.0: {readers} read only 1.0; they ignore world_collision, so cuRobo's robot "
        "loader raises (KeyError 'collision_spheres') and its converter alone gives a robot "
        "with NO collision spheres. Write 1.0 for them, or pass --target cumotion / isaac-sim "
        "if those are the readers",
        "format_version",
    )


RULE = Rule("curobo-format-version", Severity.WARNING, check, __doc__ or "", reader="curobo")
