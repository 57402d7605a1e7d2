"""An ``add_frame`` modifier cannot be applied as written.

Only fixed joints are supported (``joint_type: FIXED``, the default); added frame names and
joint names must be unique within the file (and, checked with ``--urdf``, not already used by
the URDF); a frame cannot be its own parent; an orientation quaternion cannot be all zeros
(it is no rotation: a reader normalising it divides by 0).
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ...yaml.io import YMap, YNode, YSeq
from ..context import LintContext, Problem, Rule, name, number


def _quaternion(orientation: YNode | None) -> list[float | None] | None:
    """The four numbers of an orientation written as a quaternion (``{w, xyz}`` or
    ``quaternion: [w, x, y, z]``), None for another form or shape."""
    if not isinstance(orientation, YMap):
        return None
    q = orientation.get("quaternion")
    if isinstance(q, YSeq) and len(q) == 4:
        return [number(item) for item in q]
    xyz = orientation.get("xyz")
    if orientation.get("w") is not None and isinstance(xyz, YSeq) and len(xyz) == 3:
        return [number(orientation.get("w")), *(number(item) for item in xyz)]
    return None


def _zero_quaternion(ctx: LintContext, v: YMap, kp: str) -> Iterator[Problem]:
    ft = v.get("fixed_transform")
    orientation = ft.get("orientation") if isinstance(ft, YMap) else None
    q = _quaternion(orientation)
    if q is not None and all(x == 0 for x in q):
        yield ctx.problem(
            orientation,
            "add_frame orientation is a quaternion of zeros, which is no rotation (a reader "
            "normalising it divides by 0); write {w: 1.0, xyz: [0.0, 0.0, 0.0]} for none",
            kp + ".fixed_transform.orientation",
        )


def check(ctx: LintContext) -> Iterator[Problem]:
    frames: dict[str, int] = {}
    joints: dict[str, int] = {}
    for i, kind, _, v in ctx.modifier_items:
        if kind != "add_frame" or not isinstance(v, YMap):
            continue
        kp = f"modifiers[{i}].add_frame"
        yield from _zero_quaternion(ctx, v, kp)
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
