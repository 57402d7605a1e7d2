"""An integer literal where cuRobo needs a float.

cuRobo accepts only floats for the scalars it broadcasts (buffer distances, radii, default
positions, limits): ``0`` breaks its loader where ``0.0`` works. Write ``1.0``, not ``1``.
Sphere centres and positions are lists converted as a whole and are not reported.
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ...yaml_io import YMap, YNode, YScalar, YSeq
from ..context import LintContext, Problem, Rule


def _is_int(node: YNode | None) -> bool:
    return (
        isinstance(node, YScalar)
        and isinstance(node.value, int)
        and not isinstance(node.value, bool)
    )


def check(ctx: LintContext) -> Iterator[Problem]:
    found: list[tuple[YNode, str]] = []
    for s in ctx.iter_spheres():
        found.append((s.field("radius") or s.node, s.key_path + ".radius"))
    for key, section in ctx.collision_sections():
        buf = section.get("buffer_distance")
        if isinstance(buf, YMap):
            found += [(v, f"{key}.buffer_distance.{k}") for k, v in buf.items()]
        else:
            found.append((buf or section, f"{key}.buffer_distance"))
    for n, _, v in ctx.default_position_nodes():
        found.append((v, f"default_joint_positions.{n}"))
    cs = ctx.get("cspace")
    if isinstance(cs, YMap):
        for key in ("acceleration_limits", "jerk_limits"):
            lst = cs.get(key)
            if isinstance(lst, YSeq):
                found += [(item, f"cspace.{key}[{i}]") for i, item in enumerate(lst.items)]
    for node, kp in found:
        if _is_int(node):
            assert isinstance(node, YScalar)
            yield ctx.problem(
                node,
                f"{kp} is the integer {node.value}; cuRobo needs a float (write {node.value}.0)",
                kp,
            )


RULE = Rule("curobo-integer", Severity.WARNING, check, __doc__ or "")
