"""With ``--urdf``: a frame the file refers to does not exist after the modifiers are applied.

Sphere frames, ``buffer_distance`` and ``ignore`` entries and ``tool_frames`` must name a URDF
link or a frame added with ``add_frame``, and must not have been cut off by
``set_base_frame``. The message suggests the closest existing frame.
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ...util.errors import did_you_mean
from ..context import LintContext, Problem, Rule


def check(ctx: LintContext) -> Iterator[Problem]:
    kin = ctx.kin
    if kin is None or ctx.robot is None:
        return
    frames = set(kin.frame_names)
    pruned = set(kin.pruned_frames)
    fname = ctx.robot.file_name
    for frame, node, kp, what in ctx.frame_references():
        if frame in frames:
            continue
        if frame in pruned:
            msg = (
                f"{what} '{frame}' was removed by set_base_frame '{kin.base_frame}' (it is not "
                "below the new base)"
            )
        else:
            msg = f"{what} '{frame}' is not a frame of {fname}" + did_you_mean(
                frame, kin.frame_names
            )
        yield ctx.problem(node, msg, kp)


RULE = Rule("unknown-frame", Severity.ERROR, check, __doc__ or "", needs_urdf=True)
