"""The PNG's translucent sphere polygons are drawn in an order that is the same on every
machine: projected and sorted by the tool (a depth computed term by term, equal depths by
index), not by matplotlib (the example-robot-data Panda with fixtures/panda/panda.xrdf, from
the front, where many depths are equal)."""

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
from xrdf_tools.viz.png import VIEWS, draw_png, sphere_quads
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


def _scene_quads(scene: Scene) -> np.ndarray:
    """The quads of every sphere at the default pose, link by link (the order drawn)."""
    centres, radii = [], []
    for link in scene.links:
        T = scene.poses[0, link.frame_index]
        centres.extend(link.centers @ T[:3, :3].T + T[:3, 3])
        radii.extend(link.radii)
    return sphere_quads(np.array(centres), np.array(radii))


def test_polygons_are_drawn_farthest_first_as_a_plain_loop_projects_and_sorts_them(
    scene: Scene,
) -> None:
    """The picture's polygons are one 2-D collection of the figure (no private matplotlib
    hook orders them): the quads projected with the axes' camera, farthest first, equal depths
    by descending index, checked against a plain loop."""
    from matplotlib.collections import PolyCollection

    fig = draw_png(scene, legend="off", view=VIEWS["front"])
    ax: Any = fig.axes[0]
    M = np.asarray(ax.get_proj(), dtype=np.float64)
    fig.canvas.draw()
    np.testing.assert_array_equal(ax.get_proj(), M)  # drawing keeps the camera used
    (collection,) = fig.artists
    assert isinstance(collection, PolyCollection) and not ax.collections
    quads = _scene_quads(scene)
    projected, depth = [], []
    for quad in quads:
        corners, zs = [], []
        for x, y, z in quad:
            row = [x * M[k, 0] + y * M[k, 1] + z * M[k, 2] + M[k, 3] for k in range(4)]
            corners.append((row[0] / row[3], row[1] / row[3]))
            zs.append(row[2] / row[3])
        projected.append(corners)
        depth.append(((zs[0] + zs[1]) + zs[2] + zs[3]) / 4.0)
    order = sorted(range(len(depth)), key=lambda i: (-depth[i], -i))
    paths = collection.get_paths()
    assert len(paths) == len(quads) == 61 * 153
    drawn = np.array([p.vertices[:4] for p in paths])
    np.testing.assert_allclose(drawn, np.array(projected)[order], rtol=0, atol=1e-12)
    assert len(set(depth)) < len(depth)  # equal depths, the ties a sort breaks


def test_polygons_are_shaded_as_matplotlib_shades_a_3d_surface() -> None:
    """The tool's own shading gives the colours matplotlib's ``shade=True`` gives the same
    quads (compared as sets: matplotlib returns them in its drawing order)."""
    from matplotlib.figure import Figure
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    from xrdf_tools.viz.png import shaded

    rng = np.random.default_rng(3)
    quads = sphere_quads(rng.uniform(-1, 1, (5, 3)), np.array([0.1, 0.2, 0.0, 0.3, 0.05]))
    rgb = np.repeat(rng.uniform(0, 1, (5, 3)), len(quads) // 5, axis=0)
    ax: Any = Figure().add_subplot(projection="3d")
    theirs = Poly3DCollection(quads, facecolors=np.c_[rgb, np.full(len(rgb), 0.85)], shade=True)
    ax.add_collection3d(theirs)
    want = np.asarray(theirs.get_facecolor())[:, :3]
    got = shaded(rgb, quads)
    np.testing.assert_allclose(got[np.lexsort(got.T)], want[np.lexsort(want.T)], atol=1e-12)


def test_a_long_title_is_wrapped_inside_the_picture(scene: Scene) -> None:
    """Unitree's G1 with Inspire hands names its robot and its group in 125 characters: the
    title's first line ran past both edges of a 640-pixel picture, cut at each end."""
    from dataclasses import replace

    name = "g1_29dof_rev_1_0_with_inspire_hand_FTP"
    long = replace(scene, robot_name=name, group=f"{name}_collision_spheres")
    for size in (400, 640):
        fig = draw_png(long, size_px=size)
        title = fig.axes[0].title
        box = title.get_window_extent(fig.canvas.get_renderer())
        assert box.x0 >= 0 and box.x1 <= fig.bbox.width, (size, box)
        assert name in title.get_text() and f"'{name}_collision_spheres'" in title.get_text()
