"""With ``--urdf``: the URDF is not a valid robot, so no reader can load the XRDF with it.

A URDF that parses but does not describe one kinematic tree — a mimic joint naming a missing
joint, mimic joints that loop, several links without a parent joint (and no
``set_base_frame`` choosing one part), malformed XML or numbers — is rejected by every reader.
It is a finding of the XRDF under test (exit 1). A URDF that cannot be read at all (missing
file, no permission) is a usage error (exit 2). URDF-bound checks are skipped.
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ..context import LintContext, Problem, Rule


def check(ctx: LintContext) -> Iterator[Problem]:
    err = ctx.urdf_error
    if err is None:
        return
    yield ctx.problem(None, f"the URDF is not a valid robot: {err}")


RULE = Rule("urdf-invalid", Severity.ERROR, check, __doc__ or "", needs_urdf=True)
