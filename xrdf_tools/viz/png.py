"""PNG back-end: a static matplotlib picture of the spheres at the default pose.

Headless (the Agg canvas, no pyplot state, no display needed) and needs only matplotlib, a
core dependency. Spheres are drawn with their true radii, one colour per link (red when the
default pose is in self-collision), on equal axes, from a chosen camera (:func:`parse_view`),
with a legend of the links that fits large robots (:data:`LEGEND_COLUMNS_FROM`) and a title
that counts the frame pairs (:func:`png_title`).
"""

from __future__ import annotations

import math
import textwrap
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from ..util.arrays import FloatArray, IntArray
from ..util.errors import XrdfToolsError
from ..util.fixed_order import transform_points
from . import DEFAULT_PICTURE, Picture, atomic_path
from .scene import Progress, Scene

if TYPE_CHECKING:
    from matplotlib.figure import Figure

#: Named cameras: (elevation, azimuth) in degrees, matplotlib's convention (azimuth 0 looks
#: from +x, 90 from +y). ``iso`` is the three-quarter view drawn by default.
VIEWS: dict[str, tuple[float, float]] = {
    "iso": (18.0, -55.0),
    "front": (0.0, 0.0),
    "side": (0.0, 90.0),
    "top": (90.0, -90.0),
}
#: ``auto``: a legend of the links (in columns below the picture from
#: :data:`LEGEND_COLUMNS_FROM` links on); ``off``: none.
Legend = Literal["auto", "off"]
LEGEND_COLUMNS_FROM = 21


def parse_view(text: str) -> tuple[float, float]:
    """``iso``, ``front``, ``side``, ``top`` or ``ELEV,AZIM`` (degrees) → (elevation, azimuth).

    Raises :class:`XrdfToolsError` naming the valid forms."""
    key = text.strip().lower()
    if key in VIEWS:
        return VIEWS[key]
    parts = key.split(",")
    try:
        elev, azim = (float(p) for p in parts) if len(parts) == 2 else (math.nan, math.nan)
    except ValueError:
        elev = azim = math.nan
    if not (math.isfinite(elev) and math.isfinite(azim)):
        raise XrdfToolsError(
            f"--view '{text}': expected {', '.join(VIEWS)} or ELEV,AZIM in degrees (e.g. 30,-60)"
        )
    return elev, azim


#: Title characters per pixel of the picture's width (8-point text at 100 dpi is about 6.5
#: pixels a character): a longer line is wrapped, never cut at the picture's edges.
TITLE_CHARS_PER_PX = 1 / 7


def png_title(scene: Scene, width: int | None = None) -> str:
    """Robot, spheres, group; then the frame pairs self-collision checks, how many of those
    collide at the drawn pose (the default pose; ignored pairs are not counted), and the frame
    pairs it ignores. ``width``: lines wrapped to that many characters (Unitree's
    ``g1_29dof_rev_1_0_with_inspire_hand_FTP`` names its robot and its group in 125)."""
    return "\n".join(
        wrapped
        for line in _title_lines(scene)
        for wrapped in (
            [line]
            if width is None
            else textwrap.wrap(line, width, break_long_words=False, break_on_hyphens=False)
        )
    )


def _title_lines(scene: Scene) -> list[str]:
    """The lines of :func:`png_title`, unwrapped."""
    first = f"{scene.robot_name}: {scene.n_spheres} spheres, group '{scene.group}'"
    checked, ignored = scene.frame_pairs_checked, scene.frame_pairs_ignored
    if checked + ignored == 0:
        return [first, "no frame pairs checked for self-collision"]
    hit = len(scene.samples[0].frame_contacts)
    red = " (red)" if hit and scene.collisions_shown else ""
    second = (
        f"frame pairs: {checked} checked ({hit} colliding at the default pose{red}), "
        f"{ignored} ignored"
    )
    return [first, second]


