"""The 3D scene of the ``xrdf edit`` page (viser): frames, meshes, spheres and their colours.

:class:`RobotView` draws what an :class:`~xrdf_tools.edit.state.EditState` and a pose show and
keeps the viser scene nodes in step with them: a scene node per frame placed by forward
kinematics, the link meshes and spheres as its children (so a new pose moves only the frames),
spheres redrawn only for the frames whose spheres changed.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np

from ..viz.meshes import MeshKind, load_link_meshes
from ..viz.scene import link_color
from ..xrdf.model import Sphere, Xrdf
from .robot import Collisions, EditRobot

if TYPE_CHECKING:
    import viser

    from ..diagnostics import Diagnostic
    from ..robot.packages import PackagePaths
    from ..viz.meshes import MeshPart

__all__ = ["CHECKED_RGB", "IGNORED_RGB", "SELECTED_RGB", "RobotView"]

Rgb = tuple[int, int, int]
#: Spheres in a touching pair the mask checks (a self-collision), one it ignores, the selection.
CHECKED_RGB: Rgb = (230, 20, 20)
IGNORED_RGB: Rgb = (255, 165, 0)
SELECTED_RGB: Rgb = (255, 235, 59)
PREVIEW_RGB: Rgb = (40, 220, 120)
MESH_OPACITY = 0.45

#: ``on_pick(frame, sphere index or None)``: a click on a sphere or a mesh.
Pick = Callable[[str, int | None], None]


def _rgb(color: tuple[float, ...]) -> Rgb:
    return (round(color[0] * 255), round(color[1] * 255), round(color[2] * 255))


def node(frame: str) -> str:
    """Scene-tree name of a frame. ``/`` is the tree's separator, so it is written ``~s`` (and
    ``~`` itself ``~~``): two frames never share a node (``a/b`` and ``a_b`` are both links of
    one robot, and a shared node would take the other's spheres and pose)."""
    return "/robot/" + frame.replace("~", "~~").replace("/", "~s")


class RobotView:
    """The robot as drawn on a viser server."""

    def __init__(
        self,
        server: viser.ViserServer,
        robot: EditRobot,
        *,
        on_pick: Pick,
        package_paths: PackagePaths | None = None,
    ) -> None:
        self.server = server
        self.robot = robot
        self.on_pick = on_pick
        self.package_paths = dict(package_paths or {})
        self.frames: dict[str, Any] = {}
        self.spheres: dict[str, list[Any]] = {}
        self.drawn: dict[str, tuple[Sphere, ...]] = {}
        #: The buffer distance each frame's buffered spheres are drawn with.
        self.drawn_buffer: dict[str, float] = {}
        self.buffers: dict[str, list[Any]] = {}
        self.meshes: list[Any] = []
        self.preview: list[Any] = []
        self.tool_frames: list[Any] = []
        self.shown_tool_frames: tuple[str, ...] = ()
        self.colors: dict[str, list[Rgb]] = {}
        self.link_rgb: dict[str, Rgb] = {}
        self.show_buffered = False
        self.show_ignored = False
        self.show_axes = False
        self.mesh_kind: MeshKind = "none"
        self._mesh_cache: dict[str, dict[str, tuple[MeshPart, ...]]] = {}
        self.diagnostics: list[Diagnostic] = []
        for frame in robot.frame_names:
            self.frames[frame] = server.scene.add_frame(
                node(frame), show_axes=False, axes_length=0.08, axes_radius=0.003
            )

    # --- pose ------------------------------------------------------------------------------
    def set_pose(self, q: np.ndarray[Any, Any]) -> None:
        """Place every frame at pose ``q``."""
        import viser.transforms as vtf

        poses = self.robot.poses(q)
        with self.server.atomic():
            for i, frame in enumerate(self.robot.frame_names):
                T = poses[i]
                handle = self.frames[frame]
                handle.wxyz = vtf.SO3.from_matrix(T[:3, :3]).wxyz
                handle.position = T[:3, 3]

    def set_axes(self, show: bool) -> None:
        self.show_axes = show
        for handle in self.frames.values():
            handle.show_axes = show

    def set_tool_frames(self, frames: tuple[str, ...]) -> None:
        """Axes and a label on each of ``frames`` (those the robot has)."""
        self.shown_tool_frames = tuple(frames)
        for h in reversed(self.tool_frames):  # a label before the frame it hangs from
            h.remove()
        self.tool_frames = []
        for frame in frames:
            if frame in self.frames:
                self.tool_frames.append(
                    self.server.scene.add_frame(
                        node(frame) + "/tool", axes_length=0.12, axes_radius=0.005
                    )
                )
                self.tool_frames.append(
                    self.server.scene.add_label(node(frame) + "/tool/label", frame)
                )

    # --- meshes ----------------------------------------------------------------------------
    def set_meshes(self, kind: MeshKind) -> None:
        """Draw the URDF's ``kind`` geometry (read once per kind)."""
        for h in self.meshes:
            h.remove()
        self.meshes = []
        self.mesh_kind = kind
        if kind == "none":
            return
        if kind not in self._mesh_cache:
            loaded, diags = load_link_meshes(
                self.robot.robot,
                self.robot.frame_names,
                kind,
                package_paths=self.package_paths or None,
            )
            self._mesh_cache[kind] = loaded
            self.diagnostics.extend(diags)
        for frame, parts in self._mesh_cache[kind].items():
            for k, part in enumerate(parts):
                h = self.server.scene.add_mesh_simple(
                    f"{node(frame)}/{kind}_{k}",
                    part.vertices.astype(np.float32),
                    part.faces.astype(np.uint32),
                    color=_rgb(part.color),
                    opacity=MESH_OPACITY,
                )
                h.on_click(self._picker(frame, None))
                self.meshes.append(h)

    # --- spheres ---------------------------------------------------------------------------
    def _picker(self, frame: str, index: int | None) -> Callable[[Any], None]:
        def picked(_: Any) -> None:
            self.on_pick(frame, index)

        return picked

    def set_spheres(self, xrdf: Xrdf, group: str) -> None:
        """Draw ``group``'s spheres; only frames whose spheres changed are redrawn."""
        spheres = {f: s for f, s in xrdf.resolved_spheres(group).items() if f in self.frames}
        for i, frame in enumerate(spheres):
            self.link_rgb.setdefault(frame, _rgb(link_color(i)))
        for frame in [f for f in self.drawn if f not in spheres]:
            self._clear(frame)
        buffers = xrdf.self_collision.buffer_distance if xrdf.self_collision else {}
        for frame, items in spheres.items():
            b = float(buffers.get(frame, 0.0))
            if (
                self.drawn.get(frame) == items
                and (frame in self.buffers) == self.show_buffered
                and (not self.show_buffered or self.drawn_buffer.get(frame) == b)
            ):
                continue
            self._clear(frame)
            rgb = self.link_rgb[frame]
            handles = []
            for k, s in enumerate(items):
                h = self.server.scene.add_icosphere(
                    f"{node(frame)}/sphere_{k}",
                    radius=max(s.radius, 1e-4),
                    color=rgb,
                    subdivisions=2,
                    position=s.center,
                    visible=s.radius >= 0,
                )
                h.on_click(self._picker(frame, k))
                handles.append(h)
            self.spheres[frame] = handles
            self.colors[frame] = [rgb] * len(items)
            self.drawn[frame] = items
            if self.show_buffered:
                self.drawn_buffer[frame] = b
                self.buffers[frame] = [
                    self.server.scene.add_icosphere(
                        f"{node(frame)}/buffered_{k}",
                        radius=max(s.radius + b, 1e-4),
                        color=rgb,
                        subdivisions=2,
                        position=s.center,
                        opacity=0.2,
                        visible=s.radius + b > 0,
                    )
                    for k, s in enumerate(items)
                ]

    def _clear(self, frame: str) -> None:
        for h in self.spheres.pop(frame, []) + self.buffers.pop(frame, []):
            h.remove()
        self.drawn.pop(frame, None)
        self.drawn_buffer.pop(frame, None)
        self.colors.pop(frame, None)

    def set_buffered(self, show: bool, xrdf: Xrdf, group: str) -> None:
        self.show_buffered = show
        for frame in list(self.drawn):
            self._clear(frame)
        self.set_spheres(xrdf, group)

    def color_spheres(
        self, collisions: Collisions, selected: tuple[str, int | None] | None
    ) -> None:
        """Colour every sphere: its link's colour, or touching in a checked pair, or touching
        in an ignored pair (when :attr:`show_ignored`), or selected."""
        for frame, handles in self.spheres.items():
            hit = collisions.spheres.get(frame, frozenset())
            ign = collisions.ignored_spheres.get(frame, frozenset())
            for k, h in enumerate(handles):
                rgb = self.link_rgb[frame]
                if k in hit:
                    rgb = CHECKED_RGB
                elif self.show_ignored and k in ign:
                    rgb = IGNORED_RGB
                if selected is not None and selected == (frame, k):
                    rgb = SELECTED_RGB
                if self.colors[frame][k] != rgb:
                    h.color = rgb
                    self.colors[frame][k] = rgb

    def show_preview(self, frame: str, spheres: tuple[Sphere, ...]) -> None:
        """Draw proposed spheres of ``frame`` as green wireframes (none: remove them)."""
        for h in self.preview:
            h.remove()
        self.preview = [
            self.server.scene.add_icosphere(
                f"{node(frame)}/preview_{k}",
                radius=s.radius,
                color=PREVIEW_RGB,
                subdivisions=2,
                wireframe=True,
                position=s.center,
            )
            for k, s in enumerate(spheres)
        ]
