"""A fitter re-bound to another protrusion bound, and the bound chosen for a given count
(:func:`~xrdf_tools.spheres.fit.bound_for_coverage`), on real Panda meshes."""

from __future__ import annotations

import numpy as np
import pytest

from tests.robots import robot_urdf
from xrdf_tools.spheres import sphere_metrics
from xrdf_tools.spheres.count_policy import CountPolicy
from xrdf_tools.spheres.distance import surface_distance
from xrdf_tools.spheres.fit import PROBE_STRIDE, SphereFitter, bound_for_coverage
from xrdf_tools.spheres.geometry import LinkGeometry, load_link_geometry
from xrdf_tools.spheres.inside import points_inside
from xrdf_tools.spheres.metrics import fibonacci_directions
from xrdf_tools.spheres.robot_fit import fit_robot
from xrdf_tools.spheres.sdf_grid import level_points
from xrdf_tools.util.errors import XrdfToolsError
from xrdf_tools.xrdf.model import Sphere


@pytest.fixture(scope="module")
def panda() -> dict[str, LinkGeometry]:
    geoms, _ = load_link_geometry(robot_urdf("panda"), links=["panda_link1", "panda_leftfinger"])
    return geoms


def _max_protrusion(solid: object, spheres: tuple[Sphere, ...]) -> float:
    """The largest distance outside ``solid`` of 400 points on each sphere, one sphere at a
    time (exact point-mesh distances)."""
    worst = 0.0
    directions = fibonacci_directions(400)
    for s in spheres:
        points = np.asarray(s.center) + s.radius * directions
        outside = points[~points_inside(solid, points)]  # type: ignore[arg-type]
        if len(outside):
            worst = max(worst, float(surface_distance(solid, outside).max()))  # type: ignore[arg-type]
    return worst


def test_a_finger_with_one_sphere_gets_the_bound_that_covers_it(
    panda: dict[str, LinkGeometry],
) -> None:
    """At the default bound (2 mm) one sphere covers about a quarter of a Panda finger; the
    bound is raised until it covers 90 %, and the sphere stays within the raised bound."""
    solid = panda["panda_leftfinger"].solid
    fitter = SphereFitter(solid, seed=0)
    tau0 = fitter.tau
    assert fitter.covered_share(fitter.fit(1)) < 0.5
    spheres = bound_for_coverage(fitter, 1, 0.9)
    assert len(spheres) == 1
    assert fitter.tau > 3 * tau0
    assert fitter.covered_share(spheres) >= 0.9
    assert sphere_metrics(solid, spheres, samples=4000).coverage >= 0.85
    # the grid's level set is interpolated: within half a cell, plus the 0.1 mm rounding up
    assert _max_protrusion(solid, spheres) <= fitter.tau + fitter.sdf.step / 2 + 1e-4


def test_a_count_that_covers_more_than_asked_gets_a_tighter_bound(
    panda: dict[str, LinkGeometry],
) -> None:
    """Twelve spheres on panda_link1 cover more than 95 % at the default bound; the bound is
    lowered to the smallest that still covers 95 %, and the spheres protrude less."""
    solid = panda["panda_link1"].solid
    plain_fitter = SphereFitter(solid, seed=0)
    plain = plain_fitter.fit(12)
    assert plain_fitter.covered_share(plain) > 0.97
    fitter = SphereFitter(solid, seed=0)
    spheres = bound_for_coverage(fitter, 12, 0.95)
    assert fitter.tau < plain_fitter.tau
    assert fitter.covered_share(spheres) >= 0.95
    assert _max_protrusion(solid, spheres) <= fitter.tau + fitter.sdf.step / 2 + 1e-4
    assert _max_protrusion(solid, spheres) < _max_protrusion(solid, plain)


def test_rebinding_below_the_grid_room_and_back_gives_the_same_candidates(
    panda: dict[str, LinkGeometry],
) -> None:
    fitter = SphereFitter(panda["panda_link1"].solid, seed=0)
    tau0, radii, room = fitter.tau, fitter.cand_r.copy(), fitter.room
    fitter.rebound(0.6 * tau0)
    assert np.all(fitter.cand_r <= radii) and fitter.cand_r.sum() < radii.sum()
    fitter.rebound(tau0)
    assert np.array_equal(fitter.cand_r, radii) and fitter.room == room


def _greedy_share_by_loop(fitter: SphereFitter, tau: float, k: int) -> float:
    """:meth:`SphereFitter.greedy_share`, one candidate and one pick at a time."""
    level = level_points(fitter.sdf, tau)
    vol, surf = fitter.points[: fitter.n_volume], fitter.points[fitter.n_volume :]
    covers = []
    for c in fitter.cand_c[::PROBE_STRIDE]:
        r = float(np.sqrt(((level - c) ** 2).sum(1)).min()) if fitter.sdf(c[None])[0] < tau else 0.0
        covers.append((((vol - c) ** 2).sum(1) <= r * r, ((surf - c) ** 2).sum(1) <= r * r))
    free_v = np.ones(len(vol), dtype=bool)
    free_s = np.ones(len(surf), dtype=bool)
    picked: list[int] = []
    for _ in range(k):
        gains = [
            -1.0
            if i in picked
            else int((cv & free_v).sum()) * fitter.w_volume
            + int((cs & free_s).sum()) * fitter.w_surface
            for i, (cv, cs) in enumerate(covers)
        ]
        best = int(np.argmax(gains))
        picked.append(best)
        free_v &= ~covers[best][0]
        free_s &= ~covers[best][1]
    return float((~free_v).mean())


def test_greedy_probe_equals_a_plain_loop(panda: dict[str, LinkGeometry]) -> None:
    fitter = SphereFitter(panda["panda_link1"].solid, seed=0)
    for tau, k in ((fitter.tau, 5), (0.7 * fitter.tau, 9)):
        got = fitter.greedy_share(tau, k)
        assert got == pytest.approx(
            _greedy_share_by_loop(fitter, tau, k), abs=1.5 / fitter.n_volume
        )


def test_fit_robot_searches_the_bound_only_when_asked(panda: dict[str, LinkGeometry]) -> None:
    finger = {"panda_leftfinger": panda["panda_leftfinger"]}
    default = fit_robot("", geometry=finger, counts=CountPolicy(per_link=1, refine=False)).spheres
    searched = fit_robot(
        "", geometry=finger, counts=CountPolicy(per_link=1, count_coverage=0.9)
    ).spheres
    given = fit_robot(
        "",
        geometry=finger,
        counts=CountPolicy(per_link=1, count_coverage=0.9),
        max_protrusion=0.002,
    ).spheres
    assert given == default  # a bound given is kept (the finger's default bound is 2 mm)
    solid = panda["panda_leftfinger"].solid
    covered = [
        sphere_metrics(solid, s["panda_leftfinger"], samples=3000).coverage
        for s in (default, searched)
    ]
    assert covered[0] < 0.5 < 0.85 <= covered[1]
    with pytest.raises(XrdfToolsError, match="count coverage"):
        fit_robot("", geometry=finger, counts=CountPolicy(per_link=1, count_coverage=1.5))
