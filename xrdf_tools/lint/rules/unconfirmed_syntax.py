"""A construct whose meaning no published file or loader confirms.

Each of these is accepted by the linter but may be read differently (or rejected) by cuMotion:

* ``geometry: [group]`` (a one-item list instead of the group name) in a collision section;
* ``orientation: {quaternion: [w, x, y, z]}`` or ``{euler_rpy: [r, p, y]}`` in ``add_frame``
  (seen in one unreliable test file; ``{w: …, xyz: […]}`` is the confirmed form);
* ``velocity_limit`` (singular) in ``remove_mimic_attributes`` (``velocity_limits`` is
  confirmed);
* a single number as ``buffer_distance`` in XRDF 2.0 (cuRobo's 1.0 loader broadcasts it; write a
  per-frame map);
* ``ignore: []`` (cuRobo's writer emits it; 2.0 expects a mapping or null).
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ...yaml.io import YMap, YSeq
from ..context import LintContext, Problem, Rule, number


def check(ctx: LintContext) -> Iterator[Problem]:
    for key, section in ctx.collision_sections():
        g = section.get("geometry")
        if isinstance(g, YSeq) and len(g) == 1:
            yield ctx.problem(
                g,
                f"{key}.geometry is a one-item list; write the group name itself",
                f"{key}.geometry",
            )
        buf = section.get("buffer_distance")
        if ctx.version == "2.0" and number(buf) is not None:
            yield ctx.problem(
                buf,
                f"{key}.buffer_distance is a single number; XRDF 2.0 expects a per-frame map",
                f"{key}.buffer_distance",
            )
        ignore = section.get("ignore") if key == "self_collision" else None
        if isinstance(ignore, YSeq) and len(ignore) == 0:
            yield ctx.problem(
                ignore,
                "'ignore: []' is a list; leave it empty (null) or write a mapping",
                "self_collision.ignore",
            )
    for i, kind, _, v in ctx.modifier_items:
        if not isinstance(v, YMap):
            continue
        if kind == "add_frame":
            ft = v.get("fixed_transform")
            o = ft.get("orientation") if isinstance(ft, YMap) else None
            if isinstance(o, YMap):
                for form in ("quaternion", "euler_rpy"):
                    if form in o:
                        yield ctx.problem(
                            o.key_node(form),
                            f"orientation form '{form}' is unconfirmed; cuMotion's confirmed "
                            "form is {w: …, xyz: [x, y, z]}",
                            f"modifiers[{i}].add_frame.fixed_transform.orientation.{form}",
                        )
        elif kind == "remove_mimic_attributes" and "velocity_limit" in v:
            yield ctx.problem(
                v.key_node("velocity_limit"),
                "'velocity_limit' is unconfirmed; the confirmed spelling is 'velocity_limits'",
                f"modifiers[{i}].remove_mimic_attributes.velocity_limit",
            )


RULE = Rule("unconfirmed-syntax", Severity.WARNING, check, __doc__ or "")
