"""Exact point-to-surface distance (the protrusion and gap metrics): against a plain loop
over every triangle, and closed forms in each region of a triangle."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
import pytest

from tests.odd_meshes import fan_capped_cylinder, fan_cone
from tests.robots import robot_urdf


def _ur5_forearm() -> object:
    from xrdf_tools.spheres.geometry import load_link_geometry

    geoms, _ = load_link_geometry(robot_urdf("ur5"), links=["forearm_link"])
    return geoms["forearm_link"].solid


@pytest.mark.parametrize(
    "mesh_of", [_ur5_forearm, lambda: fan_cone(1200), lambda: fan_capped_cylinder(300)]
)
@pytest.mark.parametrize(
    "leaf, frontier, share, waste, seeds",
    [(8, 1 << 20, 1 / 64, 8.0, 3), (1, 64, 1 / 8, 1.0, 1), (32, 1 << 20, 1.0, 1e9, 1)],
)
def test_surface_distance_is_the_smallest_point_triangle_distance(
    mesh_of: Callable[[], object],
    leaf: int,
    frontier: int,
    share: float,
    waste: float,
    seeds: int,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """The pruned, blocked distance equals a plain loop over every triangle (and is never
    above trimesh's closest-point distance, which can overshoot by micrometres): on a real
    link and on CAD-style slivers (a fan cone, a shaft with fan caps), with the tree's
    leaves and frontier as shipped, tiny (every frontier split, every sliver and broad
    triangle cut into cells of an eighth of the part) or huge (nothing cut)."""
    from trimesh import proximity

    from xrdf_tools.spheres import box_tree, distance
    from xrdf_tools.spheres.distance import _point_triangle_distance, surface_distance

    monkeypatch.setattr(box_tree, "LEAF", leaf)
    monkeypatch.setattr(box_tree, "FRONTIER", frontier)
    monkeypatch.setattr(distance, "_PIECE_SHARE", share)
    monkeypatch.setattr(distance, "_BOX_WASTE", waste)
    monkeypatch.setattr(distance, "_SEEDS", seeds)
    mesh: Any = mesh_of()
    assert len(mesh.faces) > distance._FEW_TRIANGLES  # a mesh whose triangles may be cut
    rng = np.random.default_rng(5)
    near, face = mesh.sample(60, return_index=True)
    points = np.vstack(
        [
            rng.uniform(mesh.bounds[0] - 0.05, mesh.bounds[1] + 0.05, size=(60, 3)),
            near + mesh.face_normals[face] * rng.uniform(-0.004, 0.004, (60, 1)),
            mesh.vertices[:5],
        ]
    )
    ours = surface_distance(mesh, points)
    loop = np.array(
        [
            _point_triangle_distance(np.repeat(p[None], len(mesh.faces), 0), mesh.triangles).min()
            for p in points
        ]
    )
    np.testing.assert_allclose(ours, loop, rtol=0, atol=1e-12)
    _, theirs, _ = proximity.closest_point(mesh, points)
    assert np.all(ours <= theirs + 1e-12)


def test_the_box_tree_finds_every_box_within_reach(monkeypatch: pytest.MonkeyPatch) -> None:
    """Every (point, box) pair whose box lies within the point's reach, each once, and no
    other: long thin boxes across and along the axes, points inside boxes and far away,
    reaches of zero, against a plain test of every pair; frontiers split to a few pairs."""
    from xrdf_tools.spheres import box_tree

    monkeypatch.setattr(box_tree, "FRONTIER", 50)
    rng = np.random.default_rng(11)
    lo = rng.uniform(-1, 1, size=(300, 3))
    hi = lo + rng.uniform(0, 0.05, size=(300, 3)) * rng.choice([1.0, 40.0], size=(300, 3))
    pts = np.vstack([rng.uniform(-2, 2, size=(80, 3)), 0.5 * (lo[:20] + hi[:20])])
    reach = rng.uniform(0, 0.5, size=len(pts))
    reach[::7] = 0.0
    found = [
        (int(p), int(b))
        for pi, box in box_tree.BoxTree(lo, hi).within(pts, reach)
        for p, b in zip(pi, box, strict=True)
    ]
    gap = np.maximum(np.maximum(lo[None] - pts[:, None], pts[:, None] - hi[None]), 0.0)
    want = {
        (int(p), int(b))
        for p, b in zip(*np.nonzero((gap**2).sum(2) <= reach[:, None] ** 2), strict=True)
    }
    assert len(found) == len(set(found))
    assert set(found) == want
    assert want  # the case tests something


def test_point_triangle_distance_in_every_voronoi_region() -> None:
    """Closed forms for the unit right triangle: the face, each edge and each vertex."""
    from xrdf_tools.spheres.distance import _point_triangle_distance

    tri = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    cases = {
        (0.25, 0.25, 2.0): 2.0,  # above the face
        (0.5, -1.0, 0.0): 1.0,  # beside edge ab
        (-1.0, 0.5, 0.0): 1.0,  # beside edge ac
        (1.0, 1.0, 0.0): np.sqrt(0.5) - 0.0,  # beside edge bc: distance to (0.5, 0.5)
        (-1.0, -1.0, 0.0): np.sqrt(2.0),  # vertex a
        (2.0, -1.0, 0.0): np.sqrt(2.0),  # vertex b
        (-1.0, 2.0, 1.0): np.sqrt(3.0),  # vertex c
    }
    p = np.array(list(cases))
    d = _point_triangle_distance(p, np.repeat(tri[None], len(p), 0))
    np.testing.assert_allclose(d, list(cases.values()), rtol=0, atol=1e-12)


def test_zero_area_triangles_warn_nothing_and_leave_the_distance_to_the_others() -> None:
    """Real meshes hold zero-area triangles (three points on a line): they never put the
    surface closer than the segment the three points span, and no RuntimeWarning (an error
    under the test settings) reaches the user."""
    from xrdf_tools.spheres.distance import _point_triangle_distance

    rng = np.random.default_rng(0)
    a, b = rng.normal(size=(2, 200, 3))
    c = a + (b - a) * rng.uniform(-2, 2, size=(200, 1))  # on the line through a and b
    tri = np.stack([a, b, c], axis=1)
    p = rng.normal(size=(200, 3))
    d = _point_triangle_distance(p, tri)
    u = (b - a) / np.linalg.norm(b - a, axis=1)[:, None]
    along = np.einsum("tkj,tj->tk", tri - a[:, None], u)  # the three points on the line
    t = np.clip(np.einsum("tj,tj->t", p - a, u), along.min(1), along.max(1))
    to_segment = np.linalg.norm(p - (a + t[:, None] * u), axis=1)
    assert np.all(d >= to_segment - 1e-12)
    good = np.array([[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]])
    assert _point_triangle_distance(np.array([[0.25, 0.25, 0.5]]), good)[0] == 0.5


def test_two_vertices_a_rounding_error_apart_warn_nothing() -> None:
    """A sliver whose two vertices differ in one coordinate by a rounding error (an exported
    mesh's welded corner) makes an edge weight infinite against an edge vector holding zeros:
    inf * 0 must not reach the user as a RuntimeWarning (an error under the test settings),
    and the distance is the one to the nearer of the two coinciding vertices."""
    from xrdf_tools.spheres.distance import _point_triangle_distance

    a = np.array([1.3040000451301372, 0.9470809631292422, -0.7037352358069926])
    b = np.array([0.6409637706641725, 1.5206799400568236, 0.8296882754660052])
    c = np.array([0.6409637706642067, 1.5206799400568236, 0.8296882754660052])
    p = np.array([[-3.241608554196193, 2.6716808310288207, -5.24621838425321]])
    d = _point_triangle_distance(p, np.stack([a, b, c])[None])
    segment = b - a
    t = np.clip((p[0] - a) @ segment / (segment @ segment), 0.0, 1.0)
    np.testing.assert_allclose(d, [np.linalg.norm(p[0] - (a + t * segment))], atol=1e-9)
