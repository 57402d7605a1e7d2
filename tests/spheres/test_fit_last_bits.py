"""A fit amplifies differences in its input: a mesh placed in its link frame by another
machine's BLAS (its last bits differ) must still give the same spheres."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

import xrdf_tools.robot.link_geometry as link_geometry
from tests.robots import robot_urdf
from xrdf_tools.spheres import fit_link_spheres
from xrdf_tools.util.fixed_order import transform_points


def _one_last_bit_off(seed: int) -> Any:
    """``transform_points`` as another machine might compute it: each coordinate left alone,
    or one unit in the last place up or down."""
    rng = np.random.default_rng(seed)

    def placed(T: Any, points: Any) -> np.ndarray:
        v = transform_points(T, points)
        step = rng.integers(-1, 2, v.shape)
        return np.where(step == 0, v, np.nextafter(v, np.where(step > 0, np.inf, -np.inf)))

    return placed


@pytest.mark.parametrize(
    ("robot", "links"), [("panda", ["panda_link3", "panda_hand"]), ("ur5", ["shoulder_link"])]
)
def test_a_last_bit_in_the_mesh_changes_no_sphere(
    monkeypatch: pytest.MonkeyPatch, robot: str, links: list[str]
) -> None:
    urdf = robot_urdf(robot)
    exact, _ = fit_link_spheres(urdf, links=links)
    for seed in (1, 2):
        monkeypatch.setattr(link_geometry, "transform_points", _one_last_bit_off(seed))
        noisy, _ = fit_link_spheres(urdf, links=links)
        assert noisy == exact, (robot, seed)
    assert all(exact[name] for name in links)


def _components_in_another_order(seed: int) -> Any:
    """``trimesh.graph.connected_components`` as another machine's sort leaves it: each
    component's faces in another order (numpy's unstable argsort breaks ties one way with
    its AVX-512 sort and another way without)."""
    import trimesh

    found = trimesh.graph.connected_components
    rng = np.random.default_rng(seed)

    def shuffled(*args: Any, **kwargs: Any) -> list[np.ndarray]:
        return [rng.permutation(np.asarray(c)) for c in found(*args, **kwargs)]

    return shuffled


def test_the_order_a_sort_leaves_a_parts_bodies_in_changes_no_sphere(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """UR5's visual shoulder mesh (COLLADA) is overlapping bodies, unioned: the order of each
    body's faces must not follow the tie-breaking of the machine's sort."""
    import trimesh

    urdf = robot_urdf("ur5")
    links = ["shoulder_link"]
    exact, _ = fit_link_spheres(urdf, links=links, source="visual")
    monkeypatch.setattr(trimesh.graph, "connected_components", _components_in_another_order(1))
    shuffled, _ = fit_link_spheres(urdf, links=links, source="visual")
    assert shuffled == exact
    assert exact["shoulder_link"]
