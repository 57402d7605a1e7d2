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
from dataclasses import dataclass
from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from ..xrdf.model import Sphere

if TYPE_CHECKING:
    from .fit import SphereFitter

__all__ = [
    "AUTO_MAX_PER_LINK",
    "SLENDER_MAX_PER_LINK",
    "HeldOut",
    "Note",
    "Slender",
    "default_fit",
    "default_most",
    "fewest_reaching",
    "overshoot",
    "past_grid_note",
    "past_the_bound",
    "reach_p95",
    "short_of",
    "slender",
]

#: The most spheres a link gets by default.
AUTO_MAX_PER_LINK = 16
#: The most a slender part (:func:`slender`) gets by default: one sphere per thickness of
#: its length up to this many.
SLENDER_MAX_PER_LINK = 48
#: A part read as a tube is slender when it is more than this many times as long as thick.
SLENDER_RATIO = 16.0
#: The neighbours of a volume sample within twice a part's thickness, and within four times
#: it: about twice as many along a tube, four times as many over a plate or a shell's wall,
#: eight times as many in a solid, more than twice as many over a bag of separate small
#: bodies (the next ones come into reach). Under this growth the part is a tube.
TUBE_GROWTH = 2.8
#: Union-boundary samples behind the protrusion a past-bound note states.
REACH_SAMPLES = 4000
#: Spheres fitted within a bound are past it when their protrusion p95 exceeds it by more
#: than this share of it (the fit's own precision: a hard bound makes every sphere reach it,
#: and real links' p95 reach 0.9-1.0 of it) plus :data:`ROUNDING` (a radius is rounded up).
REACH_SLACK = 0.1
#: How far a rounded radius may grow (metres).
ROUNDING = 1e-4
#: Volume samples held out of the fit to judge its coverage.
HELD_OUT_SAMPLES = 6000
#: The judged share is the held-out share less this many standard errors (one-sided 95 %).
HELD_OUT_Z = 1.645
#: Appended to the fitter's seed for the held-out samples' generator.
_HELD_OUT_STREAM = 0x4A5544
#: Appended to the fitter's seed for the reach's samples.
_REACH_STREAM = 0x524541


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
    fitter: SphereFitter, target: float, judge: HeldOut | None = None, most: int | None = None
) -> tuple[tuple[Sphere, ...], float]:
    """The fewest spheres (up to ``most``, by default :func:`default_most`) whose judged
    share (``judge``, else a new :class:`HeldOut`) reaches ``target``, and that share. The
    first count whose greedy cover reaches the target on the fit's own samples is where the
    search starts: counts are added from there while the judge says it falls short, and a
    bisection below it finds the fewest that the judge accepts."""
    judge = judge or HeldOut(fitter)
    most = default_most(fitter) if most is None else most
    curve = fitter.greedy(most)[1]
    reach = [k + 1 for k, c in enumerate(curve) if c >= target]
    hi = reach[0] if reach else most
    fits = {hi: fitter.fit(hi)}
    shares = {hi: judge.share(fits[hi])}
    while shares[hi] < target and hi < most:
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


class Note(NamedTuple):
    """What a default fit says: ``text``, a warning when ``warn``; ``missed`` when the
    coverage target is not reached (else the spheres were refined past the bound)."""

    missed: bool
    text: str
    warn: bool


def default_fit(
    fitter: SphereFitter, target: float, *, past: bool, most: int
) -> tuple[tuple[Sphere, ...], Note | None]:
    """A link's spheres without a count: the fewest reaching ``target`` within the fitter's
    bound (up to :func:`default_most`), else (``past``: the bound is the default, not the
    user's) as many refined past it, with how far they then reach. Also what to say, when
    something is (``most``: the largest --per-link, named in the advice). A slender part
    refined past the bound at its most spheres is a warning: its spheres are far thicker
    than it."""
    judge = HeldOut(fitter)
    tube = slender(fitter)
    spheres, share = fewest_reaching(fitter, target, judge, _most_of(tube))
    what = f"{len(spheres)} spheres cover {short_of(share)} of its volume (target {target:.0%})"
    advice = "raise --max-protrusion or give --per-link for more"
    if share < target and past:
        capped = tube is not None  # short of the target: at its most spheres
        within = tube.said() if tube is not None else ""
        count = f"{len(spheres)} spheres" + (", the most it gets by default," if capped else "")
        within += (
            f"{count} within its {fitter.tau * 1000:.3g} mm default bound cover "
            f"{short_of(share)} of it (target {target:.0%})"
        )
        spheres, share = past_the_bound(fitter, len(spheres), judge)
        reached = _reaching(reach_p95(fitter, spheres))
        more = f"give --per-link (up to {most}) for more" + (", thinner spheres" if capped else "")
        if share >= target:
            said = f"refined past the bound (as --per-link is) they cover {share:.0%}, {reached}"
            hard = (f"{more}; " if capped else "") + "--max-protrusion keeps a hard bound"
            return spheres, Note(False, f"{within}; {said}; {hard}", capped)
        what = f"{within}, and refined past the bound {short_of(share)}, {reached}"
        advice = more
    reach = None if share < target and past else overshoot(fitter, spheres)  # not said yet
    if reach is not None:
        what += f", {_past_grid(fitter, reach, past)}"
    if share < target:
        return spheres, Note(True, f"{what}; {advice}", True)
    if reach is not None:
        return spheres, Note(False, f"{what}; {_FINER}", True)
    return spheres, None


