"""Every diagnostic id xrdf-tools emits, in one registry: lint rules, report findings, and the
notes of convert, export, kinematics, sphere fitting and viz.

A :class:`~xrdf_tools.diagnostics.RuleInfo` (the one rule record) gives the id, its default
severity, a one-line summary and the command that emits it. ``docs/rules.md`` is generated
from this registry (``python -m xrdf_tools.rules.docs``) and SARIF logs describe their rules
from it; a test checks that every id the code emits is registered. Lint rules and report
findings are registered where they are defined (the lint rule modules,
:data:`xrdf_tools.report.RULES`); the table below holds the others.
"""

from __future__ import annotations

from functools import cache

from ..diagnostics import RuleInfo, Severity

__all__ = ["PRODUCER_RULES", "RuleInfo", "all_rules", "rule_info"]


W, I, E = Severity.WARNING, Severity.INFO, Severity.ERROR  # noqa: E741 - table shorthand

#: Diagnostics that are not lint rules or report findings: (id, default severity, summary).
_PRODUCERS: dict[str, tuple[tuple[str, Severity, str], ...]] = {
    "convert": (
        ("convert-chosen-group", W, "No planning group given: the one chosen, why, the others."),
        ("convert-chosen-state", W, "No group state given: the one used for default positions."),
        ("convert-chosen-tool-frame", W, "No tool frame in the inputs: the one guessed, why."),
        ("convert-clamped-default", W, "A default outside the URDF limits: turned or clamped in."),
        (
            "convert-computed-mask",
            I,
            "--fit-spheres or a Lula source: the mask computed, pairs per reason.",
        ),
        ("convert-cspace-order", W, "--target curobo: c-space put in URDF order (defaults kept)."),
        ("convert-default-acceleration", W, "No acceleration limit: a default or --acceleration."),
        ("convert-default-jerk", W, "No jerk limit in the inputs: the default or --jerk."),
        ("convert-default-positions", W, "No default position: 0, or the middle of the limits."),
        (
            "convert-drake-acceleration",
            I,
            "Acceleration limits from a URDF's drake:acceleration (below the limits file).",
        ),
        (
            "convert-drake-filter-group",
            I,
            "Pairs a Drake collision filter group never checks: ignored, with that reason.",
        ),
        ("convert-drake-frame", W, "A Drake frame (no link): no reader sees it unless added."),
        ("convert-drake-ignored", W, "A Drake-only element or attribute: left out, one per kind."),
        ("convert-dropped-joint", W, "A c-space joint that is not actuated: dropped."),
        (
            "convert-dropped-joint-value",
            I,
            "A state/lock value not used: non-actuated joint, several numbers; a lock's default.",
        ),
        (
            "convert-locked-default",
            I,
            "A joint outside the c-space with 0 outside its limits: its clamped default written.",
        ),
        ("convert-dropped-key", W, "A source key without XRDF equivalent: dropped."),
        ("convert-duplicate-frame", W, "An extra link that already exists in the URDF."),
        ("convert-duplicate-key", W, "A key repeated in a cuRobo file: the last value is used."),
        ("convert-empty-cspace", W, "The c-space is empty."),
        ("convert-fitted-spheres", I, "--fit-spheres: spheres fitted per link, links left out."),
        (
            "convert-moving-link-without-spheres",
            W,
            "--fit-spheres: a link a c-space joint moves has visual geometry only: no spheres.",
        ),
        ("convert-floating-base", W, "A floating/planar joint above the robot: base below it."),
        ("convert-frame-added", I, "--tool-frame names a Drake frame: written as an add_frame."),
        ("convert-launch-substitution", I, "$(var NAME) in joint_limits: --xacro-arg or ''."),
        (
            "convert-lula-no-mask",
            W,
            "A Lula description has no self-collision mask: convert computes it, else this.",
        ),
        (
            "convert-limit-not-carried",
            W,
            "joint_limits velocity/position limits tighter than the URDF: no XRDF carries them.",
        ),
        (
            "convert-mask-default-pose",
            W,
            "--fit-spheres: pairs masked for colliding at a default pose, apart elsewhere.",
        ),
        (
            "convert-mask-nothing-checked",
            W,
            "--fit-spheres: no pair left to check: the c-space moves none, or each is ignored.",
        ),
        ("convert-negative-limit", I, "A negative MoveIt limit: its absolute value is used."),
        (
            "convert-no-spheres",
            W,
            "No collision spheres at all in the inputs (an error when --fit-spheres fitted none).",
        ),
        ("convert-placeholder-spheres", W, "SRDF sphere approximation radii of zero, dropped."),
        ("convert-ros-parameters", I, "joint_limits read from a ROS 2 parameter file."),
        (
            "convert-srdf-end-effector",
            W,
            "An SRDF end effector naming a group it lacks: dropped, as MoveIt drops it.",
        ),
        ("convert-srdf-unused-group", W, "An SRDF group the conversion does not use is broken."),
        ("convert-unknown-joint", W, "A joint name that is not in the URDF: dropped."),
        ("convert-unknown-link", W, "A link name that is not in the URDF: dropped."),
        ("convert-target-check", E, "The XRDF fails --target whatever spheres: not fitted."),
        ("convert-unplannable-joint", W, "A planar/floating joint in a group: not in c-space."),
        ("convert-unreachable-links", W, "URDF parts the chosen base does not reach."),
        ("convert-unused-spheres", W, "Spheres cuRobo never used (not a collision link)."),
        ("convert-version", W, "Writing 2.0: the readers that load it with no collision."),
        ("convert-virtual-joint", I, "An SRDF virtual joint (XRDF is relative to the URDF root)."),
    ),
    "convert, export xrdf": (
        ("different-collision-groups", W, "World and self collision use different groups."),
        ("dropped-nonpositive-sphere", W, "Writing 2.0: a sphere with radius ≤ 0 is dropped."),
        ("flattened-clone", I, "Writing 1.0: a cloned geometry group, flattened."),
        ("invalid-radius-written", W, "Writing 1.0: a 2.0 sphere with radius ≤ 0 (invalid)."),
        ("missing-for-curobo", I, "Writing 1.0: a key cuRobo's loader requires is absent."),
        ("export-version", W, "Exported as 2.0: the readers that load it with no collision."),
    ),
    "export curobo": (
        ("export-default-positions", W, "A c-space joint without default: 0.0 is written."),
        ("export-different-groups", W, "World and self groups differ: the world group is used."),
        ("export-dropped-joint", W, "A default position of a joint that is not actuated."),
        ("export-dropped-key", W, "Top-level keys that have no cuRobo equivalent."),
        ("export-expanded-urdf", I, "A xacro --urdf: the expanded URDF written beside the YAML."),
        ("export-joint-axes", I, "Joint axes cuRobo cannot take, rewritten in the URDF written."),
        ("export-no-spheres", W, "No collision sphere to export: cuRobo checks no collision."),
        ("export-no-self-collision", I, "No self_collision: every sphere frame pair is ignored."),
        ("export-no-pair", E, "No sphere pair left to check: cuRobo's loader raises; not written."),
        ("export-self-only", W, "Self-collision spheres only: cuRobo checks the world too."),
    ),
    "export srdf": (
        ("export-mesh-paths", W, "Mesh names cuRobo cannot find from asset_root_path."),
        ("export-srdf-added", I, "Pairs added to the SRDF, with their reasons."),
        ("export-srdf-added-frame", W, "Ignore pairs on added frames MoveIt does not know."),
        (
            "export-srdf-held-joint",
            W,
            "Ignore pairs not added: the mask held a joint between them that MoveIt moves.",
        ),
        ("export-srdf-removed", W, "A disabled pair the XRDF no longer ignores: removed."),
        ("export-srdf-unknown-link", I, "Pairs naming a link the URDF lacks: kept as they are."),
        ("export-srdf-robot-name", W, "The SRDF robot name differs from the URDF's."),
    ),
    "robot loading (every command reading a URDF)": (
        ("urdf-color-ignored", W, "A material colour that is not 4 numbers: ignored."),
        (
            "urdf-limit-reversed",
            W,
            "A limit whose lower is above its upper: an error in a c-space.",
        ),
        ("urdf-limit-unbounded", W, "A limit beyond ±1e12 (no limit): dropped; turns freely."),
        ("urdf-ros-refuses", W, "What ROS's URDF parser refuses the robot for: read anyway."),
        ("xacro-package-unused", W, "A package not found, named only in <gazebo>, <ros2_control>."),
        ("xacro-warning", W, "A warning of xacro's while expanding (an include body it ignores)."),
        ("xacro-arg-unread", W, "A --xacro-arg the expansion never reads: it changes nothing."),
        (
            "urdf-prefix-undeclared",
            W,
            "A namespace prefix without xmlns: read past as ROS does (drake: as Drake does).",
        ),
    ),
    "kinematics (lint, report, viz)": (
        ("joint-held-fixed", W, "A joint that cannot move is held at its default."),
        ("joint-limits-missing", W, "A joint without limits: sampled in a default range."),
        ("sphere-frame-unknown", W, "Spheres on a frame the robot does not have: not checked."),
    ),
    "spheres, convert --fit-spheres": (
        ("spheres-adjacent-ignored", I, "Adjacent links' spheres overlap: the pair is ignored."),
        ("spheres-cloned-link", W, "Links that share one mesh: spheres fitted once."),
        ("spheres-bounding-box", W, "A part with no volume even as a hull: its bounding box."),
        ("spheres-collision-not-visual", W, "Collision geometry away from the visual: turned?"),
        ("spheres-convex-hull", W, "A mesh that is not watertight: its convex hull is used."),
        ("spheres-link-not-covered", E, "A link with geometry got no spheres, or only some."),
        ("spheres-mesh-unreadable", W, "A mesh that cannot be read: the link gets no spheres."),
        ("spheres-mesh-scale", W, "A link over 10 m across: a mesh in millimetres without scale?"),
        ("spheres-morphit-dropped", W, "Fewer MorphIt spheres than asked: pruned or out of room."),
        ("spheres-morphit-failed", W, "A solid MorphIt cannot fit: the link gets no spheres."),
        ("spheres-no-geometry", W, "A link without geometry: no spheres."),
        ("spheres-placeholder", I, "A part under 2 cm across: one sphere."),
        ("spheres-from-urdf", I, "A link whose geometry is <sphere> elements: taken as they are."),
        ("spheres-shared-mesh", I, "Links with identical geometry: fitted once, same spheres."),
        ("spheres-sheet", I, "A sheet, or a wide plate: its box cut into cells, a sphere each."),
        (
            "spheres-past-bound",
            I,
            "Spheres reach past their bound: too few within it, or too thin a part.",
        ),
        (
            "spheres-surface-gap",
            I,
            "A thin part far from every sphere: spheres added, or too few reach it.",
        ),
        ("spheres-target-missed", W, "A link whose spheres fall short of the coverage target."),
        ("spheres-thin-shell", I, "A shell far thinner than its hull: the hull is fitted."),
        ("spheres-unsupported-geometry", W, "A geometry kind the fitter does not handle."),
        ("spheres-visual-fallback", W, "No collision geometry: the visual geometry is used."),
        (
            "spheres-visual-unchecked",
            I,
            "Visual meshes not read: collision not compared with them.",
        ),
    ),
    "viz": (
        ("mesh-not-loaded", W, "A link mesh that cannot be loaded is not drawn."),
        ("mesh-simplified", I, "A mesh of over 100,000 triangles is drawn simplified."),
        ("viz-collisions-not-drawn", I, "Too many configurations: contacts logged, not coloured."),
        ("viz-frame-unknown", W, "Spheres on a frame the robot does not have: not drawn."),
        ("viz-placeholder-spheres", I, "Attached-object slots (radius ≤ −1) are not drawn."),
    ),
}

#: The rules of :data:`_PRODUCERS` as :class:`RuleInfo`.
PRODUCER_RULES: tuple[RuleInfo, ...] = tuple(
    RuleInfo(rid, sev, summary, producer)
    for producer, rows in _PRODUCERS.items()
    for rid, sev, summary in rows
)


@cache
def all_rules() -> dict[str, RuleInfo]:
    """Every registered id → :class:`RuleInfo`: lint rules, report findings, the rest."""
    from ..lint import RULES as LINT_RULES
    from ..report import RULES as REPORT_RULES

    out = {r.id: r.info for r in LINT_RULES}
    out["internal-error"] = RuleInfo(
        "internal-error",
        E,
        "A lint rule crashed: a bug in xrdf-tools, please report it.",
        "lint (framework)",
    )
    out.update({r.id: r for r in REPORT_RULES})
    out.update({r.id: r for r in PRODUCER_RULES})
    return out


def rule_info(rule_id: str) -> RuleInfo | None:
    """The registered :class:`RuleInfo` of ``rule_id``, or None."""
    return all_rules().get(rule_id)
