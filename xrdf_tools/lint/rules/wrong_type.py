"""A value has the wrong type or shape.

Sections are mappings (``cspace``, ``world_collision``/``collision``, ``self_collision``,
``geometry``, each group, ``spheres``, ``buffer_distance``, ``ignore``), lists stay lists
(``joint_names``, limits, ``tool_frames``, the spheres of a frame, each frame's ``ignore``
entry, ``clone``, ``modifiers``), names are non-empty strings and numbers are finite numbers.
Positions and ``xyz`` have 3 numbers, quaternions 4, ``position_limits`` 2. Optional values may
be null (``tool_frames:``, ``ignore:``, ``buffer_distance:``, ``clone:``, a frame's spheres).
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ..context import LintContext, Problem, Rule
from ..schema import walk


def check(ctx: LintContext) -> Iterator[Problem]:
    if ctx.top is None:
        return
    for ev in walk(ctx.top):
        if ev.kind == "type":
            yield ctx.problem(ev.node, ev.message, ev.key_path)


RULE = Rule("wrong-type", Severity.ERROR, check, __doc__ or "")