#: The advice of a note on spheres past a bound the distance grid did not resolve.
_FINER = "give --per-link for more spheres, or a larger --max-protrusion"


def overshoot(fitter: SphereFitter, spheres: tuple[Sphere, ...]) -> float | None:
    """How far ``spheres``, fitted within the fitter's bound, reach past the solid
    (:func:`reach_p95`) when that is past the bound by more than :data:`REACH_SLACK` of it
    and :data:`ROUNDING` (their radii come from the distance grid's level set: a part the
    grid does not resolve gets spheres past it); None within it."""
    if not spheres:
        return None
    reach = reach_p95(fitter, spheres)
    return reach if reach > fitter.tau * (1.0 + REACH_SLACK) + ROUNDING else None


def past_grid_note(fitter: SphereFitter, spheres: tuple[Sphere, ...], own: bool) -> str | None:
    """What to say of spheres fitted within the fitter's bound (``own``: the user's, else the
    default) when they reach past it (:func:`overshoot`); None when they do not."""
    reach = overshoot(fitter, spheres)
    if reach is None:
        return None
    return f"{len(spheres)} spheres {_past_grid(fitter, reach, not own)}; {_FINER}"


def _reaching(reach: float) -> str:
    return f"reaching {reach * 1000:.3g} mm past it (protrusion p95)"


def _past_grid(fitter: SphereFitter, reach: float, default: bool) -> str:
    """Spheres fitted within the bound that still reach ``reach`` past the solid."""
    which = "default bound" if default else "bound"
    return (
        f"within its {fitter.tau * 1000:.3g} mm {which} as its distance grid reads it, yet "
        f"{_reaching(reach)}: the part is finer than the grid resolves"
    )


@dataclass(frozen=True)
class Slender:
    """A part read as a tube: its length (area² / (4π volume)) and thickness (4 volume /
    area), exact for a round rod."""

    length: float
    thickness: float

    @property
    def most(self) -> int:
        """The most spheres it gets by default: one per thickness of its length, at least
        :data:`AUTO_MAX_PER_LINK`, at most :data:`SLENDER_MAX_PER_LINK`."""
        per_thickness = math.ceil(self.length / self.thickness - 1e-9)
        return min(SLENDER_MAX_PER_LINK, max(AUTO_MAX_PER_LINK, per_thickness))

    def said(self) -> str:
        """The start of a note on it."""
        mm = 1000.0
        ratio = self.length / self.thickness
        return (
            f"a slender part (about {self.length * mm:.0f} mm long, {self.thickness * mm:.3g} mm "
            f"thick: {ratio:.0f} times as long as thick): "
        )


def slender(fitter: SphereFitter) -> Slender | None:
    """The fitter's solid as a :class:`Slender` tube (a rod, a finger, a mast, a coiled
    cable) when it is one: over :data:`SLENDER_RATIO` times as long as thick, as a tube and
    along its longest side (UR5's upper arm, 20 times as long as thick as a tube, is 7 times
    along its longest side), and its volume
    samples spread along a line: their neighbours within twice its thickness and within four
    times it grow by less than :data:`TUBE_GROWTH` (a plate's or a hollow part's grow about
    four times: as long as thick read as tubes, they are not)."""
    from scipy.spatial import cKDTree

    area = float(fitter.solid.area)
    if fitter.volume <= 0.0 or area <= 0.0:
        return None
    tube = Slender(area * area / (4.0 * math.pi * fitter.volume), 4.0 * fitter.volume / area)
    points = fitter.points[: fitter.n_volume]
    longest = float(np.max(fitter.solid.extents))
    if min(tube.length, longest) < SLENDER_RATIO * tube.thickness or len(points) < 2:
        return None  # compact: its neighbours within four times its thickness are all of it
    tree = cKDTree(points)
    near, far = (  # each sample's neighbours, itself left out
        float(np.sum(tree.query_ball_point(points, r * tube.thickness, return_length=True) - 1))
        for r in (2.0, 4.0)
    )
    return tube if 0.0 < far < TUBE_GROWTH * near else None


def default_most(fitter: SphereFitter) -> int:
    """The most spheres the default count gives the fitter's solid: :data:`AUTO_MAX_PER_LINK`,
    or a slender part's own (:attr:`Slender.most`)."""
    return _most_of(slender(fitter))


def _most_of(tube: Slender | None) -> int:
    return AUTO_MAX_PER_LINK if tube is None else tube.most


def reach_p95(fitter: SphereFitter, spheres: tuple[Sphere, ...]) -> float:
    """How far ``spheres`` reach past the fitter's solid: the 95th percentile of the
    protrusion of their union's boundary (as the metrics measure it, on samples of its own,
    seeded from the fitter's seed)."""
    from .metrics import outside_distance, sphere_arrays, union_boundary_samples, weighted_quantile

    seed = [int(s) for s in np.atleast_1d(np.asarray(fitter.seed, dtype=np.int64))]
    rng = np.random.default_rng([*seed, _REACH_STREAM])
    points, weights = union_boundary_samples(*sphere_arrays(spheres), REACH_SAMPLES, rng)
    return weighted_quantile(outside_distance(fitter.solid, points), weights, 0.95)


def short_of(share: float) -> str:
    """A coverage below its target as a whole percentage rounded down: 89.96 % is '89%', never
    the '90%' that reads as the target met."""
    return f"{math.floor(share * 100)}%"
