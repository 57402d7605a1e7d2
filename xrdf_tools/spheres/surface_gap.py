"""The default count's second criterion: no feature of a link left far from every sphere.

The fewest spheres that cover the target share of a link's *volume* (:mod:`.fewest`) can leave
a thin feature with none: Interbotix PincherX 100's forearm is a bar 28.5 mm thick with a
bracket of two thin plates at its elbow end, 3.5 % of its volume and a sixth of its surface;
15 spheres covered 90.5 % of the volume, none of them on the bracket, whose surface lay up to
31 mm from every sphere (a planner would not see it, nor keep it off an obstacle).

So the default count also asks that at most :data:`GAP_SHARE` of the link's surface lie
farther than its *reach*, :data:`GAP_THICKNESSES` times its mean thickness (2 · volume /
area: a plate's thickness, a third of a cube's side, half a rod's diameter), from every
sphere. Judged on surface samples held out of the fit (:class:`SurfaceJudge`), as the volume
is. Where the volume's spheres fall short, spheres are added one at a time
(:func:`reach_far_surface`): the sphere within the fitter's bound, centred on one of its
candidates or on a far surface sample of its own, that brings the most far surface samples
of the fit within reach, up to :data:`~.count_policy.MAX_PER_LINK` spheres. Over the 90 links
of nine arms measured (example-robot-data's Panda, UR5, Kinova, Z1, SO-101, xArm 7, TIAGo and
Talos' arm, and the PincherX), no other link has any of 20,000 surface samples beyond its
reach: the farthest reaches 1.02 of it (PincherX's upper arm), the largest 95th percentile is
0.63 of it (xArm 7's base); the PincherX forearm has 12.7 % of its surface beyond it, its 95th
percentile at 2.0.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from ..util.arrays import BoolArray
from ..xrdf.model import Sphere

if TYPE_CHECKING:
    from .fit import SphereFitter

__all__ = [
    "GAP_SHARE",
    "GAP_THICKNESSES",
    "HELD_OUT_SURFACE",
    "Reached",
    "SurfaceJudge",
    "mean_thickness",
    "reach_far_surface",
]

#: A surface point is far when it lies farther than this many mean thicknesses of its link
#: (2 · volume / area) from every sphere.
GAP_THICKNESSES = 1.0
#: The default count leaves at most this share of a link's (held-out) surface far.
GAP_SHARE = 0.01
#: Surface samples held out of the fit to judge the far share.
HELD_OUT_SURFACE = 3000
#: An added sphere has at least this share of the bound as its radius: any centre inside or on
#: the solid has that much room, so a smaller one is a distance grid's misreading of a part
#: thinner than its cells, and a speck of a sphere brings the surface within reach of nothing.
MIN_RADIUS = 0.5
#: Appended to the fitter's seed for the held-out surface samples' generator.
_SURFACE_STREAM = 0x535246


def mean_thickness(fitter: SphereFitter) -> float:
    """2 · volume / area of the fitter's solid (0 without area)."""
    area = float(fitter.solid.area)
    return 2.0 * fitter.volume / area if area > 0.0 else 0.0


class SurfaceJudge:
    """Surface samples of a fitter's solid that its fit never sees (on the kept side of its
    clip planes), from a generator seeded from the fitter's seed, and the reach they are
    judged by (:data:`GAP_THICKNESSES` mean thicknesses)."""

    def __init__(self, fitter: SphereFitter, samples: int = HELD_OUT_SURFACE) -> None:
        from .metrics import sample_surface

        seed = [int(s) for s in np.atleast_1d(np.asarray(fitter.seed, dtype=np.int64))]
        rng = np.random.default_rng([*seed, _SURFACE_STREAM])
        self.points = fitter.kept(sample_surface(fitter.solid, samples, rng))
        self.reach = GAP_THICKNESSES * mean_thickness(fitter)

    def far(self, spheres: tuple[Sphere, ...]) -> BoolArray:
        """Which samples lie farther than the reach from every sphere."""
        from .metrics import inside_any, sphere_arrays

        centers, radii = sphere_arrays(spheres)
        return ~inside_any(self.points, centers, radii + self.reach)

    def far_share(self, spheres: tuple[Sphere, ...]) -> float:
        """The share of the samples farther than the reach from every sphere (0 without
        samples)."""
        return float(self.far(spheres).mean()) if len(self.points) else 0.0

    def largest_gap(self, spheres: tuple[Sphere, ...]) -> float:
        """The largest distance of a sample from the spheres."""
        from .metrics import gap_to_spheres, sphere_arrays

        if not len(self.points) or not spheres:
            return 0.0
        return float(gap_to_spheres(self.points, *sphere_arrays(spheres)).max())


