"""What ``xrdf convert --fit-spheres`` says of the self-collision mask it computed: its counts and
the input's pairs it removed (``convert-computed-mask``), pairs it ignores because they collide
at the default configuration (``convert-mask-default-pose``), and a mask that leaves nothing to
check (``convert-mask-nothing-checked``)."""

from __future__ import annotations

from collections import Counter
from typing import TYPE_CHECKING

from ..diagnostics import Diagnostic, Severity
from ..util.text import name_list, pair_text

if TYPE_CHECKING:
    from ..report import PairStat, Report
    from ..xrdf.model import Xrdf

__all__ = [
    "RULE_MASK",
    "RULE_MASK_DEFAULT",
    "RULE_MASK_NOTHING",
    "default_pose_pairs",
    "mask_summary",
    "nothing_checked",
]

RULE_MASK = "convert-computed-mask"
RULE_MASK_DEFAULT = "convert-mask-default-pose"
RULE_MASK_NOTHING = "convert-mask-nothing-checked"


def default_pose_pairs(report: Report) -> list[Diagnostic]:
    """A warning naming the pairs the mask ignores because they collide at the default
    configuration although sampling finds them apart elsewhere (``convert-mask-default-pose``).

    The Setup Assistant's rule takes such a pair for parts that always overlap; when the
    default pose itself collides (a folded home pose, spheres that reach past a mesh), the
    pair does collide in other configurations and the planner no longer sees it.
    """
    from ..report import ALWAYS_RATE

    pairs = [
        p
        for p in report.pairs
        if p.classification == "default"
        and p.recommendation != "check"
        and p.rate is not None
        and p.rate <= ALWAYS_RATE
    ]
    if not pairs:
        return []
    shown = name_list(
        (f"{pair_text(p.frame_a, p.frame_b)} (apart in {1 - (p.rate or 0.0):.0%})" for p in pairs),
        6,
    )
    msg = (
        f"{len(pairs)} pair(s) ignored because they collide at the default configuration, "
        f"though apart in some of the {report.samples} samples: {shown}; the planner will not "
        "see them collide anywhere. Give a default configuration free of self-collision "
        "(an SRDF group_state: --srdf, --state; or the XRDF's default_joint_positions, then "
        "`xrdf report ROBOT.xrdf --urdf ROBOT.urdf --write-mask NEW.xrdf` computes the mask "
        "again) or check these pairs (`xrdf report`)"
    )
    return [
        Diagnostic(
            report.urdf_path,
            None,
            None,
            RULE_MASK_DEFAULT,
            Severity.WARNING,
            msg,
            "self_collision.ignore",
        )
    ]


def nothing_checked(report: Report) -> list[Diagnostic]:
    """A warning when the mask leaves no pair of sphere frames to check
    (``convert-mask-nothing-checked``), saying which of two causes it is: the c-space moves no
    two sphere frames relative to each other (the Shadow Hand's default c-space is its two
    wrist joints, which turn the whole hand and no finger), or it does, and every pair it
    moves is ignored, counted per reason (adjacent, colliding at the default configuration or
    nearly always, never colliding). cuRobo's loader raises on either file."""
    if not report.pairs or any(p.recommendation == "check" for p in report.pairs):
        return []
    joints = report.cspace_joints
    cspace = f"the c-space ({len(joints)}: {name_list(joints, 6)})"
    moved = [p for p in report.pairs if p.joints_on_path > 0]
    head = (
        f"no pair of the {len(report.frames)} sphere frames is left to check for self-collision: "
    )
    if not moved:
        why = (
            f"{cspace} moves none of them relative to another (all {len(report.pairs)} pair(s) "
            "keep their relative pose); cuRobo's loader raises on such a file. Plan for the "
            "joints that move parts against each other (--joints, --chain or --group)"
        )
    else:
        why = (
            f"{cspace} moves {len(moved)} of the {len(report.pairs)} pair(s) relative to each "
            f"other, and the mask ignores each of them ({_ignored_reasons(moved, report.samples)})"
            "; cuRobo's loader raises on such a file. Check those pairs (`xrdf report`), or "
            "plan for joints that move more parts against each other (--joints, --chain or "
            "--group)"
        )
    return [
        Diagnostic(
            report.urdf_path,
            None,
            None,
            RULE_MASK_NOTHING,
            Severity.WARNING,
            head + why,
            "self_collision.ignore",
        )
    ]


