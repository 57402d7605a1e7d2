"""Without ``--urdf``: a buffer or ignore entry names a frame that no part of the file defines.

Without a URDF the linter cannot know the robot's links, but a ``buffer_distance`` or
``ignore`` entry for a frame that has no spheres in the section's geometry group and is not
added by ``add_frame`` is often a typo (cuRobo's own UR10e config masks ``forarm_link``). Reported
as info with the closest frame the file does know; pass ``--urdf`` (or map the file to its URDF in
the config) to turn this into a real check (``unknown-frame``).
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ...util.errors import did_you_mean
from ...yaml.io import YMap, YSeq
from ..context import LintContext, Problem, Rule, name


def check(ctx: LintContext) -> Iterator[Problem]:
    if ctx.has_urdf:
        return
    all_frames = {r.frame for r in ctx.iter_spheres()} | set(ctx.added_frames)
    for key, section in ctx.collision_sections():
        g = ctx.group_name(section)
        frames = ctx.sphere_frames(g) if g is not None else None
        if frames is None:
            continue
        known = frames | set(ctx.added_frames)
        entries = []
        buf = section.get("buffer_distance")
        if isinstance(buf, YMap):
            entries += [(k, f"{key}.buffer_distance") for k, _ in buf.pairs]
        ignore = section.get("ignore") if key == "self_collision" else None
        if isinstance(ignore, YMap):
            for k, v in ignore.pairs:
                entries.append((k, "self_collision.ignore"))
                if isinstance(v, YSeq):
                    entries += [(item, "self_collision.ignore") for item in v.items]
        for node, where in entries:
            n = name(node)
            if n is None or n in known:
                continue
            hint = (
                "; it has spheres only in other groups"
                if n in all_frames
                else did_you_mean(n, sorted(all_frames))
            )
            yield ctx.problem(
                node,
                f"{where} names frame '{n}', which has no spheres in group '{g}' and is not "
                f"added by add_frame{hint}; lint with --urdf to check it exists",
                f"{where}.{n}",
            )


RULE = Rule("undefined-frame", Severity.INFO, check, __doc__ or "")
