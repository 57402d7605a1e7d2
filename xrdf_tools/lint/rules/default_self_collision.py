"""With ``--urdf``: the default configuration is in self-collision.

The spec requires the default joint positions (missing ones: zero clamped to the limits) to be
free of self-collision when ``self_collision`` is given. The check uses the self-collision
group's spheres with ``self_collision.buffer_distance`` added and the ``ignore`` mask applied,
and names every colliding frame pair with its worst penetration. Fix the positions, the
spheres, or (for adjacent links) add the pair to ``ignore``.

A warning, not an error: cuMotion does not reject such a file. Its shipped
``gantry2d_anisotropic`` robot and its valid test robots ``simple_mimic`` (a link and its mimic
twin on one spot at the default) and ``thirty_link_arm_with_aux_cspace`` (auxiliary defaults
that fold the arm onto itself) load although their defaults collide.
Use ``--strict`` or configure the rule as ``error`` to enforce the spec's wording.
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ...yaml.io import YMap
from ..context import LintContext, Problem, Rule


def check(ctx: LintContext) -> Iterator[Problem]:
    kin, model = ctx.kin, ctx.model
    if kin is None or model is None or model.self_collision is None:
        return
    if ctx.clone_closure(model.self_collision.geometry) is None:
        return  # an undefined or cyclic group: undefined-group / clone-cycle report it
    from ...robot.kinematics import default_configuration
    from ...selfcollision.collision import SphereLimitError, colliding_frame_pairs

    known = set(kin.actuated_joints)
    defaults = {k: v for k, v in (model.default_joint_positions or {}).items() if k in known}
    section = ctx.get("self_collision")
    try:
        contacts = colliding_frame_pairs(kin, model, default_configuration(kin, defaults))
    except SphereLimitError as err:  # beyond the documented ceilings: said, not checked
        geometry = section.get("geometry") if isinstance(section, YMap) else section
        yield ctx.problem(geometry, f"default pose not checked: {err.message}", "geometry")
        return
    anchor = ctx.get("default_joint_positions") or (
        section.get("geometry") if isinstance(section, YMap) else section
    )
    for c in contacts:
        yield ctx.problem(
            anchor,
            f"default configuration is in self-collision: '{c.frame_a}' and '{c.frame_b}' "
            f"penetrate by {-c.clearance * 1000:.1f} mm (spheres {c.sphere_a} and "
            f"{c.sphere_b}); move the defaults, shrink the spheres or add the pair to ignore",
            "default_joint_positions",
        )


RULE = Rule("default-self-collision", Severity.WARNING, check, __doc__ or "", needs_urdf=True)
