"""With ``--urdf``: the modifiers cannot be applied to the URDF.

``add_frame`` needs an existing parent frame (a URDF link or an earlier added frame) and a frame
and joint name the URDF does not use; ``set_base_frame`` needs an existing frame;
``remove_mimic_attributes`` needs a mimic joint that is still in the tree. The message suggests
the closest existing name. Frame and joint checks of the rest of the file are skipped while
the modifiers fail.
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ..context import LintContext, Problem, Rule


def check(ctx: LintContext) -> Iterator[Problem]:
    err = ctx.modifier_error
    if err is None:
        return
    yield Problem(err.line, err.col, err.message)


RULE = Rule("urdf-modifiers", Severity.ERROR, check, __doc__ or "", needs_urdf=True)