def _unit_sphere_quads(n_around: int = 18, n_down: int = 10) -> FloatArray:
    """The quadrilaterals [F, 4, 3] of a unit sphere on a longitude × latitude grid (the
    grid ``plot_surface`` would draw)."""
    u = np.linspace(0.0, 2.0 * np.pi, n_around)
    v = np.linspace(0.0, np.pi, n_down)
    grid = np.stack(
        [
            np.outer(np.cos(u), np.sin(v)),
            np.outer(np.sin(u), np.sin(v)),
            np.outer(np.ones_like(u), np.cos(v)),
        ],
        axis=-1,
    )
    corners = (grid[:-1, :-1], grid[1:, :-1], grid[1:, 1:], grid[:-1, 1:])
    return np.stack(corners, axis=2).reshape(-1, 4, 3)


#: Unit spheres, finest first; a picture uses the finest whose polygons for all its spheres
#: stay within :data:`MAX_POLYGONS` (a sphere a few pixels across needs no 153 faces).
_UNIT_SPHERES = (_unit_sphere_quads(), _unit_sphere_quads(12, 7), _unit_sphere_quads(8, 5))
MAX_POLYGONS = 300_000


def draw_png(
    scene: Scene,
    *,
    buffered: bool = False,
    size_px: int = 640,
    view: tuple[float, float] = VIEWS["iso"],
    legend: Legend = "auto",
) -> Figure:
    """The figure of sample 0 (the default pose): ``size_px`` square, taller when a legend of
    many links is placed below the picture. Names are drawn as they are written: a ``$`` in a
    link or group name does not start matplotlib's math text."""
    from ..util.extras import VIZ, require

    require(VIZ, "viz", "a PNG picture")
    return _draw(scene, buffered, size_px, view, legend)


def _as_written(texts: Any) -> None:
    """Draw ``texts`` as written, not as math text: set on each text, never through
    matplotlib's global ``rcParams`` (another thread may be drawing)."""
    for text in texts:
        text.set_parse_math(False)


def _draw(
    scene: Scene, buffered: bool, size_px: int, view: tuple[float, float], legend: Legend
) -> Figure:
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D

    dpi = 100
    fig = Figure(figsize=(size_px / dpi, size_px / dpi), dpi=dpi)
    FigureCanvasAgg(fig)
    ax: Any = fig.add_subplot(projection="3d")
    fig.subplots_adjust(left=0.0, right=1.0, bottom=0.02, top=0.94)
    poses = scene.poses[0]
    colors = scene.colors(0)
    handles = []
    centers: list[FloatArray] = []
    radii: list[FloatArray] = []
    rgb: list[FloatArray] = []
    for link in scene.links:
        if not link.n_spheres:
            continue
        T = poses[link.frame_index]
        centers.append(transform_points(T, link.centers))
        radii.append(link.buffered_radii if buffered else link.radii)
        rgb.append(np.array([col[:3] for col in colors[link.name]], dtype=np.float64))
        handles.append(
            Line2D([], [], marker="o", linestyle="", color=link.color[:3], label=link.name)
        )
    if centers:
        c, r = np.concatenate(centers), np.concatenate(radii)
        lo, hi = (c - r[:, None]).min(axis=0), (c + r[:, None]).max(axis=0)
        mid = (lo + hi) / 2.0
        half = float(np.max(hi - lo)) / 2.0 or 0.1
        ax.set_xlim(mid[0] - half, mid[0] + half)
        ax.set_ylim(mid[1] - half, mid[1] + half)
        ax.set_zlim(mid[2] - half, mid[2] + half)
        ax.set_box_aspect((1.0, 1.0, 1.0))
    ax.view_init(elev=view[0], azim=view[1])
    if centers:  # projected with the camera and limits just set
        _add_spheres(fig, ax, c, r, np.concatenate(rgb))
    ax.set_xlabel("x (m)", fontsize=7)
    ax.set_ylabel("y (m)", fontsize=7)
    ax.set_zlabel("z (m)", fontsize=7)
    ax.tick_params(labelsize=6)
    _hide_depth_axis(ax, view)
    width = int(size_px * TITLE_CHARS_PER_PX)
    ax.set_title(png_title(scene, width), fontsize=8, parse_math=False)
    if handles and legend != "off":
        if len(handles) < LEGEND_COLUMNS_FROM:
            leg = fig.legend(
                handles=handles,
                loc="upper left",
                bbox_to_anchor=(0.01, 0.92),
                fontsize=7,
                frameon=False,
                handletextpad=0.2,
            )
            _as_written(leg.get_texts())
        else:
            _legend_below(fig, ax, handles, size_px)
    return fig


