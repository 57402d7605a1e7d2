"""A collision section's geometry group holds no sphere: nothing of the robot is checked.

The readers collide the robot's spheres only, so a group without any (``spheres: {}``, or
only frames with empty lists) loads without error and plans straight through obstacles and
through the robot itself. It is what a conversion writes when no link had collision geometry
to fit (``xrdf convert --fit-spheres --from visual`` fits the visual meshes instead). Spheres
with a negative radius (cuRobo's slots for attached objects) are no robot geometry.

A warning by default; an error for a planning reader (``--target curobo`` or
``--target cumotion``).
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ...yaml.io import YMap
from ..context import LintContext, Problem, Rule, finite_number
from .mesh_without_spheres import PLANNING_TARGETS


def check(ctx: LintContext) -> Iterator[Problem]:
    severity = Severity.ERROR if ctx.target in PLANNING_TARGETS else Severity.WARNING
    said: set[str] = set()
    for key, section in ctx.collision_sections():
        group = ctx.group_name(section)
        closure = ctx.clone_closure(group) if group is not None else None
        if group is None or closure is None or group in said:
            continue  # no group, or an undefined one: other rules say so
        if any(_has_sphere(ctx, g) for g in closure):
            continue
        said.add(group)
        yield ctx.problem(
            section.get("geometry"),
            f"geometry group '{group}' ({key}) holds no collision sphere: the reader checks "
            "no collision for this robot",
            f"{key}.geometry",
            severity,
        )


def _has_sphere(ctx: LintContext, group: str) -> bool:
    """Whether ``group`` lists a sphere that is no negative-radius slot (a group whose
    ``spheres`` is not a mapping is another rule's finding, not this one's)."""
    node = ctx.groups[group]
    if not isinstance(node, YMap) or not isinstance(node.get("spheres"), YMap):
        return True
    for s in ctx.iter_spheres(group):
        r = finite_number(s.field("radius"))
        if r is None or r >= 0:
            return True
    return False


RULE = Rule("empty-collision-group", Severity.WARNING, check, __doc__ or "")
