"""Without ``--urdf``: a buffer or ignore entry names a frame that no part of the file defines.

Without a URDF the linter cannot know the robot's links, but a ``buffer_distance`` or
``ignore`` entry for a frame that has no spheres in the section's geometry group and is not
added by ``add_frame`` is often a typo (cuRobo's own UR10e config masks ``forarm_link``). Reported
as info with the closest frame the file does know; pass ``--urdf`` (or map the file to its URDF in
the config) to turn this into a real check (``unknown-frame``).

Each frame is reported once, at its first entry, with the number of entries that name it. When
the group holds no spheres at all (an XRDF converted from an SRDF without ``--fit-spheres``)
every entry's frame is undefined and none is a typo to point at: one finding says so
(``empty-collision-group`` is the problem there).
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ...util.errors import did_you_mean
from ...util.text import name_list
from ...yaml.io import YMap, YNode, YSeq
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
        if not frames:
            yield from _group_without_spheres(ctx, g, entries, known)
            continue
        named: dict[str, list[tuple[YNode, str]]] = {}
        for node, where in entries:
            n = name(node)
            if n is not None and n not in known:
                named.setdefault(n, []).append((node, where))
        for n, uses in named.items():
            node, where = uses[0]
            hint = (
                "; it has spheres only in other groups"
                if n in all_frames
                else did_you_mean(n, sorted(all_frames))
            )
            times = f" (and in {len(uses) - 1} more entries)" if len(uses) > 1 else ""
            yield ctx.problem(
                node,
                f"{where} names frame '{n}'{times}, which has no spheres in group '{g}' and is "
                f"not added by add_frame{hint}; lint with --urdf to check it exists",
                f"{where}.{n}",
            )


def _group_without_spheres(
    ctx: LintContext, group: str | None, entries: list[tuple[YNode, str]], known: set[str]
) -> Iterator[Problem]:
    """One finding for the entries of a section whose group holds no spheres (none when they
    all name frames the file adds)."""
    first = [(n, node, where) for node, where in entries if (n := name(node)) and n not in known]
    names = list(dict.fromkeys(n for n, _, _ in first))
    if not names:
        return
    _, node, where = first[0]
    yield ctx.problem(
        node,
        f"group '{group}' holds no spheres, so the {len(names)} frame(s) its buffer and ignore "
        f"entries name ({name_list(names, 5)}) cannot be checked without the URDF; lint with "
        "--urdf to check they exist",
        where,
    )


RULE = Rule("undefined-frame", Severity.INFO, check, __doc__ or "")
