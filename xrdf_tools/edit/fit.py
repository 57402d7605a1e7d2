"""Refit the spheres of one link, with metrics to judge the proposal before accepting it.

The fitter and the metrics are :mod:`xrdf_tools.spheres`'s (the ones ``xrdf spheres`` and
``xrdf convert --fit-spheres`` use, with the same per-link seed), so a refit in the editor gives
the spheres those commands would give for the same count.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..spheres import MAX_PER_LINK, SphereMetrics, link_seed, sphere_metrics
from ..util.errors import XrdfToolsError
from ..xrdf.model import Sphere

if TYPE_CHECKING:
    from ..robot.core import Robot
    from ..robot.link_geometry import GeometryChoice

__all__ = ["FitProposal", "propose_fit"]

#: Points sampled to measure a proposal (and the current spheres): quick, a few 0.1 % noise.
METRIC_SAMPLES = 6000


@dataclass(frozen=True)
class FitProposal:
    """New spheres for ``frame`` and the metrics of the current (``before``) and the new
    (``after``) ones against the link's solid; ``warnings``: what the fit warns about the
    link's geometry (collision geometry not where its visual geometry is)."""

    frame: str
    spheres: tuple[Sphere, ...]
    before: SphereMetrics
    after: SphereMetrics
    warnings: tuple[str, ...] = ()

    def describe(self) -> str:
        b, a = self.before, self.after
        return (
            f"{self.frame}: {b.sphere_count} -> {a.sphere_count} spheres, coverage "
            f"{b.coverage:.1%} -> {a.coverage:.1%}, surface {b.surface_coverage:.1%} -> "
            f"{a.surface_coverage:.1%}, protrusion p95 {b.protrusion_p95 * 1000:.1f} -> "
            f"{a.protrusion_p95 * 1000:.1f} mm"
        )


def propose_fit(
    robot: Robot,
    frame: str,
    current: tuple[Sphere, ...],
    *,
    count: int | None = None,
    coverage: float | None = None,
    seed: int = 0,
    source: GeometryChoice = "auto",
) -> FitProposal:
    """Fit ``count`` spheres to ``frame``'s geometry, or the fewest (up to the per-link
    maximum) that reach ``coverage`` (a share of the volume, 0-1): the fit of
    :func:`xrdf_tools.spheres.robot_fit.fit_robot`, as ``xrdf spheres`` runs it.

    Exactly one of ``count`` and ``coverage``. Raises :class:`XrdfToolsError` for a link
    without geometry or a bad count/target.
    """
    from ..spheres.count_policy import CountPolicy
    from ..spheres.robot_fit import fit_robot
    from ..spheres.visual_agreement import RULE_MISMATCH

    if (count is None) == (coverage is None):
        raise XrdfToolsError("give either a sphere count or a coverage target")
    if count is not None and not 1 <= count <= MAX_PER_LINK:
        raise XrdfToolsError(f"sphere count must be between 1 and {MAX_PER_LINK}, got {count}")
    if coverage is not None and not 0 < coverage <= 1:
        raise XrdfToolsError(f"coverage target must be in (0, 1], got {coverage}")
    policy = (
        CountPolicy(per_link=count) if coverage is None else CountPolicy(target_coverage=coverage)
    )
    result = fit_robot(robot, links=[frame], counts=policy, seed=seed, source=source)
    if frame not in result.geometry:
        raise XrdfToolsError(f"link '{frame}' has no geometry to fit spheres to")
    solid = result.geometry[frame].solid
    spheres = result.spheres[frame]
    mseed = link_seed(seed, frame)
    return FitProposal(
        frame,
        spheres,
        sphere_metrics(solid, current, samples=METRIC_SAMPLES, seed=mseed),
        sphere_metrics(solid, spheres, samples=METRIC_SAMPLES, seed=mseed),
        tuple(d.message for d in result.diagnostics if d.rule == RULE_MISMATCH),
    )