def _ignored_reasons(pairs: list[PairStat], samples: int) -> str:
    """``1 adjacent, 2 never colliding in the 1000 samples``: the ignored ``pairs`` counted
    per reason."""
    counts: Counter[str] = Counter(p.classification for p in pairs)
    said = {
        "adjacent": "adjacent",
        "default": "colliding at the default configuration",
        "always": f"colliding in more than 95 % of the {samples} samples",
        "never": f"never colliding in the {samples} samples",
    }
    return ", ".join(f"{counts[c]} {what}" for c, what in said.items() if counts[c])


_REASONS = (
    ("adjacent", "adjacent"),
    ("default", "colliding at the default configuration"),
    ("always", "colliding in more than 95 % of them"),
    ("never", "never colliding"),
)


def mask_summary(report: Report, x: Xrdf) -> Diagnostic:
    """Counts per reason of the computed mask (``convert-computed-mask``)."""
    ignored: Counter[str] = Counter(
        p.classification for p in report.pairs if p.recommendation != "check"
    )
    near = [p for p in report.pairs if p.recommendation == "check" and p.classification == "never"]
    checked = sum(1 for p in report.pairs if p.recommendation == "check") - len(near)
    reasons = ", ".join(f"{ignored[c]} {what}" for c, what in _REASONS if ignored[c])
    sc = x.self_collision
    total = len(sc.ignore_pairs()) if sc is not None else 0
    sampled = {frozenset((p.frame_a, p.frame_b)) for p in report.pairs}
    kept = total - sum(ignored.values())
    msg = (
        f"self_collision.ignore computed from {report.samples} {report.sampler} samples (seed "
        f"{report.seed}), like `xrdf report --write-mask`: {sum(ignored.values())} pair(s) "
        f"ignored ({reasons or 'none'}); {checked} pair(s) checked (they sometimes collide)"
    )
    if near:
        msg += "; " + _near_misses(near)
    if kept:
        msg += f"; {kept} pair(s) of the inputs kept (a frame without spheres)"
    removed = [p for p in report.mask_change.removed if frozenset(p) in sampled]
    if removed:
        msg += (
            f"; {len(removed)} pair(s) of the inputs removed (they sometimes collide, or came "
            "within the margin): " + _removed_pairs(report, removed)
        )
    return Diagnostic(
        report.urdf_path, None, None, RULE_MASK, Severity.INFO, msg, "self_collision.ignore"
    )


def _near_misses(near: list[PairStat]) -> str:
    """``2 pair(s) checked although they never collided: ... (closest a/b 0.1 mm)``."""
    closest = sorted(near, key=lambda p: (p.min_clearance or 0.0, p.frame_a, p.frame_b))
    shown = name_list(
        f"{pair_text(p.frame_a, p.frame_b)} {(p.min_clearance or 0.0) * 1000:.1f} mm"
        for p in closest
    )
    return (
        f"{len(near)} pair(s) checked although they never collided: they came within the 10 mm "
        f"margin, where a configuration between the samples may close the gap ({shown}); "
        "`xrdf report --certify --write-mask` ignores those it proves apart"
    )


def _share(rate: float) -> str:
    """``3.3%``; a rate under 0.1 % with two significant digits (``0.042%``), never ``0.0%``."""
    return f"{rate:.1%}" if rate >= 0.001 else f"{rate * 100:.2g}%"


def _removed_pairs(report: Report, removed: list[tuple[str, str]]) -> str:
    """``a/b (in 3.3 % of samples)``: the input's ignored pairs the samples saw collide."""
    rates = {frozenset((p.frame_a, p.frame_b)): p.rate for p in report.pairs}

    gaps = {frozenset((p.frame_a, p.frame_b)): p.min_clearance for p in report.pairs}

    def named(a: str, b: str) -> str:
        rate = rates.get(frozenset((a, b)))
        if rate:
            return f"{pair_text(a, b)} (in {_share(rate)} of samples)"
        gap = gaps.get(frozenset((a, b)))
        if gap is None:
            return pair_text(a, b)
        return f"{pair_text(a, b)} ({gap * 1000:.1f} mm apart at the closest)"

    return name_list(named(a, b) for a, b in removed)
