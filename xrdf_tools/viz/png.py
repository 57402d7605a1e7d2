"""PNG back-end: a static matplotlib picture of the spheres at the default pose.

Headless (the Agg canvas, no pyplot state, no display needed) and needs only matplotlib, a
core dependency. Spheres are drawn with their true radii, one colour per link (red when the
default pose is in self-collision), on equal axes, with a legend of the links.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from . import atomic_path
from .scene import Progress, Scene

_U = np.linspace(0.0, 2.0 * np.pi, 18)
_V = np.linspace(0.0, np.pi, 10)
_UNIT = (
    np.outer(np.cos(_U), np.sin(_V)),
    np.outer(np.sin(_U), np.sin(_V)),
    np.outer(np.ones_like(_U), np.cos(_V)),
)


def write_png(
    scene: Scene,
    path: Path | None,
    *,
    buffered: bool = False,
    progress: Progress | None = None,
    size_px: int = 640,
    elevation: float = 18.0,
    azimuth: float = -55.0,
) -> None:
    """Write a ``size_px`` square PNG of sample 0 (the default pose) to ``path``."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D

    assert path is not None
    dpi = 100
    fig = Figure(figsize=(size_px / dpi, size_px / dpi), dpi=dpi)
    FigureCanvasAgg(fig)
    ax: Any = fig.add_subplot(projection="3d")
    fig.subplots_adjust(left=0.0, right=1.0, bottom=0.02, top=0.96)
    poses = scene.poses[0]
    colors = scene.colors(0)
    lo = np.full(3, np.inf)
    hi = np.full(3, -np.inf)
    handles = []
    for link in scene.links:
        if not link.n_spheres:
            continue
        T = poses[link.frame_index]
        world = link.centers @ T[:3, :3].T + T[:3, 3]
        radii = link.buffered_radii if buffered else link.radii
        for c, r, col in zip(world, radii, colors[link.name], strict=True):
            ax.plot_surface(
                c[0] + r * _UNIT[0],
                c[1] + r * _UNIT[1],
                c[2] + r * _UNIT[2],
                color=col[:3],
                alpha=0.85,
                linewidth=0,
                shade=True,
                antialiased=False,
            )
            lo = np.minimum(lo, c - r)
            hi = np.maximum(hi, c + r)
        handles.append(
            Line2D([], [], marker="o", linestyle="", color=link.color[:3], label=link.name)
        )
    if np.all(np.isfinite(lo)):
        mid = (lo + hi) / 2.0
        half = float(np.max(hi - lo)) / 2.0 or 0.1
        ax.set_xlim(mid[0] - half, mid[0] + half)
        ax.set_ylim(mid[1] - half, mid[1] + half)
        ax.set_zlim(mid[2] - half, mid[2] + half)
        ax.set_box_aspect((1.0, 1.0, 1.0))
    ax.view_init(elev=elevation, azim=azimuth)
    ax.set_xlabel("x (m)", fontsize=7)
    ax.set_ylabel("y (m)", fontsize=7)
    ax.set_zlabel("z (m)", fontsize=7)
    ax.tick_params(labelsize=6)
    n_hit = len(scene.samples[0].contacts)
    title = f"{scene.robot_name}: {scene.n_spheres} spheres, group '{scene.group}'"
    if n_hit:
        title += f" ({n_hit} colliding pair(s) in red)"
    ax.set_title(title, fontsize=9)
    if handles:
        fig.legend(
            handles=handles,
            loc="upper left",
            bbox_to_anchor=(0.01, 0.94),
            fontsize=7,
            frameon=False,
            handletextpad=0.2,
        )
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png", dpi=dpi)
    if progress is not None:
        progress(1, 1)