def depth_axis(view: tuple[float, float]) -> str | None:
    """The axis a camera looks along (``front``: x, ``side``: y, ``top``: z), else None: its
    ticks would all be drawn on one point, their labels over one another."""
    elev, azim = view
    if abs(elev) == 90.0:
        return "z"
    if elev == 0.0 and azim % 90.0 == 0.0:
        return "x" if azim % 180.0 == 0.0 else "y"
    return None


def _hide_depth_axis(ax: Any, view: tuple[float, float]) -> None:
    axis = depth_axis(view)
    if axis is not None:
        getattr(ax, f"set_{axis}ticks")([])
        getattr(ax, f"set_{axis}label")("")


def sphere_quads(centers: FloatArray, radii: FloatArray) -> FloatArray:
    """The quadrilaterals [N × F, 4, 3] of spheres ``centers`` [N, 3], ``radii`` [N], sphere
    by sphere, on the finest unit sphere whose N × F polygons stay within
    :data:`MAX_POLYGONS`."""
    unit = next(
        (u for u in _UNIT_SPHERES if len(u) * len(radii) <= MAX_POLYGONS), _UNIT_SPHERES[-1]
    )
    verts: FloatArray = centers[:, None, None, :] + radii[:, None, None, None] * unit[None]
    return verts.reshape(-1, 4, 3)


def _add_spheres(
    fig: Any, ax: Any, centers: FloatArray, radii: FloatArray, rgb: FloatArray
) -> None:
    """Every sphere as shaded, translucent polygons, projected here with the axes' camera
    (``ax.get_proj()``: the view and limits must be set) and drawn as one 2-D collection in
    painter's order, farthest first (:func:`painter_order`): the polygons of all spheres are
    sorted together (spheres of different links overlap correctly), and thousands of spheres
    draw in seconds with coarser spheres (:data:`MAX_POLYGONS`). The collection is the
    figure's, drawn over the 3-D axes in their data coordinates and clipped to them, as the
    axes would draw a 3-D collection of theirs (after the panes, the grid and the axis lines)."""
    from matplotlib.collections import PolyCollection

    quads = sphere_quads(centers, radii)
    per_sphere = len(quads) // len(radii)
    colors = shaded(np.repeat(rgb, per_sphere, axis=0), quads)
    faces = np.concatenate([colors, np.full((len(quads), 1), SPHERE_ALPHA)], axis=1)
    xy, depth = project(quads, ax.get_proj())
    order = painter_order(depth)
    # matplotlib's stubs ask for a sequence of polygons; it takes the [F, 4, 2] array as it is
    verts: Any = xy[order]
    polygons = PolyCollection(verts, facecolors=faces[order], linewidths=0.0, antialiased=False)
    polygons.set_transform(ax.transData)
    polygons.set_clip_path(ax.patch)
    fig.add_artist(polygons)


#: Opacity of the sphere polygons.
SPHERE_ALPHA = 0.85
#: Where the light comes from (degrees): matplotlib's default for shaded 3-D surfaces.
LIGHT_AZIMUTH, LIGHT_ALTITUDE = 225.0, 19.4712


