"""Verdicts and findings: how a frame pair is classified and what the report flags.

Classification, first match wins (MoveIt Setup Assistant order, :func:`classify_pair`):

``adjacent``  the frames are joined by a joint once frames without spheres are collapsed,
              with at most two moving joints between them (:func:`adjacent_frame_pairs`);
``default``   the pair collides at the default configuration;
``always``    it collides in more than :data:`ALWAYS_RATE` of the configurations;
``never``     it never collides in the ``N`` configurations: with independent uniform samples
              the collision rate is below :func:`never_upper_bound` (≈ 3/N) with 95 %
              confidence;
``sometimes`` anything else.

``--certify`` may then turn a "never" into proven or, with a witness, into "sometimes"
(:func:`certified_stat`). :func:`pair_findings` turns the statistics into diagnostics with
the rule ids of :data:`RULES`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import replace
from typing import TYPE_CHECKING

from ..diagnostics import Diagnostic, RuleInfo, Severity
from ..robot.adjacency import adjacent_pairs, joint_moves
from ..robot.kinematics import JointType, KinematicModel
from ..selfcollision.collision import Contact
from ..util.errors import did_you_mean
from ..xrdf.model import SelfCollisionSection, Xrdf
from .results import CertifyOptions, Classification, PairStat, Recommendation, TrajectoryHit

if TYPE_CHECKING:
    from ..selfcollision.certify import Certificate

__all__ = ["ALWAYS_RATE", "RULES", "adjacent_frame_pairs", "never_upper_bound"]

#: A pair colliding in more than this fraction of configurations is "always" colliding.
ALWAYS_RATE = 0.95

#: The report's rules.
RULES: tuple[RuleInfo, ...] = (
    RuleInfo(
        "report-always-colliding",
        Severity.ERROR,
        "an unmasked frame pair collides in more than 95 % of configurations",
        "report",
    ),
    RuleInfo(
        "report-default-colliding",
        Severity.ERROR,
        "an unmasked frame pair collides at the default configuration",
        "report",
    ),
    RuleInfo(
        "report-mask-hides-collision",
        Severity.WARNING,
        "a masked frame pair that is not adjacent collides sometimes",
        "report",
    ),
    RuleInfo(
        "report-unknown-mask-frame",
        Severity.WARNING,
        "self_collision.ignore names a frame the robot does not have",
        "report",
    ),
    RuleInfo(
        "report-nothing-checked",
        Severity.WARNING,
        "the self-collision spheres sit on one frame: no frame pair to check",
        "report",
    ),
    RuleInfo(
        "report-no-spheres",
        Severity.ERROR,
        "the self-collision group holds no sphere: the report checks nothing",
        "report",
    ),
    RuleInfo(
        "report-trajectory-collision",
        Severity.ERROR,
        "a given configuration (--configs) is in self-collision",
        "report",
    ),
)
_SEVERITY = {r.id: r.severity for r in RULES}


def never_upper_bound(n: int, confidence: float = 0.95) -> float:
    """Upper bound of the collision rate after ``n`` samples without a hit (exact binomial).

    ``1 − (1 − confidence)^(1/n)``; about ``3/n`` for 95 %. ``1.0`` for ``n == 0``.
    """
    if n <= 0:
        return 1.0
    return -math.expm1(math.log(1.0 - confidence) / n)


def adjacent_frame_pairs(
    kin: KinematicModel, geometry_frames: Sequence[str]
) -> frozenset[frozenset[str]]:
    """Pairs of ``geometry_frames`` joined by a joint once frames without geometry collapse.

    Two geometry frames are adjacent when the kinematic tree path between them passes only
    through frames without geometry (none at all: parent and child), the rule of the MoveIt
    Setup Assistant (siblings under a geometry-less frame are adjacent too), and at most
    :data:`~xrdf_tools.robot.adjacency.MAX_ADJACENT_MOVING_JOINTS` joints on it move
    (:func:`~xrdf_tools.robot.adjacency.adjacent_pairs`).
    """
    names = kin.frame_names
    edges = {names[i]: (names[int(kin.parent[i])], _moves(kin, i)) for i in range(1, kin.n_frames)}
    return adjacent_pairs(edges, geometry_frames)


def _moves(kin: KinematicModel, frame: int) -> bool:
    """Whether the joint above ``frame`` counts as moving (:func:`joint_moves`)."""
    joint = kin.joint_of_frame[frame]
    info = kin.joints.get(joint) if joint is not None else None
    if info is not None:
        return joint_moves(info)
    return int(kin.joint_type[frame]) != JointType.FIXED


def certified_stat(
    p: PairStat,
    cert: Certificate,
    cspace: Sequence[str],
    opts: CertifyOptions,
) -> PairStat:
    """The pair's statistics with the verdict of ``--certify`` (``cert``, whose joints index
    ``cspace``). Its notes say how many boxes it took, never how long: the same on every run."""
    path = [cspace[j] for j in cert.joints]
    took = f"{cert.boxes:,} box{'es' if cert.boxes != 1 else ''}"
    if cert.verdict == "witness" and cert.witness is not None:
        values = {j: float(v) for j, v in zip(cspace, cert.witness, strict=True)}
        what = "remove from ignore" if p.masked else "keep checking"
        at = ", ".join(f"{j}={values[j]:.4f}" for j in path)
        note = f"collides at {at} (others at default; found by --certify in {took}): {what}"
        return replace(
            p,
            classification="sometimes",
            recommendation="check",
            note=note,
            certificate="witness",
            witness=values,
            certify_boxes=cert.boxes,
        )
    if cert.verdict == "proven":
        note = f"proven never to collide over the whole joint box ({took}): ignore"
        return replace(
            p, recommendation="ignore", note=note, certificate="proven", certify_boxes=cert.boxes
        )
    rec: Recommendation = "check" if opts.mask_policy == "proven" else p.recommendation
    limit = "--certify-budget time limit" if cert.timed_out else "--certify-boxes budget"
    note = f"{p.note}; not proven within the {limit} ({took})"
    return replace(
        p, recommendation=rec, note=note, certificate="undecided", certify_boxes=cert.boxes
    )


def classify_pair(
    adjacent: bool,
    default_clearance: float,
    hits: int | None,
    rate: float | None,
    n: int,
    ub: float,
    masked: bool,
    source: str,
    near_miss: tuple[float, float] | None = None,
    fixed: bool = False,
) -> tuple[Classification, Recommendation, str]:
    """``near_miss``: ``(clearance, margin)`` when the pair came within the clearance margin
    (its smallest clearance is exact there); a "never" pair that came that near is kept
    checked: a configuration between the samples may well close the gap (two FR3 arms: a
    pair 4.5 mm apart at best in 100,000 samples collides where --certify looked).
    ``fixed``: no c-space joint lies between the two frames, so their clearance is the same
    in every configuration (the default one's): apart there, the pair never collides, however
    near (a gripper on its flange, two links of an arm the c-space holds)."""
    what = "samples" if source == "sampled" else "given configurations"
    if adjacent:
        return "adjacent", "ignore", "adjacent frames: ignore"
    if default_clearance < 0:
        return "default", "ignore", "collides at the default configuration: ignore"
    assert hits is not None and rate is not None
    if rate > ALWAYS_RATE:
        return "always", "ignore", f"collides in {rate:.1%} of {what}: ignore"
    if hits == 0 and fixed:
        return (
            "never",
            "ignore",
            f"never collides: no c-space joint moves these frames against each other, "
            f"{default_clearance * 1000:.1f} mm apart in every configuration: ignore",
        )
    if hits == 0 and near_miss is not None:
        gap, margin = near_miss
        return (
            "never",
            "check",
            f"never seen in {n} {what}, but {gap * 1000:.1f} mm apart at the closest, within "
            f"the {margin * 1000:g} mm margin: keep checking (--certify may prove it never "
            "collides)",
        )
    if hits == 0:
        return (
            "never",
            "may-ignore",
            f"may ignore: never seen in {n} {what} (rate < {ub:.2g} at 95 % confidence)",
        )
    if masked:
        return "sometimes", "check", f"collides in {rate:.3%} of {what}: remove from ignore"
    return "sometimes", "check", f"collides in {rate:.3%} of {what}: keep checking"


def _diag(xrdf: Xrdf, rule: str, message: str, key_path: str) -> Diagnostic:
    line, col = xrdf.source.position(key_path)
    return Diagnostic(xrdf.source.path, line, col, rule, _SEVERITY[rule], message, key_path)


def _ignore_key_path(sc: SelfCollisionSection | None, a: str, b: str) -> str:
    if sc is None:
        return "self_collision"
    for x, y in ((a, b), (b, a)):
        others = sc.ignore.get(x, ())
        if y in others:
            return f"self_collision.ignore.{x}[{others.index(y)}]"
    return "self_collision.ignore"


def unchecked_finding(xrdf: Xrdf, n_spheres: int, n_pairs: int) -> Diagnostic | None:
    """The finding of a report that checked no pair, where "free of self-collision" would say
    nothing about the robot: an error when there is no sphere at all (an XRDF converted
    without --fit-spheres, or a group left empty), a warning when spheres sit on one frame
    only; None when some pair was checked."""
    if n_pairs:
        return None
    sc = xrdf.self_collision
    where = "self_collision.geometry" if sc is not None else "self_collision"
    fit = "fit spheres: xrdf convert --fit-spheres, or xrdf spheres"
    world = sum(len(s) for s in xrdf.world_collision_spheres().values()) if sc is None else 0
    if n_spheres == 0 and world and xrdf.world_collision is not None:
        message = (
            f"the XRDF has no self_collision section: its {world} world-collision spheres are "
            "never checked against each other, so the report checks nothing (to check them, add "
            f"self_collision: {{geometry: {xrdf.world_collision.geometry}, ignore: {{}}}})"
        )
        return _diag(xrdf, "report-no-spheres", message, xrdf.collision_key)
    if n_spheres == 0:
        what = f"self-collision group '{sc.geometry}'" if sc is not None else "XRDF"
        message = (
            f"the {what} holds no collision sphere: no pair can collide, so the report checks "
            f"nothing ({fit})"
        )
        return _diag(xrdf, "report-no-spheres", message, where)
    message = (
        "no two frames have self-collision spheres, so no pair was checked: this report says "
        f"nothing about self-collision ({fit})"
    )
    return _diag(xrdf, "report-nothing-checked", message, where)


def pair_findings(
    xrdf: Xrdf,
    kin: KinematicModel,
    stats: Sequence[PairStat],
    def_contacts: Sequence[Contact],
    trajectory: Sequence[TrajectoryHit] | None,
    n: int,
) -> list[Diagnostic]:
    """The report's findings, in this order: per pair of ``stats``, an unmasked pair that
    collides nearly always and a masked one that collides sometimes; each pair colliding at
    the default configuration; each frame of the mask the robot lacks; each given
    configuration in self-collision. ``n``: the configurations counted."""
    out: list[Diagnostic] = []
    for p in stats:
        for found in (_always_colliding(xrdf, p, n), _mask_hides_collision(xrdf, p, n)):
            if found is not None:
                out.append(found)
    out.extend(_default_colliding(xrdf, c) for c in def_contacts)
    out.extend(_unknown_mask_frames(xrdf, kin))
    out.extend(_trajectory_collision(xrdf, hit) for hit in trajectory or ())
    return out


def _always_colliding(xrdf: Xrdf, p: PairStat, n: int) -> Diagnostic | None:
    """``report-always-colliding`` when the unmasked pair ``p`` collides in more than
    :data:`ALWAYS_RATE` of the ``n`` configurations."""
    if p.masked or p.rate is None or not p.rate > ALWAYS_RATE:
        return None
    return _diag(
        xrdf,
        "report-always-colliding",
        f"'{p.frame_a}' and '{p.frame_b}' collide in {p.rate:.1%} of {n} configurations but "
        "are not in self_collision.ignore: a planner will find no valid configuration",
        "self_collision.ignore" if xrdf.self_collision is not None else "self_collision",
    )


def _mask_hides_collision(xrdf: Xrdf, p: PairStat, n: int) -> Diagnostic | None:
    """``report-mask-hides-collision`` when the masked pair ``p`` collides sometimes (in the
    samples, or at the witness --certify found)."""
    if not p.masked or p.classification != "sometimes":
        return None
    seen = (
        "collide at a configuration that --certify found (sampling missed it)"
        if p.certificate == "witness"
        else f"collide in {p.hits} of {n} configurations ({p.rate:.3%})"
    )
    return _diag(
        xrdf,
        "report-mask-hides-collision",
        f"'{p.frame_a}' and '{p.frame_b}' are ignored but are not adjacent and {seen}: the "
        "mask hides real collisions",
        _ignore_key_path(xrdf.self_collision, p.frame_a, p.frame_b),
    )


def _default_colliding(xrdf: Xrdf, c: Contact) -> Diagnostic:
    """``report-default-colliding``: the unmasked pair of ``c`` collides at the default
    configuration."""
    return _diag(
        xrdf,
        "report-default-colliding",
        f"'{c.frame_a}' and '{c.frame_b}' collide at the default configuration "
        f"(clearance {c.clearance * 1000:.1f} mm, spheres {c.sphere_a} and "
        f"{c.sphere_b}) but are not in self_collision.ignore",
        "default_joint_positions",
    )


def _unknown_mask_frames(xrdf: Xrdf, kin: KinematicModel) -> list[Diagnostic]:
    """``report-unknown-mask-frame`` at each name of ``self_collision.ignore`` (a key or a
    listed frame) that is not a frame of the robot."""
    sc = xrdf.self_collision
    if sc is None:
        return []
    out: list[Diagnostic] = []
    for a, others in sc.ignore.items():
        for i, name in enumerate((a, *others)):
            if kin.has_frame(name):
                continue
            kp = f"self_collision.ignore.{a}" + ("#key" if i == 0 else f"[{i - 1}]")
            out.append(
                _diag(
                    xrdf,
                    "report-unknown-mask-frame",
                    f"self_collision.ignore names unknown frame '{name}'"
                    + did_you_mean(name, kin.frame_names)
                    + "; the entry masks nothing",
                    kp,
                )
            )
    return out


def _trajectory_collision(xrdf: Xrdf, hit: TrajectoryHit) -> Diagnostic:
    """``report-trajectory-collision``: a given configuration is in self-collision, named
    with its worst pair."""
    worst = hit.contacts[0] if hit.contacts else None
    detail = (
        f"'{worst.frame_a}' and '{worst.frame_b}' (clearance {worst.clearance * 1000:.1f} mm)"
        if worst
        else "?"
    )
    more = f" and {len(hit.contacts) - 1} more pair(s)" if len(hit.contacts) > 1 else ""
    return Diagnostic(
        xrdf.source.path,
        None,
        None,
        "report-trajectory-collision",
        Severity.ERROR,
        f"configuration {hit.index} is in self-collision: {detail}{more}",
        f"configs[{hit.index}]",
    )
