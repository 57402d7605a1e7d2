"""The PNG's translucent sphere polygons are drawn in an order that is the same on every
machine: by a depth computed term by term, equal depths by index (the example-robot-data
Panda with fixtures/panda/panda.xrdf, from the front, where many depths are equal)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pytest

from tests.paths import FIXTURES
from tests.robots import robot_urdf
from xrdf_tools.robot.kinematics import build_kinematic_model
from xrdf_tools.robot.urdf_source import load_urdf
from xrdf_tools.viz import Picture, Scene, build_scene, render, sample_configurations
from xrdf_tools.viz.png import VIEWS, depth_ranks, draw_png, sphere_quads
from xrdf_tools.xrdf.io import load_xrdf


@pytest.fixture(scope="module")
def scene() -> Scene:
    pytest.importorskip("matplotlib")
    urdf_path = robot_urdf("panda")
    urdf, xrdf = load_urdf(urdf_path), load_xrdf(FIXTURES / "panda" / "panda.xrdf")
    kin, _ = build_kinematic_model(urdf, xrdf)
    q = sample_configurations(kin, xrdf, 0, seed=0)  # the default pose only
    return build_scene(urdf, xrdf, q, kinematic_model=kin, meshes="none", urdf_path=urdf_path)


def _argsort_breaking_ties_the_other_way(original: Any) -> Any:
    """``np.argsort`` as another machine's unstable sort may leave it: equal values in
    descending index order (a stable sort, ``kind`` given, is left alone)."""

    def argsort(a: Any, axis: int = -1, kind: Any = None, order: Any = None, **kw: Any) -> Any:
        values = np.asarray(a)
        if kind is not None or values.ndim != 1:
            return original(a, axis=axis, kind=kind, order=order, **kw)
        backwards = original(values[::-1], kind="stable")
        return len(values) - 1 - backwards

    return argsort


def test_the_picture_does_not_follow_how_the_sort_breaks_ties(
    scene: Scene, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    picture = Picture(view=VIEWS["front"], legend="off", size_px=240)
    render(scene, "png", tmp_path / "a.png", picture=picture)
    monkeypatch.setattr(np, "argsort", _argsort_breaking_ties_the_other_way(np.argsort))
    render(scene, "png", tmp_path / "b.png", picture=picture)
    assert (tmp_path / "a.png").read_bytes() == (tmp_path / "b.png").read_bytes()


def test_depth_ranks_match_a_plain_loop_and_matplotlibs_depths(scene: Scene) -> None:
    fig = draw_png(scene, legend="off", view=VIEWS["front"])
    ax: Any = fig.axes[0]
    fig.canvas.draw()
    M = np.asarray(ax.M, dtype=np.float64)
    collection: Any
    (collection,) = ax.collections
    quads = np.asarray(collection._faces, dtype=np.float64)  # the quads drawn, in order
    assert len(quads) == len(sphere_quads(np.zeros((61, 3)), np.ones(61)))
    depth = []
    for quad in quads:
        zs = []
        for x, y, z in quad:
            row = [x * M[k, 0] + y * M[k, 1] + z * M[k, 2] + M[k, 3] for k in (2, 3)]
            zs.append(row[0] / row[1])
        depth.append(((zs[0] + zs[1]) + zs[2] + zs[3]) / 4.0)
    expected = np.empty(len(depth))
    for rank, i in enumerate(sorted(range(len(depth)), key=lambda i: (depth[i], i))):
        expected[i] = rank
    got = depth_ranks(quads, M)
    assert np.array_equal(got, expected)
    assert len(set(depth)) < len(depth)  # equal depths, the ties a sort breaks
    # matplotlib draws the largest rank first: a farthest quad
    assert depth[int(np.argmax(got))] == max(depth)
