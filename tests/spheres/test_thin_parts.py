"""Parts thinner than a cell of the default distance grid (48 cells along the longest side):
rods, wires and plates get a grid that follows their thickness, in their own frame, and a fit
whose spheres reach past its bound says so, whatever the grid."""

from __future__ import annotations

from pathlib import Path

import pytest
import trimesh

from tests.odd_meshes import one_link_urdf
from xrdf_tools.spheres import fit as fit_module
from xrdf_tools.spheres import sphere_metrics
from xrdf_tools.spheres.fewest import REACH_SLACK, ROUNDING, reach_p95
from xrdf_tools.spheres.fit import SphereFitter
from xrdf_tools.spheres.robot_fit import fit_robot
from xrdf_tools.spheres.sdf_grid import THIN_GRID_NODES, level_radius


def _rod(length: float) -> trimesh.Trimesh:
    """A rod 2 mm thick (16 flat sides) along z."""
    return trimesh.creation.cylinder(radius=0.001, height=length, sections=16)


def _diagonal(mesh: trimesh.Trimesh) -> trimesh.Trimesh:
    """``mesh`` with its z axis turned onto (1, 1, 1)."""
    mesh.apply_transform(trimesh.geometry.align_vectors([0.0, 0.0, 1.0], [1.0, 1.0, 1.0]))
    return mesh


def _within(fitter: SphereFitter, reach: float) -> bool:
    """Whether a reach is within the fitter's bound as the past-bound note judges it."""
    return reach <= fitter.tau * (1.0 + REACH_SLACK) + ROUNDING


PARTS = {
    "0.5 m rod": lambda: _rod(0.5),
    "1 m rod": lambda: _rod(1.0),
    "0.5 m rod along (1, 1, 1)": lambda: _diagonal(_rod(0.5)),
    "0.3 x 0.3 m plate, 1 mm": lambda: trimesh.creation.box((0.3, 0.3, 0.001)),
}


@pytest.mark.parametrize("name", list(PARTS))
def test_spheres_of_a_thin_part_stay_within_their_bound(name: str) -> None:
    """Spheres within the default bound of a part far thinner than a 48-cell grid's cells
    (12 mm for the 0.5 m rod, 24 mm for the 1 m one, 7 mm for the plate) reached 5.7 mm past
    a 2 mm bound (the 0.5 m rod; 2.7 mm along the diagonal), or were 0.1 mm specks covering
    nothing, the level set lost between nodes (the 1 m rod, the plate). Their grid now
    follows the part's thickness in its own frame: spheres as thick as the bound allows
    (the bound plus half the part's thickness), their protrusion p95 within the bound."""
    part = PARTS[name]()
    fitter = SphereFitter(part, seed=0)
    assert fitter.sdf.values.size <= THIN_GRID_NODES
    spheres = fitter.fit(24)
    assert _within(fitter, reach_p95(fitter, spheres))
    thickest = max(s.radius for s in spheres)
    assert 0.8 * level_radius(part, fitter.tau) <= thickest <= level_radius(part, fitter.tau) + 2e-4


def test_a_diagonal_rod_gets_the_grid_of_a_straight_one() -> None:
    """The grid is laid along the part's oriented box: the rod along (1, 1, 1) has the same
    cells and node counts as the rod along z (its axis-aligned box was a 0.29 m cube)."""
    straight = SphereFitter(_rod(0.5), seed=0).sdf
    turned = SphereFitter(_diagonal(_rod(0.5)), seed=0).sdf
    assert turned.values.shape == straight.values.shape
    assert turned.step == pytest.approx(straight.step, rel=1e-9)
    assert straight.values.shape[2] > 20 * straight.values.shape[0]  # its length along z


def test_spheres_past_their_bound_are_said_whatever_the_grid(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """With the 48-cell grid (the thin grid switched off) the 0.5 m rod got 38 spheres of
    6.4 mm that reached the target "within" its 2 mm bound, protrusion p95 5.7 mm, and
    nothing was said. Spheres fitted within a bound are measured against it: a
    spheres-past-bound warning names the link and how far they reach."""
    monkeypatch.setattr(fit_module, "needs_thin_grid", lambda *_: False)
    rod = _rod(0.5)
    result = fit_robot(one_link_urdf(tmp_path, rod))
    (note,) = [d for d in result.diagnostics if d.rule == "spheres-past-bound"]
    assert note.severity.value == "warning"
    assert note.message.startswith("link 'part': 38 spheres cover 90% of its volume")
    assert "within its 2 mm default bound as its distance grid reads it, yet reaching" in (
        note.message
    )
    reach = float(note.message.split("reaching ")[1].split(" mm past it (protrusion p95)")[0])
    p95 = sphere_metrics(rod, result.spheres["part"]).protrusion_p95 * 1000
    assert reach == pytest.approx(p95, rel=0.1) and reach > 4.0


def test_a_count_within_a_bound_says_when_it_is_past_it(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """--per-link with --max-protrusion keeps every sphere within the bound: where the grid
    cannot, a spheres-past-bound warning says so."""
    from xrdf_tools.spheres.count_policy import CountPolicy

    monkeypatch.setattr(fit_module, "needs_thin_grid", lambda *_: False)
    result = fit_robot(
        one_link_urdf(tmp_path, _rod(0.5)), counts=CountPolicy(per_link=8), max_protrusion=0.002
    )
    (note,) = [d for d in result.diagnostics if d.rule == "spheres-past-bound"]
    assert note.message.startswith("link 'part': 8 spheres within its 2 mm bound as its")


@pytest.mark.slow
@pytest.mark.parametrize("name", [n for n in PARTS if n != "1 m rod"])  # test_slender_parts
def test_a_thin_part_is_within_its_bound_or_says_how_far_past(tmp_path: Path, name: str) -> None:
    """The default fit of each thin part: its protrusion p95 (the metrics' own samples) is
    within the bound, or a warning names the link and how far its spheres reach (the 0.5 m
    rod had 38 spheres reaching 5.7 mm past its 2 mm bound, and no note). The plate is a
    sheet: its note says how far its spheres reach from its faces."""
    part = PARTS[name]()
    result = fit_robot(one_link_urdf(tmp_path, part))
    p95 = sphere_metrics(part, result.spheres["part"]).protrusion_p95
    notes = [d for d in result.diagnostics if d.rule != "spheres-collision-not-visual"]
    if p95 <= 0.002 * (1.0 + REACH_SLACK) + ROUNDING:
        return
    (note,) = notes
    assert note.message.startswith("link 'part'")
    if note.rule == "spheres-sheet":
        assert "reaching" in note.message and "from its faces" in note.message
        return
    assert note.severity.value == "warning"
    assert note.rule in ("spheres-past-bound", "spheres-target-missed")
    reach = float(note.message.split("reaching ")[1].split(" mm past it (protrusion p95)")[0])
    assert reach == pytest.approx(p95 * 1000, rel=0.1)