def shaded(rgb: FloatArray, quads: FloatArray) -> FloatArray:
    """The colours ``rgb`` [F, 3] of the quads [F, 4, 3] lit by :data:`LIGHT_AZIMUTH` /
    :data:`LIGHT_ALTITUDE`: scaled from 0.3 (facing away) to 1 (facing the light), 0.65 for a
    quad without area (a pole's, or a sphere of radius 0), as matplotlib shades a 3-D surface.
    Sums term by term: the same bits on every machine."""
    az, alt = math.radians(LIGHT_AZIMUTH), math.radians(LIGHT_ALTITUDE)
    light = (math.cos(alt) * math.cos(az), math.cos(alt) * math.sin(az), math.sin(alt))
    a, b = quads[:, 0] - quads[:, 1], quads[:, 1] - quads[:, 2]
    normal = (
        a[:, 1] * b[:, 2] - a[:, 2] * b[:, 1],
        a[:, 2] * b[:, 0] - a[:, 0] * b[:, 2],
        a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0],
    )
    length = np.sqrt(normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2])
    facing = normal[0] * light[0] + normal[1] * light[1] + normal[2] * light[2]
    with np.errstate(invalid="ignore", divide="ignore"):
        cosine = np.where(length > 0.0, facing / length, 0.0)
    factor = 0.3 + 0.7 * ((cosine + 1.0) / 2.0)
    colors: FloatArray = rgb * factor[:, None]
    return colors


def project(quads: FloatArray, projection: FloatArray) -> tuple[FloatArray, FloatArray]:
    """The quads [F, 4, 3] under the 4x4 ``projection`` (a 3-D axes' ``get_proj()``): their
    2-D corners [F, 4, 2] in the axes' data coordinates and each quad's mean depth [F] (larger
    is farther). Each row of ``M (x, y, z, 1)`` is summed term by term in index order, as
    ``fixed_order`` does: the same bits on every machine."""
    points = np.asarray(quads, dtype=np.float64).reshape(-1, 3)
    m = np.asarray(projection, dtype=np.float64)

    def row(r: int) -> FloatArray:
        out: FloatArray = points[:, 0] * m[r, 0] + points[:, 1] * m[r, 1]
        out = out + points[:, 2] * m[r, 2] + m[r, 3]
        return out

    w = row(3)
    xy = np.stack([row(0) / w, row(1) / w], axis=-1).reshape(len(quads), -1, 2)
    depth = (row(2) / w).reshape(len(quads), -1).mean(axis=1)
    return xy, depth


def painter_order(depth: FloatArray) -> IntArray:
    """The quads' drawing order [F]: farthest first, equal depths in descending index order
    (a stable sort reversed): the same on every machine, where an unstable sort breaks the
    ties of a sphere's symmetric quads one way with numpy's AVX-512 sort and another without."""
    order: IntArray = np.argsort(depth, kind="stable")[::-1]
    return order


def _legend_below(fig: Any, ax: Any, handles: list[Any], size_px: int) -> None:
    """Many links: a legend in columns, small font, below the picture; the figure grows so
    that the picture keeps its size and the legend stays inside the image."""
    dpi = fig.dpi
    renderer = fig.canvas.get_renderer()
    # The most columns (up to 6) whose measured width fits the picture's width.
    ncol = min(6, len(handles))
    while True:
        leg = fig.legend(
            handles=handles,
            loc="upper center",
            ncol=ncol,
            fontsize=5,
            frameon=False,
            handletextpad=0.2,
            columnspacing=0.8,
            labelspacing=0.25,
            borderaxespad=0.0,
        )
        _as_written(leg.get_texts())
        box = leg.get_window_extent(renderer)
        if box.width <= size_px - 8 or ncol == 1:
            break
        leg.remove()
        ncol -= 1
    pad = 8.0
    legend_h = float(box.height) + 2 * pad
    height = size_px + legend_h
    fig.set_size_inches(size_px / dpi, height / dpi)
    # The picture keeps its square in the top size_px pixels; the legend hangs below it.
    ax.set_position([0.0, legend_h / height, 1.0, size_px / height * 0.92])
    leg.set_bbox_to_anchor((0.5, (legend_h - pad) / height), transform=fig.transFigure)


def write_png(
    scene: Scene,
    path: Path | None,
    *,
    buffered: bool = False,
    progress: Progress | None = None,
    picture: Picture = DEFAULT_PICTURE,
) -> None:
    """Write the picture of :func:`draw_png`, framed by ``picture``, to ``path`` (atomically)."""
    assert path is not None
    view = VIEWS["iso"] if picture.view is None else picture.view
    fig = draw_png(
        scene, buffered=buffered, size_px=picture.size_px, view=view, legend=picture.legend
    )
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png", dpi=fig.dpi)
    if progress is not None:
        progress(1, 1)
