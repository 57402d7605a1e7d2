"""How many spheres each link gets: the counting options of a fit (:class:`CountPolicy`) and
their bounds, as :func:`~.robot_fit.fit_robot` and each link's fit (:mod:`.link_fit`) read
them."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

from ..util.errors import XrdfToolsError

__all__ = [
    "AUTO_COVERAGE_TARGET",
    "BY_TARGET",
    "MAX_PER_LINK",
    "CountPolicy",
    "check_counts",
    "check_policy",
]

MAX_PER_LINK = 64
AUTO_COVERAGE_TARGET = 0.9


def check_counts(
    per_link: int | Mapping[str, int] | None, count: int | None, density: float | None
) -> None:
    """Raise for more than one counting option or a value out of range."""
    given = [
        n
        for n, v in (("per_link", per_link), ("count", count), ("density", density))
        if v is not None
    ]
    if len(given) > 1:
        raise XrdfToolsError(f"give at most one of count, per-link and density (got {given})")
    for n in per_link.values() if isinstance(per_link, Mapping) else [per_link]:
        if n is not None and not 0 <= n <= MAX_PER_LINK:
            raise XrdfToolsError(f"per-link must be between 1 and {MAX_PER_LINK}, got {n}")
    if isinstance(per_link, int) and per_link < 1:
        raise XrdfToolsError(f"per-link must be between 1 and {MAX_PER_LINK}, got {per_link}")
    if count is not None and count < 1:
        raise XrdfToolsError(f"count must be at least 1, got {count}")
    if density is not None and not (density > 0 and math.isfinite(density)):
        raise XrdfToolsError(f"density must be a positive number, got {density}")


@dataclass(frozen=True)
class CountPolicy:
    """How many spheres each link gets (see :func:`~.robot_fit.fit_robot`)."""

    per_link: int | Mapping[str, int] | None = None
    count: int | None = None
    density: float | None = None
    target_coverage: float = AUTO_COVERAGE_TARGET
    #: With a count given and no protrusion bound of the link's own: its bound is the
    #: smallest at which its spheres cover this share of its volume (None: the default
    #: bound, :func:`~.fit.default_max_protrusion`).
    count_coverage: float | None = None
    #: With a count given and no protrusion bound of the link's own (and no
    #: ``count_coverage``): the greedy spheres are refined on coverage and on the protrusion
    #: of their union (:mod:`.refine`). False keeps every sphere within the default bound.
    refine: bool = True
    #: Without a count: spheres are added until little of the link's surface lies far from
    #: every sphere (:mod:`.surface_gap`). False: the volume target alone decides the count.
    reach_surface: bool = True

    @property
    def given(self) -> bool:
        """Whether a count is given (per link, in total or by density)."""
        return self.per_link is not None or self.count is not None or self.density is not None


#: No count given: each link gets the fewest spheres that reach the coverage target.
BY_TARGET = CountPolicy()


def check_policy(counts: CountPolicy) -> None:
    """Raise for counting options out of range or together, or a coverage share out of
    (0, 1]."""
    check_counts(counts.per_link, counts.count, counts.density)
    for what, share in (("target", counts.target_coverage), ("count", counts.count_coverage)):
        if share is not None and not 0.0 < share <= 1.0:
            raise XrdfToolsError(f"{what} coverage must be in (0, 1], got {share}")
