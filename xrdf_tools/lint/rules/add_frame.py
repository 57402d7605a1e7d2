"""An ``add_frame`` modifier cannot be applied as written.

Only fixed joints are supported (``joint_type: FIXED``, the default); added frame names and
joint names must be unique within the file (and, checked with ``--urdf``, not already used by
the URDF); a frame cannot be its own parent.
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ...yaml.io import YMap
from ..context import LintContext, Problem, Rule, name


def check(ctx: LintContext) -> Iterator[Problem]:
    frames: dict[str, int] = {}
    joints: dict[str, int] = {}
    for i, kind, _, v in ctx.modifier_items:
        if kind != "add_frame" or not isinstance(v, YMap):
            continue
        kp = f"modifiers[{i}].add_frame"
        jt = v.get("joint_type")
        jtn = name(jt)
        if jtn is not None and jtn.lower() != "fixed":
            yield ctx.problem(
                jt, f"add_frame joint_type must be FIXED, not '{jtn}'", kp + ".joint_type"
            )
        fnode, jnode = v.get("frame_name"), v.get("joint_name")
        f, j, p = name(fnode), name(jnode), name(v.get("parent_frame_name"))
        if f is not None:
            if f in frames:
                yield ctx.problem(
                    fnode,
                    f"frame '{f}' is already added by modifiers[{frames[f]}]; frame names must "
                    "be unique",
                    kp + ".frame_name",
                )
            else:
                frames[f] = i
            if f == p:
                yield ctx.problem(
                    fnode, f"frame '{f}' cannot be its own parent", kp + ".parent_frame_name"
                )
        if j is not None:
            if j in joints:
                yield ctx.problem(
                    jnode,
                    f"joint '{j}' is already used by modifiers[{joints[j]}]; joint names must "
                    "be unique",
                    kp + ".joint_name",
                )
            else:
                joints[j] = i


RULE = Rule("add-frame", Severity.ERROR, check, __doc__ or "")
