"""The default count of a link: the fewest spheres reaching the coverage target.

:func:`fewest_reaching` finds the fewest spheres (up to :data:`AUTO_MAX_PER_LINK`) that cover
the target share of a link's volume within its protrusion bound. A part the bound cannot cover
with so few (a disc 80 mm wide and 10 mm thick under a 2.2 mm default bound: 16 spheres cover
43 % of it) is refined past its default bound instead (:func:`past_the_bound`), as a count
given with ``--per-link`` is: coverage against the 95th percentile of the protrusion (the disc:
96 % at 5.9 mm). A bound the user gives stays hard.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..xrdf.model import Sphere

if TYPE_CHECKING:
    from .fit import SphereFitter

__all__ = ["AUTO_MAX_PER_LINK", "fewest_reaching", "past_the_bound"]

#: The most spheres a link gets by default.
AUTO_MAX_PER_LINK = 16


def fewest_reaching(fitter: SphereFitter, target: float) -> tuple[tuple[Sphere, ...], float]:
    """The fewest refined spheres (up to AUTO_MAX_PER_LINK) covering ``target`` of the volume
    samples: the greedy count is an upper bound (refinement only adds coverage), and a
    bisection below it with refined fits finds the fewest."""
    curve = fitter.greedy(AUTO_MAX_PER_LINK)[1]
    reach = [k + 1 for k, c in enumerate(curve) if c >= target]
    hi = reach[0] if reach else AUTO_MAX_PER_LINK
    fits = {hi: fitter.fit(hi)}
    lo = 0  # lo spheres do not reach the target (0 never does), hi do (or hi is the cap)
    while hi - lo > 1:
        mid = (lo + hi) // 2
        fits[mid] = fitter.fit(mid)
        if fitter.covered_share(fits[mid]) >= target:
            hi = mid
        else:
            lo = mid
    return fits[hi], fitter.covered_share(fits[hi])


def past_the_bound(fitter: SphereFitter, k: int) -> tuple[tuple[Sphere, ...], float]:
    """``k`` spheres refined past the fitter's default bound (:func:`~.refine.refined_fit`,
    its distance grid first widened as a count-given fit's is) and the share of the volume
    samples they cover."""
    from .fit import default_max_protrusion
    from .refine import START_BOUNDS, refined_fit

    fitter.widen(max(START_BOUNDS) * default_max_protrusion(fitter.solid))
    spheres = refined_fit(fitter, k)
    return spheres, fitter.covered_share(spheres)
