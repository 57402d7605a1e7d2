"""`xrdf viz --png` drawing time: the spheres projected and depth-sorted by the tool and drawn
as one 2-D polygon collection (what the tool does) vs the same polygons as one matplotlib
``Poly3DCollection`` (matplotlib projects and sorts them at draw time: what the tool did before
it sorted them itself) and vs one ``plot_surface`` per sphere (a simple baseline), in the same
process.

Usage: ``python benchmarks/bench_viz_png.py [--spheres 61 1000 10000] [--baseline-max 2000]``

Prints one JSON line per sphere count: seconds to draw and save the PNG each way (the
``plot_surface`` baseline only up to ``--baseline-max`` spheres, it grows ~4 ms a sphere) and
the speed-ups. Random spheres in a 1 m cube on one link of the example-robot-data Panda.
"""

from __future__ import annotations

import argparse
import dataclasses
import importlib.metadata
import io
import json
import time
from pathlib import Path
from typing import Any

import numpy as np

from xrdf_tools.robot.urdf_source import load_urdf
from xrdf_tools.viz import build_scene
from xrdf_tools.viz.png import draw_png, sphere_quads
from xrdf_tools.viz.scene import LinkScene, Scene
from xrdf_tools.xrdf.io import load_xrdf

REPO = Path(__file__).resolve().parents[1]
PANDA = Path("cmeel.prefix/share/example-robot-data/robots/panda_description/urdf/panda.urdf")


def scene_with(n: int) -> Scene:
    dist = importlib.metadata.distribution("example-robot-data")
    urdf = load_urdf(Path(str(dist.locate_file(PANDA))))
    scene = build_scene(urdf, load_xrdf(REPO / "fixtures/panda/panda.xrdf"), None, meshes="none")
    rng = np.random.default_rng(0)
    centres, radii = rng.uniform(-0.5, 0.5, (n, 3)), rng.uniform(0.005, 0.03, n)
    link = scene.links[0]
    big = LinkScene(link.name, link.frame_index, link.color, centres, radii, radii, tuple(range(n)))
    return dataclasses.replace(scene, links=(big,))


def baseline(scene: Scene) -> Any:
    """One ``plot_surface`` per sphere, as a plain loop."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(6.4, 6.4), dpi=100)
    FigureCanvasAgg(fig)
    ax: Any = fig.add_subplot(projection="3d")
    u, v = np.linspace(0.0, 2.0 * np.pi, 18), np.linspace(0.0, np.pi, 10)
    unit = (np.outer(np.cos(u), np.sin(v)), np.outer(np.sin(u), np.sin(v)))
    unit += (np.outer(np.ones_like(u), np.cos(v)),)
    link = scene.links[0]
    for c, r in zip(link.centers, link.radii, strict=True):
        xyz = [c[k] + r * unit[k] for k in range(3)]
        ax.plot_surface(*xyz, color=link.color[:3], alpha=0.85, linewidth=0, shade=True)
    return fig


def poly3d(scene: Scene) -> Any:
    """The same shaded polygons as one ``Poly3DCollection``, in matplotlib's own order."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # type: ignore[import-untyped]

    fig = Figure(figsize=(6.4, 6.4), dpi=100)
    FigureCanvasAgg(fig)
    ax: Any = fig.add_subplot(projection="3d")
    link = scene.links[0]
    quads = sphere_quads(link.centers, link.radii)
    faces = np.tile([*link.color[:3], 0.85], (len(quads), 1))
    ax.add_collection3d(
        Poly3DCollection(quads, facecolors=faces, linewidths=0.0, shade=True, antialiased=False)
    )
    ax.set_xlim(-0.55, 0.55), ax.set_ylim(-0.55, 0.55), ax.set_zlim(-0.55, 0.55)
    ax.view_init(elev=18.0, azim=-55.0)
    return fig


def seconds(make: Any, scene: Scene) -> float:
    start = time.perf_counter()
    make(scene).savefig(io.BytesIO(), format="png")
    return time.perf_counter() - start


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--spheres", type=int, nargs="+", default=[61, 1000, 10_000])
    ap.add_argument("--baseline-max", type=int, default=2000)
    args = ap.parse_args()
    warm = scene_with(10)  # imports and font caches are not timed
    seconds(lambda s: draw_png(s, legend="off"), warm), seconds(baseline, warm)
    seconds(poly3d, warm)
    for n in args.spheres:
        scene = scene_with(n)
        tool = seconds(lambda s: draw_png(s, legend="off"), scene)
        p3d = seconds(poly3d, scene)
        row: dict[str, Any] = {"spheres": n, "tool_s": round(tool, 3)}
        row |= {"poly3d_s": round(p3d, 3), "speedup_vs_poly3d": round(p3d / tool, 2)}
        if n <= args.baseline_max:
            base = seconds(baseline, scene)
            row |= {"plot_surface_s": round(base, 3), "speedup": round(base / tool, 1)}
        print(json.dumps(row))


if __name__ == "__main__":
    main()
