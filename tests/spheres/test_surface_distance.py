"""Exact point-to-surface distance (the protrusion and gap metrics): against a plain loop
over every triangle, and closed forms in each region of a triangle."""

from __future__ import annotations

import numpy as np
import pytest

from tests.robots import robot_urdf


@pytest.mark.parametrize(
    "nearest, small_share, dense_max", [(32, 0.98, 2048), (1, 0.5, 2048), (32, 0.5, 8)]
)
def test_surface_distance_is_the_smallest_point_triangle_distance(
    nearest: int, small_share: float, dense_max: int, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The pruned, blocked distance equals a plain loop over every triangle (and is never
    above trimesh's closest-point distance, which can overshoot by micrometres): with the
    k-d tree's first answer enough for most points, and with every point asking it again and
    half the triangles tested against every point, or only the 8 largest (the cap that keeps
    a mesh of millions of like triangles from testing each point against 2 % of them)."""
    from trimesh import proximity

    from xrdf_tools.spheres import distance
    from xrdf_tools.spheres.distance import _point_triangle_distance, surface_distance

    monkeypatch.setattr(distance, "_NEAREST", nearest)
    monkeypatch.setattr(distance, "_SMALL_SHARE", small_share)
    monkeypatch.setattr(distance, "_DENSE_MAX", dense_max)
    from xrdf_tools.spheres.geometry import load_link_geometry

    geoms, _ = load_link_geometry(robot_urdf("ur5"), links=["forearm_link"])
    mesh = geoms["forearm_link"].solid
    assert len(mesh.faces) > 2 * distance._DENSE_TRIANGLES  # the k-d tree path
    rng = np.random.default_rng(5)
    points = rng.uniform(mesh.bounds[0] - 0.05, mesh.bounds[1] + 0.05, size=(120, 3))
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
