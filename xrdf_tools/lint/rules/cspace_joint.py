"""With ``--urdf``: a c-space joint does not exist, is fixed, is a mimic follower, or was
removed by ``set_base_frame``.

C-space coordinates are the URDF's revolute, continuous and prismatic joints that are not
mimics (unless ``remove_mimic_attributes`` releases them) and lie below the base frame.
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ..context import LintContext, Problem, Rule
from ._joints import joint_problem


def check(ctx: LintContext) -> Iterator[Problem]:
    if ctx.kin is None:
        return
    for i, (n, node) in enumerate(ctx.cspace_joint_nodes()):
        msg = joint_problem(ctx, n, "c-space joint")
        if msg:
            yield ctx.problem(node, msg, f"cspace.joint_names[{i}]")


RULE = Rule("cspace-joint", Severity.ERROR, check, __doc__ or "", needs_urdf=True)
