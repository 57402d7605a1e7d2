"""The Spheres panel of the ``xrdf edit`` page: pick a link and a sphere (or click one), move
it with a gizmo or typed numbers, resize (typed, or dragging the radius slider), add,
duplicate, delete, connect two spheres with a chain between them, and scale a link's spheres.

The radius slider is for dragging: its own number box (viser's, which drops an exponent:
``1e-3`` typed there arrived as 1, -1, then 13) is hidden, and the radius is typed in the
**Radius (m)** field, read as the centre fields are (:mod:`xrdf_tools.edit.typed`).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..xrdf.model import Sphere
from .edits import (
    AddSphere,
    ConnectSpheres,
    DeleteSphere,
    DuplicateSphere,
    MoveSphere,
    ScaleSpheres,
    SetRadius,
)
from .sphere_edits import MAX_CONNECT
from .surface import PageSurface, from_browser
from .typed import TypedNumber, hide_number_box, said
from .view import node

__all__ = ["NONE", "RADIUS_MAX", "RADIUS_STEP", "SpherePanel"]

NONE = "none"
#: The radius slider's step (its smallest value: XRDF 2.0 needs a radius above 0) and its
#: usual end (moved out for a larger sphere), metres.
RADIUS_STEP = 0.0005
RADIUS_MAX = 0.3


class SpherePanel:
    """The sphere controls and the gizmo on the selected sphere."""

    def __init__(self, page: PageSurface, gui: Any) -> None:
        self.page = page
        self.gui = gui
        self.gizmo: Any = None
        self.gizmo_for: tuple[str, int] | None = None
        frames = page.robot.frame_names
        #: How far from its link a sphere's centre may be typed (twice the robot's reach).
        self.far = 2.0 * max(page.robot.reach(page.q), 0.5)
        with gui.add_folder("Spheres"):
            self.link: Any = gui.add_dropdown("Link", frames, initial_value=frames[0])
            self.sphere: Any = gui.add_dropdown("Sphere", (NONE,), initial_value=NONE)
            self.center = [
                TypedNumber(gui, f"Center {axis} (m)", 0.0, unit=" m", hint="1e-3 is 1 mm")
                for axis in "xyz"
            ]
            self.typed_radius = TypedNumber(
                gui,
                "Radius (m)",
                RADIUS_STEP,
                lo=RADIUS_STEP,
                hi=self.far / 2,
                unit=" m",
                hint="1e-3 is 1 mm; or drag the slider below",
            )
            self.radius: Any = gui.add_slider(
                "Radius", RADIUS_STEP, RADIUS_MAX, step=RADIUS_STEP, initial_value=RADIUS_STEP
            )
            hide_number_box(gui, self.radius)
            add = gui.add_button("Add sphere")
            dup = gui.add_button("Duplicate sphere")
            delete = gui.add_button("Delete sphere")
            self.other = TypedNumber(
                gui, "Connect to sphere", 1, lo=0, integer=True, hint="another sphere of the link"
            )
            self.between = TypedNumber(
                gui, "Spheres between", 2, lo=1, hi=MAX_CONNECT, integer=True, hint="evenly spaced"
            )
            connect = gui.add_button("Connect spheres")
            self.factor = TypedNumber(
                gui, "Scale factor", 1.1, lo=0.1, hi=10.0, hint="every sphere's radius"
            )
            scale = gui.add_button("Scale link spheres")
        self.link.on_update(lambda e: page.pick(self.link.value, None) if from_browser(e) else None)
        self.sphere.on_update(lambda e: self._pick_sphere() if from_browser(e) else None)
        for axis, field in enumerate(self.center):
            field.on_number(page.say, self._center_moved(axis))
        self.typed_radius.on_number(page.say, self._resize)
        self.radius.on_update(lambda e: self._dragged_radius() if from_browser(e) else None)
        for field in (self.other, self.between, self.factor):
            field.watch(page.say)
        add.on_click(lambda e: self._add() if from_browser(e) else None)
        dup.on_click(lambda e: self._on_sphere(DuplicateSphere) if from_browser(e) else None)
        delete.on_click(lambda e: self._on_sphere(DeleteSphere) if from_browser(e) else None)
        connect.on_click(lambda e: self._connect() if from_browser(e) else None)
        scale.on_click(lambda e: self._scale() if from_browser(e) else None)

    def _selected_sphere(self) -> tuple[str, int] | None:
        sel = self.page.selected
        if sel is None or sel[1] is None:
            return None
        return sel[0], sel[1]

    def _pick_sphere(self) -> None:
        value = self.sphere.value
        self.page.pick(self.link.value, None if value == NONE else int(value))

    def _center_moved(self, axis: int) -> Any:
        return lambda value: self.set_center(axis, value)

    def set_center(self, axis: int, value: float) -> None:
        """Move the selected sphere's centre along ``axis`` to ``value`` (link frame, metres).

        A centre farther from its link than twice the robot's reach at the page's start is
        refused (a slip of the keyboard, or a number on its way: ``15`` typing ``15e-3``); the
        field keeps what was typed."""
        sel = self._selected_sphere()
        if sel is None:
            return
        s = self.page.state.xrdf.resolved_spheres(self.page.state.group)[sel[0]][sel[1]]
        c = list(s.center)
        c[axis] = value
        if math.isfinite(value) and math.dist(c, (0.0, 0.0, 0.0)) > self.far:
            self.page.say(
                f"not moved: {value:g} m puts the sphere farther from '{sel[0]}' than twice the "
                f"robot's reach ({self.far:.2f} m)"
            )
            return
        self._move((c[0], c[1], c[2]))

    def _move(self, center: tuple[float, float, float]) -> None:
        sel = self._selected_sphere()
        if sel is not None:
            c = (float(center[0]), float(center[1]), float(center[2]))
            self.page.apply(MoveSphere(sel[0], sel[1], c), merge_key=("move", *sel))

    def _dragged_radius(self) -> None:
        """The slider's value, taken only within the slider's range (a value past it comes
        from its number box, should the page's CSS not hide it: typed, not dragged)."""
        value, lo, hi = float(self.radius.value), float(self.radius.min), float(self.radius.max)
        if not lo <= value <= hi:
            self.page.say(
                f"not set: the Radius slider takes {said(lo)} to {said(hi)} m, not {said(value)} "
                "(type the radius in Radius (m))"
            )
            return
        self._resize(value)

    def _resize(self, radius: float) -> None:
        sel = self._selected_sphere()
        if sel is not None:
            edit = SetRadius(sel[0], sel[1], radius)
            self.page.apply(edit, merge_key=("radius", *sel))

    def _add(self) -> None:
        frame = self.link.value
        if self.page.apply(AddSphere(frame, Sphere((0.0, 0.0, 0.0), 0.03))):
            n = len(self.page.state.xrdf.resolved_spheres(self.page.state.group)[frame])
            self.page.pick(frame, n - 1)

    def _on_sphere(self, kind: type[DuplicateSphere] | type[DeleteSphere]) -> None:
        sel = self._selected_sphere()
        if sel is None:
            self.page.say("select a sphere first (click it, or choose it under Spheres)")
            return
        if not self.page.apply(kind(sel[0], sel[1])):
            return
        n = len(self.page.state.xrdf.resolved_spheres(self.page.state.group)[sel[0]])
        if kind is DuplicateSphere:
            self.page.pick(sel[0], n - 1)
        elif n == 0 and sel[0] in self.page.robot.robot.collision_counts:
            self.page.say(
                f"{self.page.message}; warning: '{sel[0]}' has collision geometry and no "
                "spheres now: a planner cannot see it (xrdf lint: mesh-without-spheres)"
            )

    def _connect(self) -> None:
        sel = self._selected_sphere()
        if sel is None:
            self.page.say("select a sphere first, then the sphere to connect it to")
            return
        other = self.other.take(self.page.say)
        count = self.between.take(self.page.say) if other is not None else None
        if other is not None and count is not None:
            self.page.apply(ConnectSpheres(sel[0], sel[1], int(other), int(count)))

    def _scale(self) -> None:
        frame = str(self.link.value)
        factor = self.factor.take(self.page.say)
        if factor is not None:
            self.page.apply(ScaleSpheres(frame, factor))

    def sync_selection(self) -> None:
        """Show the selected link and sphere in the controls and put the gizmo on it."""
        page = self.page
        sel = page.selected
        if sel is None:
            return
        frame, k = sel
        spheres = page.state.xrdf.resolved_spheres(page.state.group).get(frame, ())
        self.link.value = frame
        self.sphere.options = (NONE, *(str(i) for i in range(len(spheres))))
        self.sphere.value = NONE if k is None else str(k)
        if k is not None and k < len(spheres):
            s = spheres[k]
            for field, v in zip(self.center, s.center, strict=True):
                field.show(v)
            self.typed_radius.show(s.radius)
            # the slider reaches every radius it shows (a 0.4 m base sphere is not shown 0.3)
            self.radius.max = max(RADIUS_MAX, math.ceil(s.radius * 10) / 10)
            self.radius.value = float(min(max(s.radius, RADIUS_STEP), self.radius.max))
        self._place_gizmo(frame, None if k is None or k >= len(spheres) else spheres[k], k)

    def _place_gizmo(self, frame: str, sphere: Sphere | None, k: int | None) -> None:
        if sphere is None or k is None:
            if self.gizmo is not None:
                self.gizmo.remove()
                self.gizmo, self.gizmo_for = None, None
            return
        if self.gizmo_for != (frame, k):
            if self.gizmo is not None:
                self.gizmo.remove()
            self.gizmo = self.page.server.scene.add_transform_controls(
                f"{node(frame)}/gizmo",
                scale=max(0.12, 3 * sphere.radius),
                disable_rotations=True,
                depth_test=False,
                position=sphere.center,
            )
            self.gizmo_for = (frame, k)
            gizmo = self.gizmo

            dragging = [False]  # only a drag moves the sphere

            def dragged(e: Any) -> None:
                phase = getattr(e, "phase", "update")
                if phase == "start":
                    dragging[0] = True
                if dragging[0] and from_browser(e) and self.gizmo is gizmo:
                    p = gizmo.position
                    self._move((float(p[0]), float(p[1]), float(p[2])))
                if phase == "end":
                    dragging[0] = False

            gizmo.on_update(dragged)
        elif not np.allclose(self.gizmo.position, sphere.center):
            self.gizmo.position = sphere.center
