"""With ``--urdf``: a moving joint of the robot cuRobo builds whose axis is not along x, y or z.

cuRobo's kinematics knows rotation about and translation along ±x, ±y and ±z only: its URDF
parser reads a joint as such when one component of ``<axis xyz>`` is exactly 1 or -1, and its
loader raises on any other axis (``0 0.6 0.8``, or ``0 0 0.9999`` from a CAD export) of a
joint on the chains it builds (from the base frame to the tool frames, the sphere frames and
the added frames), a joint held outside the c-space included (the other arm of a two-arm
robot planned one arm at a time). ``xrdf export curobo`` writes the URDF cuRobo needs itself
(beside the config, the same robot: every link frame where it was): an axis a rounding error
away from a coordinate axis (iCub's creo2urdf model writes ``1.0000000000000004``) written
exactly, a tilted one turned onto z of a rotated joint origin, the child hanging from a new
frame-only link. By hand: rotate the joint's ``<origin>`` so that the axis is a coordinate
axis (the child link's frame and its meshes, inertia and collision origins move with it), or
write the axis as exact unit numbers; the message prints such an axis as written, not rounded
to the ``1`` it is not, and gives the exact axis to write.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING

from ...diagnostics import Severity
from ...robot.axes import coordinate_axis_near
from ...yaml.io import YMap, YNode
from ..context import LintContext, Problem, Rule
from ._curobo_tree import curobo_tree_joints, fixed_targets, joints_to_frames, sphere_targets
from ._joints import joint_at

if TYPE_CHECKING:  # numpy: lint without --urdf stays light
    from ...robot.urdf_joints import JointInfo


def check(ctx: LintContext) -> Iterator[Problem]:
    joints = curobo_tree_joints(ctx)
    if not joints or ctx.robot is None:
        return
    for j in joints:
        if any(abs(a) == 1.0 for a in j.axis):
            continue
        axis = " ".join(_number(a) for a in j.axis)
        node, key, held = _where(ctx, j)
        yield ctx.problem(
            node,
            f"joint {joint_at(j, ctx.robot)} of {ctx.robot.file_name}{held} has "
            f'<axis xyz="{axis}">: cuRobo moves joints about or along x, y or z only and its '
            f"loader raises on this one; {_fix(j.axis)}",
            key,
        )


def _number(a: float) -> str:
    """``a`` short (``0.6``), but never rounded to a unit it is not: iCub's
    ``1.0000000000000004`` printed as ``1`` hid why the axis is refused."""
    short = f"{a:g}"
    return repr(a) if abs(float(short)) == 1.0 and abs(a) != 1.0 else short


def _fix(axis: tuple[float, float, float]) -> str:
    """What to do: an axis a rounding error away from a coordinate axis (a CAD export's
    ``1.0000000000000004``) is that axis written exactly; any other needs a rotated origin,
    which ``xrdf export curobo`` writes itself."""
    near = coordinate_axis_near(axis)
    if near is not None:
        k = next(i for i, a in enumerate(near) if a)
        exact = " ".join(f"{a:g}" for a in near)
        return (
            f'it is {"xyz"[k]} but for rounding: write it exactly, <axis xyz="{exact}"> '
            "(cuRobo's parser needs a component that is exactly 1 or -1)"
        )
    return (
        "rotate the joint's origin so that its axis is a coordinate axis (xrdf export curobo "
        "writes such a URDF beside the config)"
    )


def _where(ctx: LintContext, j: JointInfo) -> tuple[YNode | None, str, str]:
    """Where a finding about ``j`` belongs: its node, its key path (the section that brings
    the joint into cuRobo's robot: the c-space, a tool or added frame, or a sphere frame, which
    fitting may add) and, for a joint outside the c-space, why cuRobo builds it."""
    for i, (n, node) in enumerate(ctx.cspace_joint_nodes()):
        if n == (j.mimic_joint or j.name):
            return node, f"cspace.joint_names[{i}]", ""
    fixed = joints_to_frames(ctx, fixed_targets(ctx)) or {}
    if j.name in fixed:
        frame = fixed[j.name][1]
        key, kind = ("modifiers", "added") if frame in ctx.added_frames else ("tool_frames", "tool")
        return (
            ctx.get(key),
            key,
            f", held outside the c-space on the chain to {kind} frame '{frame}',",
        )
    world = ctx.world_key()
    section = ctx.get(world)
    place = (section.get("geometry") if isinstance(section, YMap) else None) or section
    frames = joints_to_frames(ctx, sphere_targets(ctx)) or {}
    frame = f"sphere frame '{frames[j.name][1]}'" if j.name in frames else "a sphere frame"
    return place, f"{world}.geometry", f", held outside the c-space on the chain to {frame},"


RULE = Rule(
    "curobo-joint-axis",
    Severity.WARNING,
    check,
    __doc__ or "",
    needs_urdf=True,
    reader="curobo",
)
