"""The default count of a link: the fewest spheres reaching the coverage target.

:func:`fewest_reaching` finds the fewest spheres (up to :data:`AUTO_MAX_PER_LINK`) that cover
the target share of a link's volume within its protrusion bound. A part the bound cannot cover
with so few (a disc 80 mm wide and 10 mm thick under a 2.2 mm default bound: 16 spheres cover
43 % of it) is refined past its default bound instead (:func:`past_the_bound`), as a count
given with ``--per-link`` is: coverage against the 95th percentile of the protrusion (the disc:
96 % at 5.9 mm). A bound the user gives stays hard.

Whether spheres reach the target is judged on volume samples *held out* of the fit
(:class:`HeldOut`): the fit places its spheres to cover its own samples, so its share of them
overstates the share of the volume (a 12-sphere fit of an ABB IRB 2400 base covered 90.1 % of
its samples and 88.6 % of the volume). The judge takes the lower end of a one-sided 95 %
confidence interval of the held-out share, so that the coverage the metrics report afterwards,
from samples of their own, is at the target or above.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from ..xrdf.model import Sphere

if TYPE_CHECKING:
    from .fit import SphereFitter

__all__ = [
    "AUTO_MAX_PER_LINK",
    "HeldOut",
    "default_fit",
    "fewest_reaching",
    "past_the_bound",
    "short_of",
]

#: The most spheres a link gets by default.
AUTO_MAX_PER_LINK = 16
#: Volume samples held out of the fit to judge its coverage.
HELD_OUT_SAMPLES = 6000
#: The judged share is the held-out share less this many standard errors (one-sided 95 %).
HELD_OUT_Z = 1.645
#: Appended to the fitter's seed for the held-out samples' generator.
_HELD_OUT_STREAM = 0x4A5544


class HeldOut:
    """Volume samples of a fitter's solid that its fit never sees (on the kept side of its
    clip planes), from a generator seeded from the fitter's seed: the same for the same
    solid and seed."""

    def __init__(self, fitter: SphereFitter, samples: int = HELD_OUT_SAMPLES) -> None:
        from .metrics import sample_volume

        seed = [int(s) for s in np.atleast_1d(np.asarray(fitter.seed, dtype=np.int64))]
        rng = np.random.default_rng([*seed, _HELD_OUT_STREAM])
        self.points = fitter.kept(sample_volume(fitter.solid, samples, rng))

    def share(self, spheres: tuple[Sphere, ...]) -> float:
        """The covered share of the held-out samples, less :data:`HELD_OUT_Z` standard errors
        (0 without samples or spheres)."""
        from .metrics import inside_any, sphere_arrays

        n = len(self.points)
        if n == 0 or not spheres:
            return 0.0
        share = float(inside_any(self.points, *sphere_arrays(spheres)).mean())
        return max(0.0, share - HELD_OUT_Z * math.sqrt(share * (1.0 - share) / n))


def fewest_reaching(
    fitter: SphereFitter, target: float, judge: HeldOut | None = None
) -> tuple[tuple[Sphere, ...], float]:
    """The fewest spheres (up to AUTO_MAX_PER_LINK) whose judged share (``judge``, else a
    new :class:`HeldOut`) reaches ``target``, and that share. The first count whose greedy
    cover reaches the target on the fit's own samples is where the search starts: counts
    are added from there while the judge says it falls short, and a bisection below it finds
    the fewest that the judge accepts."""
    judge = judge or HeldOut(fitter)
    curve = fitter.greedy(AUTO_MAX_PER_LINK)[1]
    reach = [k + 1 for k, c in enumerate(curve) if c >= target]
    hi = reach[0] if reach else AUTO_MAX_PER_LINK
    fits = {hi: fitter.fit(hi)}
    shares = {hi: judge.share(fits[hi])}
    while shares[hi] < target and hi < AUTO_MAX_PER_LINK:
        hi += 1
        fits[hi] = fitter.fit(hi)
        shares[hi] = judge.share(fits[hi])
    lo = 0  # lo spheres do not reach the target (0 never does), hi do (or hi is the cap)
    while hi - lo > 1:
        mid = (lo + hi) // 2
        fits[mid] = fitter.fit(mid)
        shares[mid] = judge.share(fits[mid])
        if shares[mid] >= target:
            hi = mid
        else:
            lo = mid
    return fits[hi], shares[hi]


def past_the_bound(
    fitter: SphereFitter, k: int, judge: HeldOut | None = None
) -> tuple[tuple[Sphere, ...], float]:
    """``k`` spheres refined past the fitter's default bound (:func:`~.refine.refined_fit`,
    its distance grid first widened as a count-given fit's is) and their judged share."""
    from .fit import default_max_protrusion
    from .refine import START_BOUNDS, refined_fit

    fitter.widen(max(START_BOUNDS) * default_max_protrusion(fitter.solid))
    spheres = refined_fit(fitter, k)
    return spheres, (judge or HeldOut(fitter)).share(spheres)


def default_fit(
    fitter: SphereFitter, target: float, *, past: bool, most: int
) -> tuple[tuple[Sphere, ...], tuple[bool, str] | None]:
    """A link's spheres without a count: the fewest reaching ``target`` within the fitter's
    bound, else (``past``: the bound is the default, not the user's) as many refined past
    it. Also what to say, when something is: ``(missed, text)``, ``missed`` when the target
    is not reached (``most``: the largest --per-link, named in the advice)."""
    judge = HeldOut(fitter)
    spheres, share = fewest_reaching(fitter, target, judge)
    what = f"{len(spheres)} spheres cover {short_of(share)} of its volume (target {target:.0%})"
    advice = "raise --max-protrusion or give --per-link for more"
    if share < target and past:
        within = (
            f"{len(spheres)} spheres within its {fitter.tau * 1000:.3g} mm default bound cover "
            f"{short_of(share)} of it (target {target:.0%})"
        )
        spheres, share = past_the_bound(fitter, len(spheres), judge)
        if share >= target:
            said = f"refined past the bound (as --per-link is) they cover {share:.0%}"
            return spheres, (False, f"{within}; {said}; --max-protrusion keeps a hard bound")
        what = f"{within}, and refined past the bound {short_of(share)}"
        advice = f"give --per-link (up to {most}) for more"
    if share < target:
        return spheres, (True, f"{what}; {advice}")
    return spheres, None


def short_of(share: float) -> str:
    """A coverage below its target as a whole percentage rounded down: 89.96 % is '89%', never
    the '90%' that reads as the target met."""
    return f"{math.floor(share * 100)}%"
