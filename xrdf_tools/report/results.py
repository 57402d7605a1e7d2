"""What a self-collision report holds: per-pair statistics, trajectory hits, the mask change.

Plain frozen values, built by :func:`xrdf_tools.report.self_collision_report` and rendered by
:mod:`xrdf_tools.report.render`; :meth:`PairStat.to_dict` is the pair's JSON form.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Literal

from ..diagnostics import Diagnostic
from ..selfcollision.collision import Contact
from ..util.errors import XrdfToolsError
from ..util.numbers import CERTIFY_BOXES

if TYPE_CHECKING:
    from ..selfcollision.certify import Verdict
    from ..spheres import CoverageSummary

Sampler = Literal["uniform", "halton"]
Classification = Literal["adjacent", "default", "always", "never", "sometimes"]
Recommendation = Literal["ignore", "may-ignore", "check"]

__all__ = [
    "CertifyOptions",
    "Classification",
    "ConfigsError",
    "MaskChange",
    "PairStat",
    "Recommendation",
    "Report",
    "Sampler",
    "TrajectoryHit",
]


@dataclass(frozen=True)
class CertifyOptions:
    """``--certify``: decide every "never" pair over its whole joint box (see
    :mod:`xrdf_tools.selfcollision.certify`) within ``boxes`` boxes in all, shared evenly among
    the pairs still to decide (the same verdicts on every machine). ``mask_policy``
    ``"proven"`` recommends ignoring a never-colliding pair only when it is proven;
    ``"sampled"`` keeps the sampled recommendation. ``budget_s``: also stop after this many
    seconds in all (None: no wall-clock limit; with one, the verdicts can depend on the
    machine's speed)."""

    boxes: int = CERTIFY_BOXES
    mask_policy: Literal["proven", "sampled"] = "sampled"
    budget_s: float | None = None


class ConfigsError(XrdfToolsError):
    """A ``--configs`` file cannot be read or does not fit the c-space."""


@dataclass(frozen=True)
class PairStat:
    """Statistics and verdict for one pair of frames that carry spheres.

    ``hits``/``rate`` are None when the pair was not sampled (masked and adjacent).
    ``min_clearance`` is the smallest clearance seen (negative: deepest penetration), exact
    below the report's clearance margin; when ``min_clearance_is_bound`` the pair never came
    closer than the margin, and ``min_clearance`` is the margin. ``rate_upper_95`` is the 95 %
    upper bound of the collision rate when ``hits == 0``.
    """

    frame_a: str
    frame_b: str
    spheres_a: int
    spheres_b: int
    masked: bool
    adjacent: bool
    sampled: bool
    hits: int | None
    rate: float | None
    rate_upper_95: float | None
    min_clearance: float | None
    min_clearance_is_bound: bool
    default_clearance: float
    classification: Classification
    recommendation: Recommendation
    note: str
    certificate: Verdict | None = None
    witness: Mapping[str, float] | None = None
    certify_boxes: int | None = None
    #: Actuated joints whose values move the two frames relative to each other: 0 means the
    #: pair's verdict holds for every configuration, 1-2 are decided on a grid.
    joints_on_path: int = 0

    @property
    def colliding_at_default(self) -> bool:
        return self.default_clearance < 0

    def to_dict(self) -> dict[str, Any]:
        return {
            "frame_a": self.frame_a,
            "frame_b": self.frame_b,
            "spheres_a": self.spheres_a,
            "spheres_b": self.spheres_b,
            "masked": self.masked,
            "adjacent": self.adjacent,
            "sampled": self.sampled,
            "hits": self.hits,
            "rate": self.rate,
            "rate_upper_95": self.rate_upper_95,
            "min_clearance": finite_or_none(self.min_clearance),
            "min_clearance_is_bound": self.min_clearance_is_bound,
            "default_clearance": self.default_clearance,
            "classification": self.classification,
            "recommendation": self.recommendation,
            "note": self.note,
            "certified": None if self.certificate is None else self.certificate == "proven",
            "certificate": self.certificate,
            "witness": dict(self.witness) if self.witness is not None else None,
            "certify_boxes": self.certify_boxes,
            "joints_on_path": self.joints_on_path,
        }


@dataclass(frozen=True)
class TrajectoryHit:
    """A given configuration (row ``index`` of ``--configs``) in self-collision."""

    index: int
    contacts: tuple[Contact, ...]


@dataclass(frozen=True)
class MaskChange:
    """How the recommended ``ignore`` differs from the current one (pairs as (a, b))."""

    added: tuple[tuple[str, str], ...] = ()
    removed: tuple[tuple[str, str], ...] = ()
    dropped_unknown: tuple[str, ...] = ()

    @property
    def empty(self) -> bool:
        return not (self.added or self.removed or self.dropped_unknown)


@dataclass(frozen=True)
class Report:
    """Everything ``xrdf report`` shows. See :func:`self_collision_report`."""

    xrdf_path: str
    urdf_path: str
    source: Literal["sampled", "configs"]
    samples: int
    sampler: Sampler | None
    seed: int | None
    cspace_joints: tuple[str, ...]
    frames: tuple[str, ...]
    sphere_counts: Mapping[str, int]
    placeholders: int
    pairs: tuple[PairStat, ...]
    default_configuration: Mapping[str, float]
    default_contacts: tuple[Contact, ...]
    trajectory: tuple[TrajectoryHit, ...] | None
    recommended_ignore: Mapping[str, tuple[str, ...]]
    mask_change: MaskChange
    diagnostics: tuple[Diagnostic, ...]
    elapsed_s: float
    coverage: CoverageSummary | None = None
    _pair_index: dict[tuple[str, str], int] = field(default_factory=dict, compare=False, repr=False)

    @property
    def default_ok(self) -> bool:
        """No unmasked pair collides at the default configuration."""
        return not self.default_contacts

    @property
    def configs_per_s(self) -> float:
        return self.samples / self.elapsed_s if self.elapsed_s > 0 else float("inf")

    def pair(self, a: str, b: str) -> PairStat:
        """The statistics of frame pair ``a``/``b`` (either order); KeyError if absent."""
        if not self._pair_index:
            for i, p in enumerate(self.pairs):
                self._pair_index[(p.frame_a, p.frame_b)] = i
                self._pair_index[(p.frame_b, p.frame_a)] = i
        return self.pairs[self._pair_index[(a, b)]]


def finite_or_none(x: float | None) -> float | None:
    return None if x is None or not math.isfinite(x) else x
