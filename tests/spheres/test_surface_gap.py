"""The default count leaves no thin part of a link far from every sphere (:mod:`.surface_gap`).

The part is PincherX 100's forearm in miniature: a solid bar 28 mm thick with a bracket of two
thin plates at one end (a few percent of its volume, a tenth of its surface). The fewest
spheres covering 90 % of its volume put none on the bracket.
"""

from __future__ import annotations

from pathlib import Path

import pytest

trimesh = pytest.importorskip("trimesh")

from xrdf_tools.spheres.count_policy import CountPolicy  # noqa: E402
from xrdf_tools.spheres.metrics import sphere_metrics  # noqa: E402
from xrdf_tools.spheres.robot_fit import FitResult, fit_robot  # noqa: E402
from xrdf_tools.xrdf.model import Sphere  # noqa: E402

#: The bracket: two plates 30 x 2.5 x 22 mm at x 0 ... 28 mm, at either side of the bar.
PLATE_Y = 0.02075


def _box(extents: list[float], at: list[float]) -> trimesh.Trimesh:
    box = trimesh.creation.box(extents=extents)
    box.apply_translation(at)
    return box


@pytest.fixture(scope="module")
def bracket_urdf(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A URDF whose one link is the bar with its bracket, one closed mesh."""
    bar = _box([0.085, 0.044, 0.028], [-0.0425, 0.0, 0.0])
    plates = [_box([0.03, 0.0025, 0.022], [0.013, side * PLATE_Y, 0.0]) for side in (-1, 1)]
    part = trimesh.boolean.union([bar, *plates])
    assert part.is_watertight
    folder = tmp_path_factory.mktemp("bracket")
    part.export(folder / "forearm.stl")
    urdf = folder / "r.urdf"
    urdf.write_text(
        '<robot name="r"><link name="forearm"><collision><geometry>'
        '<mesh filename="forearm.stl"/></geometry></collision></link></robot>'
    )
    return urdf


@pytest.fixture(scope="module")
def default_fit(bracket_urdf: Path) -> FitResult:
    return fit_robot(bracket_urdf)


def _on_a_plate(sphere: Sphere) -> bool:
    """A sphere centred beyond the bar's end, beside its axis: on a plate of the bracket."""
    return sphere.center[0] > 0.0 and abs(sphere.center[1]) > 0.015


def _thickness(result: FitResult) -> float:
    solid = result.geometry["forearm"].solid
    return 2.0 * float(solid.volume) / float(solid.area)


def test_the_default_count_puts_spheres_on_a_thin_bracket(default_fit: FitResult) -> None:
    spheres = default_fit.spheres["forearm"]
    on_plates = {round(s.center[1] / PLATE_Y) for s in spheres if _on_a_plate(s)}
    assert on_plates == {-1, 1}  # each plate has a sphere (none had one)
    metrics = sphere_metrics(default_fit.geometry["forearm"].solid, spheres, samples=20000)
    thickness = _thickness(default_fit)  # 12.4 mm
    assert metrics.surface_gap_p95 < thickness  # 19.4 mm before, 7.7 mm now
    assert metrics.max_uncovered_gap < 1.5 * thickness  # 27.3 mm before, 13.9 mm now
    assert metrics.coverage >= 0.9
    [note] = [d for d in default_fit.diagnostics if d.rule == "spheres-surface-gap"]
    assert note.severity.value == "info"
    assert "link 'forearm'" in note.message and "2 more bring it within reach" in note.message


def test_the_volume_target_alone_leaves_the_bracket_bare(bracket_urdf: Path) -> None:
    alone = fit_robot(bracket_urdf, counts=CountPolicy(reach_surface=False))
    spheres = alone.spheres["forearm"]
    assert not [s for s in spheres if _on_a_plate(s)]
    metrics = sphere_metrics(alone.geometry["forearm"].solid, spheres, samples=20000)
    assert metrics.surface_gap_p95 > _thickness(alone)
    assert not [d for d in alone.diagnostics if d.rule == "spheres-surface-gap"]


def test_a_count_given_is_kept(bracket_urdf: Path) -> None:
    given = fit_robot(bracket_urdf, counts=CountPolicy(per_link=3))
    assert len(given.spheres["forearm"]) == 3
    assert not [d for d in given.diagnostics if d.rule == "spheres-surface-gap"]


def test_spheres_that_cannot_reach_it_are_said(default_fit: FitResult) -> None:
    from xrdf_tools.spheres.fewest import fewest_reaching
    from xrdf_tools.spheres.fit import SphereFitter
    from xrdf_tools.spheres.surface_gap import reach_far_surface

    fitter = SphereFitter(default_fit.geometry["forearm"].solid, seed=0)
    spheres, _share = fewest_reaching(fitter, 0.9)
    more, reached = reach_far_surface(fitter, spheres, most=len(spheres) + 1, bound=fitter.tau)
    assert reached is not None and not reached.met
    assert len(more) == len(spheres) + 1 and reached.added == 1
    assert reached.far_after < reached.far_before
    said = reached.said("forearm", fitter.tau, own=False)
    assert "1 more, the most a link gets, within its" in said and "default bound" in said
    assert "a larger --max-protrusion gives larger spheres, so fewer" in said
