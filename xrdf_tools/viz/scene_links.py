"""The links of a scene: each frame's drawable spheres in its own frame, its colour and its
meshes (:class:`LinkScene`), as :func:`~xrdf_tools.viz.scene.build_scene` assembles them."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np

from ..diagnostics import Diagnostic, Severity
from ..selfcollision.collision.spheres import is_slot, self_radius
from ..util.arrays import FloatArray
from ..xrdf.model import Sphere, Xrdf
from .meshes import MeshPart, Rgba

if TYPE_CHECKING:
    from ..robot.kinematics import KinematicModel

__all__: Sequence[str] = ("LinkScene", "link_color", "sphere_links", "with_meshes")

# Distinct, colour-blind friendly hues without pure red (red marks collisions).
_PALETTE: tuple[tuple[int, int, int], ...] = (
    (31, 119, 180),
    (255, 127, 14),
    (44, 160, 44),
    (148, 103, 189),
    (23, 190, 207),
    (188, 189, 34),
    (140, 86, 75),
    (227, 119, 194),
    (127, 127, 127),
    (174, 199, 232),
    (255, 187, 120),
    (152, 223, 138),
    (197, 176, 213),
    (158, 218, 229),
    (219, 219, 141),
    (196, 156, 148),
    (247, 182, 210),
    (57, 59, 121),
    (99, 121, 57),
    (140, 109, 49),
)


def link_color(index: int) -> Rgba:
    """Colour of the ``index``-th link with spheres (cycles through 20 hues)."""
    r, g, b = _PALETTE[index % len(_PALETTE)]
    return (r / 255.0, g / 255.0, b / 255.0, 1.0)


@dataclass(frozen=True, eq=False)
class LinkScene:
    """One frame of the robot as drawn.

    ``centers`` [S, 3] and ``radii`` [S] are the drawable spheres of the chosen group in the
    link frame; ``buffered_radii`` [S] add the frame's self-collision buffer; ``sphere_ids``
    [S] are their indices in the frame's resolved sphere list of the XRDF (they differ only
    when attached-object slots, radius <= -1, were skipped). A small negative radius (XRDF
    1.0) is drawn as 0 with the buffered radius the self-collision check gives it
    (:func:`~xrdf_tools.selfcollision.collision.spheres.self_radius`).
    """

    name: str
    frame_index: int
    color: Rgba
    centers: FloatArray
    radii: FloatArray
    buffered_radii: FloatArray
    sphere_ids: tuple[int, ...]
    meshes: tuple[MeshPart, ...] = ()

    @property
    def n_spheres(self) -> int:
        return len(self.sphere_ids)


def sphere_links(
    xrdf: Xrdf,
    kin: KinematicModel,
    group: str,
    spheres: Mapping[str, tuple[Sphere, ...]],
    diags: list[Diagnostic],
) -> list[LinkScene]:
    """One :class:`LinkScene` per frame of ``spheres`` (group ``group``'s), coloured in
    order. A frame the kinematic tree lacks is left out, with a warning unless ``group`` is
    the self-collision group (the collision module reports those); attached-object slots are
    not drawn, with one note counting them."""
    links: list[LinkScene] = []
    skipped = 0
    self_group = xrdf.self_collision.geometry if xrdf.self_collision is not None else None
    for frame, frame_spheres in spheres.items():
        if not kin.has_frame(frame):
            if group != self_group:
                diags.append(_unknown_frame(xrdf, kin, group, frame))
            continue
        link = _link_scene(
            frame,
            kin.frame_index(frame),
            link_color(len(links)),
            frame_spheres,
            _self_buffer(xrdf, frame),
        )
        skipped += len(frame_spheres) - link.n_spheres
        links.append(link)
    if skipped:
        diags.append(
            Diagnostic(
                xrdf.source.path or "<xrdf>",
                None,
                None,
                "viz-placeholder-spheres",
                Severity.INFO,
                f"{skipped} attached-object slot(s) (radius <= -1) in group '{group}' not drawn",
            )
        )
    return links


def _self_buffer(xrdf: Xrdf, frame: str) -> float:
    """The self-collision buffer distance of ``frame`` (0 without a self-collision section)."""
    if xrdf.self_collision is None:
        return 0.0
    return float(xrdf.self_collision.buffer_distance.get(frame, 0.0))


def _link_scene(
    frame: str, index: int, color: Rgba, frame_spheres: Sequence[Sphere], buffer: float
) -> LinkScene:
    """The drawable spheres of ``frame`` (attached-object slots left out): centres, radii
    drawn (a negative one as 0) and radii with the self-collision ``buffer``."""
    ids = tuple(i for i, s in enumerate(frame_spheres) if not is_slot(s.radius))
    raw = [frame_spheres[i].radius for i in ids]
    centers = np.array([frame_spheres[i].center for i in ids], dtype=np.float64).reshape(-1, 3)
    radii = np.maximum(np.array(raw, dtype=np.float64), 0.0)
    buffered = np.array([self_radius(r, buffer) or 0.0 for r in raw], dtype=np.float64)
    return LinkScene(frame, index, color, centers, radii, buffered, ids)


def with_meshes(
    links: Sequence[LinkScene],
    mesh_map: Mapping[str, tuple[MeshPart, ...]],
    kin: KinematicModel,
) -> tuple[LinkScene, ...]:
    """``links`` with their meshes from ``mesh_map``, plus a link without spheres for every
    other link with meshes (coloured after them), in the kinematic tree's frame order."""
    by_name = {link.name: link for link in links}
    for name, parts in mesh_map.items():
        if name in by_name:
            by_name[name] = replace(by_name[name], meshes=parts)
        else:
            empty = np.zeros((0, 3))
            by_name[name] = LinkScene(
                name,
                kin.frame_index(name),
                link_color(len(by_name)),
                empty,
                empty[:, 0],
                empty[:, 0],
                (),
                parts,
            )
    return tuple(sorted(by_name.values(), key=lambda link: link.frame_index))


def _unknown_frame(xrdf: Xrdf, kin: KinematicModel, group: str, frame: str) -> Diagnostic:
    from ..util.errors import did_you_mean

    kp = f"geometry.{group}.spheres.{frame}"
    line, col = xrdf.source.position(kp + "#key")
    return Diagnostic(
        xrdf.source.path or "<xrdf>",
        line,
        col,
        "viz-frame-unknown",
        Severity.WARNING,
        f"spheres on '{frame}' not drawn: not a frame of the robot"
        + did_you_mean(frame, kin.frame_names),
        kp,
    )
