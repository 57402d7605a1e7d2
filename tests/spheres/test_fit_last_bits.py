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