class Reached(NamedTuple):
    """What :func:`reach_far_surface` did: ``before`` spheres left the share ``far_before``
    of the surface beyond ``reach`` (metres, up to ``gap_before`` from every sphere);
    ``added`` more leave ``far_after`` (up to ``gap_after``), ``capped`` when they stopped
    at the most spheres a link gets. ``met``: at most :data:`GAP_SHARE` is left."""

    before: int
    added: int
    reach: float
    far_before: float
    gap_before: float
    far_after: float
    gap_after: float
    capped: bool

    @property
    def met(self) -> bool:
        return self.far_after <= GAP_SHARE

    def said(self, link: str, bound: float, own: bool) -> str:
        """The note on it (``bound``: the fitter's protrusion bound, ``own``: the user's)."""
        mm = 1000.0
        left = (
            f"{_share(self.far_before)} of its surface lay farther than {self.reach * mm:.3g} mm "
            f"(its mean thickness, 2 · volume / area) from its {self.before} spheres, up to "
            f"{self.gap_before * mm:.3g} mm: a part of it (a thin bracket, a plate, a rim) had "
            "no sphere near"
        )
        if self.met:
            return f"link '{link}': {left}; {self.added} more bring it within reach"
        which = "" if own else " default"
        within = f"within its {bound * mm:.3g} mm{which} bound"
        if self.capped:
            tried = f"{self.added} more, the most a link gets, {within},"
            advice = "a larger --max-protrusion gives larger spheres, so fewer"
        else:
            tried = f"{self.added} more {within},"
            advice = (
                "no other sphere within the bound brings any of the rest closer: the fit finds "
                "no volume there to centre one in (faces enclosing nothing?)"
            )
        return (
            f"link '{link}': {left}; {tried} leave {_share(self.far_after)} of it out of "
            f"reach, up to {self.gap_after * mm:.3g} mm; {advice}"
        )


def _share(share: float) -> str:
    return f"{share:.1%}" if share < 0.1 else f"{share:.0%}"


def reach_far_surface(
    fitter: SphereFitter, spheres: tuple[Sphere, ...], most: int, bound: float
) -> tuple[tuple[Sphere, ...], Reached | None]:
    """``spheres`` with spheres added until at most :data:`GAP_SHARE` of the held-out
    surface (:class:`SurfaceJudge`) lies beyond the reach, up to ``most`` spheres in all, and
    what was done (None when nothing was far). Each added sphere is the largest within
    ``bound`` (the link's protrusion bound: the fitter is re-bound to it, a fit refined past
    it having left it elsewhere) at one of the fitter's candidates' centres or at one of its
    own surface samples then far, whichever brings the most of its far surface samples within
    reach (ties: the first); it stops early when none brings any."""
    judge = SurfaceJudge(fitter)
    far_before = judge.far_share(spheres)
    if far_before <= GAP_SHARE or fitter.empty or judge.reach <= 0.0:
        return spheres, None
    if fitter.tau != bound or fitter.room != bound:
        fitter.widen(bound)  # the grid a fit within the bound has (a coarser one may miss a plate)
        fitter.rebound(bound)
    surface = fitter.points[fitter.n_volume :]
    far_fit = _beyond(fitter, spheres, judge.reach)
    centers = np.concatenate([fitter.cand_c, surface[far_fit]])
    radii = np.concatenate([fitter.cand_r, fitter.max_radius(surface[far_fit])])
    cover = fitter.covers(centers, radii + judge.reach)[:, fitter.n_volume :]
    cover[radii < MIN_RADIUS * bound] = False  # a point inside or on the solid has the bound's room
    added: list[Sphere] = []
    share = far_before
    while share > GAP_SHARE and len(spheres) + len(added) < most:
        gain = (cover & far_fit).sum(1)
        best = int(np.argmax(gain))
        if gain[best] == 0:
            break
        added += fitter.as_spheres(centers[best : best + 1], radii[best : best + 1])
        far_fit &= ~cover[best]
        share = judge.far_share((*spheres, *added))
    out = (*spheres, *added)
    gaps = (judge.largest_gap(spheres), judge.largest_gap(out))
    capped = len(out) >= most
    reached = Reached(
        len(spheres), len(added), judge.reach, far_before, gaps[0], share, gaps[1], capped
    )
    return out, reached


def _beyond(fitter: SphereFitter, spheres: tuple[Sphere, ...], reach: float) -> BoolArray:
    """Which of the fitter's own surface samples lie farther than ``reach`` from every
    sphere."""
    from .metrics import sphere_arrays

    centers, radii = sphere_arrays(spheres)
    if not len(radii):
        return np.ones(len(fitter.points) - fitter.n_volume, dtype=bool)
    return np.asarray(~fitter.covers(centers, radii + reach)[:, fitter.n_volume :].any(0))
