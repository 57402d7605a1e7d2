"""A required key is missing.

``cspace`` with ``joint_names``, ``acceleration_limits`` and ``jerk_limits``; ``geometry`` in
each collision section; ``center`` and ``radius`` in each sphere; ``frame_name``,
``parent_frame_name``, ``joint_name`` and ``fixed_transform.position`` in ``add_frame``;
``joint_name`` in ``remove_mimic_attributes``.

A document that holds nothing but geometry (groups and collision sections, no modifiers,
defaults, tool frames) is a geometry fragment: its missing ``cspace`` is reported as info only,
because such files are loaded by geometry-level tools (cuMotion's own clone tests are written
this way). A robot description always needs ``cspace``.
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ..context import LintContext, Problem, Rule
from ..schema import walk

GEOMETRY_ONLY_KEYS = {
    "format",
    "format_version",
    "geometry",
    "collision",
    "world_collision",
    "self_collision",
}

#: Missing keys that another rule reports in its own words: (key path of the mapping, key).
OWNED_ELSEWHERE = {("", "format"), ("", "format_version")}


def check(ctx: LintContext) -> Iterator[Problem]:
    top = ctx.top
    if top is None:
        return
    if "cspace" not in top:
        keys = set(top.keys())
        if "geometry" in keys and keys <= GEOMETRY_ONLY_KEYS:
            yield ctx.problem(
                top,
                "no 'cspace': read as a geometry-only fragment; a robot description needs "
                "cspace (joint_names, acceleration_limits, jerk_limits)",
                severity=Severity.INFO,
            )
        else:
            yield ctx.problem(
                top,
                "missing required key 'cspace' (joint_names, acceleration_limits, jerk_limits)",
            )
    for ev in walk(top):
        if ev.kind == "missing" and (ev.key_path, ev.key) not in OWNED_ELSEWHERE:
            yield ctx.problem(ev.node, ev.message, ev.key_path)


RULE = Rule("required-key", Severity.ERROR, check, __doc__ or "")
