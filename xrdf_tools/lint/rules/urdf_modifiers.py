"""With ``--urdf``: the modifiers cannot be applied to the URDF.

``add_frame`` needs an existing parent frame (a URDF link or an earlier added frame) and a frame
and joint name the URDF does not use; ``set_base_frame`` needs an existing frame;
``remove_mimic_attributes`` needs a mimic joint that is still in the tree. The message suggests
the closest existing name. Frame and joint checks of the rest of the file are skipped while
the modifiers fail. An ``add_frame`` whose joint is not FIXED is ``add-frame``'s finding, with or
without a URDF: it is not said twice.
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ...yaml.io import YMap
from ..context import LintContext, Problem, Rule, name, pos


def check(ctx: LintContext) -> Iterator[Problem]:
    err = ctx.modifier_error
    if err is None or (err.line, err.col) in _moving_joint_types(ctx):
        return
    yield Problem(err.line, err.col, err.message)


def _moving_joint_types(ctx: LintContext) -> set[tuple[int | None, int | None]]:
    """Where an add_frame's joint_type is not FIXED (``add-frame`` reports those)."""
    out = set()
    for _, kind, _, v in ctx.modifier_items:
        jt = v.get("joint_type") if kind == "add_frame" and isinstance(v, YMap) else None
        jtn = name(jt)
        if jtn is not None and jtn.lower() != "fixed":
            out.add(pos(jt))
    return out


RULE = Rule("urdf-modifiers", Severity.ERROR, check, __doc__ or "", needs_urdf=True)
