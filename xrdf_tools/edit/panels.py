"""The GUI panels of the ``xrdf edit`` page (viser): document, view, pose, refit, link tree.

Each control calls one :class:`~xrdf_tools.edit.page.PageSurface` method; :meth:`Panels.update`
shows the page's state again. Controls answer only to the browser (``event.client`` set), so
the page can set their values without triggering edits. The c-space, spheres and mask panels
are :mod:`xrdf_tools.edit.cspace_panel`, :mod:`xrdf_tools.edit.sphere_panel` and
:mod:`xrdf_tools.edit.mask_panel`.
"""

from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING, Any, cast

import numpy as np

from ..diff.render import render_text
from ..xrdf.model import Xrdf
from . import markup
from .cspace_panel import CspacePanel
from .edits import SetDefaults
from .markup import code, pre
from .mask_panel import MaskPanel
from .sphere_panel import SpherePanel
from .surface import PageSurface, from_browser
from .typed import TypedNumber, said

if TYPE_CHECKING:
    from ..viz.meshes import MeshKind
    from .fit import FitProposal

__all__ = ["Panels", "from_browser"]


def _link_tree(page: PageSurface) -> str:
    kin = page.robot.kin
    names = kin.frame_names
    children: dict[int, list[int]] = {}
    for i, p in enumerate(kin.parent.tolist()):
        children.setdefault(int(p), []).append(i)
    spheres = page.state.xrdf.resolved_spheres(page.state.group)
    lines: list[str] = []
    stack = [(i, 0) for i in reversed(children.get(-1, []))]
    while stack:
        i, depth = stack.pop()
        n = len(spheres.get(names[i], ()))
        lines.append("  " * depth + f"- {code(names[i])}" + (f" ({n})" if n else ""))
        stack.extend((c, depth + 1) for c in reversed(children.get(i, [])))
    return "\n".join(lines)


class Panels:
    """Every GUI control of the page."""

    def __init__(self, page: PageSurface) -> None:
        self.page = page
        gui = page.server.gui
        self.gui = gui
        self.proposal: FitProposal | None = None
        #: What the last review showed: the document and the target's bytes then. Confirm
        #: writes only that document over only those bytes.
        self.reviewed: tuple[Xrdf, bytes | None] | None = None
        self._document_panel()
        self._view_panel()
        self._pose_panel()
        self.cspace = CspacePanel(page, gui)
        self.spheres = SpherePanel(page, gui)
        self._fit_panel()
        self.mask = MaskPanel(page, gui)
        with gui.add_folder("Link tree", expand_by_default=False):
            self.tree = gui.add_markdown(_link_tree(page))

    # --- document --------------------------------------------------------------------------
    def _document_panel(self) -> None:
        gui, page = self.gui, self.page
        with gui.add_folder("Document"):
            self.status = gui.add_markdown("")
            self.message = gui.add_markdown("")
            undo = gui.add_button("Undo")
            redo = gui.add_button("Redo")
            self.undo_button, self.redo_button = undo, redo
            undo.on_click(lambda e: page.undo() if from_browser(e) else None)
            redo.on_click(lambda e: page.redo() if from_browser(e) else None)
            review = gui.add_button("Save…", disabled=page.readonly)
            review.on_click(lambda e: self.review() if from_browser(e) else None)
            self.confirm = gui.add_button("Confirm save", visible=False, color="red")
            self.confirm.on_click(lambda e: self._confirm() if from_browser(e) else None)
            self.diff = gui.add_markdown("")

    def review(self) -> None:
        """Show the semantic diff of the change (a summary for a draft never saved) and the
        button that saves it."""
        with self.page.lock:
            self.reviewed = (self.page.state.xrdf, self.page.disk_bytes())
            why = self.page.cannot_save()
            if why is not None:
                self.diff.content = f"**Cannot save**: {markup.text(why)}."
                self.confirm.visible = False
                return
            if self.page.state.saved == Xrdf():
                self._review_new()
                return
            d = self.page.state.diff()
            # from the file as it is to the file Confirm writes (-o may name another file)
            d = replace(d, a=replace(d.a, path=self.page.saved_path))
            d = replace(d, b=replace(d.b, path=str(self.page.target)))
            text = render_text(d).rstrip()
            shown = pre(text) if not d.is_equal else _no_semantic_change(self.page.state.dirty)
            warning = self.page.overwrite_warning()
            if warning is not None:
                shown = f"**Warning**: {markup.text(warning)}.\n\n{shown}"
            self.diff.content = shown
            self.confirm.visible = not self.page.readonly

    def _review_new(self) -> None:
        """A draft has no old side to compare with: say what Confirm writes."""
        page = self.page
        x = page.state.xrdf
        spheres = x.resolved_spheres(page.state.group)
        pairs = sum(len(v) for v in x.self_collision.ignore.values()) if x.self_collision else 0
        joints = len(x.cspace.joint_names) if x.cspace else 0
        summary = (
            f"XRDF {x.format_version}, {joints} c-space joint(s), "
            f"{sum(len(v) for v in spheres.values())} sphere(s) on {len(spheres)} link(s), "
            f"{pairs} ignored pair(s)"
        )
        warning = page.overwrite_warning()
        head = f"**Warning**: {markup.text(warning)}.\n\n" if warning else ""
        self.diff.content = (
            f"{head}**New file** {code(page.target)}: {markup.text(summary)}. Confirm save "
            "writes it."
        )
        self.confirm.visible = not page.readonly

    def _confirm(self) -> None:
        """Save what the review showed. When the document was edited since (in this tab or
        another) or another program changed the file, nothing is written: the review is shown
        again, to confirm."""
        page = self.page
        with page.lock:
            if self.reviewed is None:
                page.say("not saved: press Save… first, to see what it writes")
                return
            if self.reviewed != (page.state.xrdf, page.disk_bytes()):
                self.review()
                page.say(
                    "not saved: the document or the file changed since the review; the review "
                    "shows it now: confirm again to save"
                )
                return
            if page.save():
                self.reviewed = None
                self.confirm.visible = False
                self.diff.content = ""

    def show_message(self, message: str) -> None:
        self.message.content = f"_{markup.text(message)}_" if message else ""

    # --- view ------------------------------------------------------------------------------
    def _view_panel(self) -> None:
        gui, page = self.gui, self.page
        with gui.add_folder("View"):
            meshes = gui.add_dropdown(
                "Meshes", ("collision", "visual", "none"), initial_value=page.view.mesh_kind
            )
            buffered = gui.add_checkbox("Buffered radii", False)
            axes = gui.add_checkbox("Frames", False)
            ignored = gui.add_checkbox(
                "Ignored contacts",
                False,
                hint="Colour spheres touching in pairs the mask ignores (orange)",
            )

        def set_meshes(e: Any) -> None:
            if from_browser(e):
                with page.lock:
                    page.view.set_meshes(cast("MeshKind", meshes.value))

        def set_buffered(e: Any) -> None:
            if from_browser(e):
                with page.lock:
                    page.view.set_buffered(buffered.value, page.state.xrdf, page.state.group)
                    page.refresh()

        def set_ignored(e: Any) -> None:
            if from_browser(e):
                with page.lock:
                    page.view.show_ignored = bool(ignored.value)
                    page.refresh()

        ignored.on_update(set_ignored)
        meshes.on_update(set_meshes)
        buffered.on_update(set_buffered)
        axes.on_update(lambda e: page.view.set_axes(axes.value) if from_browser(e) else None)

    # --- pose ------------------------------------------------------------------------------
    def _pose_panel(self) -> None:
        gui, page, robot = self.gui, self.page, self.page.robot
        self.sliders: list[Any] = []
        with gui.add_folder("Pose"):
            self.joint_folder = gui.add_folder("Joints")
            self.rebuild_sliders()
            default = gui.add_button("Default pose")
            default.on_click(
                lambda e: (
                    page.set_pose(robot.default_pose(page.state.xrdf)) if from_browser(e) else None
                )
            )
            self.seed = 0
            rand = gui.add_button("Random pose")
            rand.on_click(lambda e: self._random() if from_browser(e) else None)
            as_default = gui.add_button("Use pose as default", disabled=False)

            as_default.on_click(lambda e: self.use_pose_as_default() if from_browser(e) else None)
            if page.configs is not None:
                n = len(page.configs)
                self.row = TypedNumber(
                    gui, "Configuration", 0, lo=0, hi=max(n - 1, 0), integer=True, hint="from 0"
                )
                self.row.watch(page.say)
                go = gui.add_button(f"Pose configuration (of {n})")
                go.on_click(lambda e: self._pose_row() if from_browser(e) else None)
            with gui.add_folder("Collisions"):
                self.contacts = gui.add_markdown("")

    def rebuild_sliders(self) -> None:
        """One slider per c-space joint (again, after the c-space changed)."""
        page, robot = self.page, self.page.robot
        for s in self.sliders:
            s.remove()
        self.sliders = []
        with self.joint_folder:
            for k, (name, i) in enumerate(zip(robot.cspace, robot.cspace_index, strict=True)):
                lo, hi = float(robot.lower[k]), float(robot.upper[k])
                value = float(np.clip(page.q[i], lo, hi))
                s = self.gui.add_slider(name, lo, hi, step=0.001, initial_value=value)
                s.on_update(self._slider_moved(int(i), s))
                self.sliders.append(s)

    def _pose_row(self) -> None:
        row = self.row.take(self.page.say)
        if row is not None and self.page.configs is not None:
            self.page.set_pose(self.page.configs[int(row)])

    def _slider_moved(self, index: int, slider: Any) -> Any:
        def moved(e: Any) -> None:
            if from_browser(e):
                value, lo, hi = float(slider.value), float(slider.min), float(slider.max)
                if not lo <= value <= hi:  # typed in the slider's box: not posed
                    self.page.say(
                        f"not posed: {slider.label} moves within its limits, {said(lo)} to "
                        f"{said(hi)}, not {said(value)}"
                    )
                    return
                with self.page.lock:
                    q = self.page.q.copy()
                    q[index] = float(slider.value)
                    self.page.set_pose(q, sliders=False)

        return moved

    def use_pose_as_default(self) -> None:
        """Write the pose's c-space values as the default positions; a pose in self-collision
        is taken, with a warning (readers start there, and a mask computed from the file
        ignores the pairs that collide at its default)."""
        page = self.page
        with page.lock:
            if not page.apply(SetDefaults(page.robot.cspace_values(page.q))):
                return
            hits = page.collisions.checked
            if hits:
                first = hits[0]
                page.say(
                    f"{page.message}; warning: this pose is in self-collision "
                    f"({len(hits)} pair(s), first {first.frame_a} ↔ {first.frame_b}): readers "
                    "start there, and a mask computed from the file would ignore those pairs"
                )

    def _random(self) -> None:
        self.seed += 1
        self.page.set_pose(self.page.robot.random_pose(self.page.state.xrdf, self.seed))

    def sync_sliders(self) -> None:
        for s, i in zip(self.sliders, self.page.robot.cspace_index, strict=True):
            s.value = float(np.clip(self.page.q[i], s.min, s.max))

    def sync_selection(self) -> None:
        """Show the selected link and sphere in the Spheres and Mask panels."""
        sel = self.page.selected
        if sel is not None:
            self.spheres.sync_selection()
            self.mask.sync_selection(sel[0])

    # --- refit -----------------------------------------------------------------------------
    def _fit_panel(self) -> None:
        gui = self.gui
        with gui.add_folder("Refit link"):
            self.fit_count = TypedNumber(gui, "Fit spheres", 4, lo=1, hi=64, integer=True)
            self.fit_target = TypedNumber(
                gui,
                "Coverage target",
                0.0,
                lo=0.0,
                hi=1.0,
                hint="0: fit the number of spheres above; else the fewest reaching this share",
            )
            for field in (self.fit_count, self.fit_target):
                field.watch(self.page.say)
            fit = gui.add_button("Fit link")
            self.fit_result = gui.add_markdown("")
            self.accept = gui.add_button("Accept fit", visible=False)
            self.discard = gui.add_button("Discard fit", visible=False)
        fit.on_click(lambda e: self._fit() if from_browser(e) else None)
        self.accept.on_click(lambda e: self._accept() if from_browser(e) else None)
        self.discard.on_click(lambda e: self._drop_proposal() if from_browser(e) else None)

    def _fit(self) -> None:
        from ..util.errors import XrdfToolsError
        from .fit import propose_fit

        page = self.page
        frame = self.spheres.link.value
        target = self.fit_target.take(page.say)
        count = self.fit_count.take(page.say) if target == 0 else None
        if target is None or (target == 0 and count is None):
            return
        current = page.state.xrdf.resolved_spheres(page.state.group).get(frame, ())
        self.fit_result.content = f"_fitting {markup.text(frame)}…_"
        try:
            proposal = propose_fit(
                page.robot.robot,
                frame,
                current,
                count=None if count is None else int(count),
                coverage=target if target > 0 else None,
            )
        except XrdfToolsError as e:
            self.fit_result.content = f"_not fitted: {markup.text(e)}_"
            return
        self.proposal = proposal
        b, a = proposal.before, proposal.after
        self.fit_result.content = (
            f"**{markup.text(frame)}**: proposal in green\n\n"
            "| | now | proposal |\n|---|---:|---:|\n"
            f"| spheres | {b.sphere_count} | {a.sphere_count} |\n"
            f"| coverage | {b.coverage:.1%} | {a.coverage:.1%} |\n"
            f"| surface | {b.surface_coverage:.1%} | {a.surface_coverage:.1%} |\n"
            f"| protrusion p95 | {b.protrusion_p95 * 1000:.1f} mm | "
            f"{a.protrusion_p95 * 1000:.1f} mm |"
        )
        for warning in proposal.warnings:
            self.fit_result.content += f"\n\n**warning**: {markup.text(warning)}"
        with page.lock:
            page.view.show_preview(frame, proposal.spheres)
        self.accept.visible = self.discard.visible = True

    def _accept(self) -> None:
        from .edits import ReplaceSpheres

        p = self.proposal
        if p is not None:
            self.page.apply(ReplaceSpheres(p.frame, p.spheres))
        self._drop_proposal()

    def _drop_proposal(self) -> None:
        self.proposal = None
        with self.page.lock:
            self.page.view.show_preview("", ())
        self.accept.visible = self.discard.visible = False
        self.fit_result.content = ""

    # --- showing the state -----------------------------------------------------------------
    def update(self, *, document: bool) -> None:
        page = self.page
        st = page.state
        if document:
            mark = "unsaved changes" if st.dirty else "saved"
            mode = " · **read-only**" if page.readonly else ""
            self.status.content = f"{code(page.target)} · group {code(st.group)} · {mark}{mode}"
            self.undo_button.disabled = not st.can_undo
            self.redo_button.disabled = not st.can_redo
            self.tree.content = _link_tree(page) if hasattr(self, "tree") else ""
            if page.selected is not None:
                self.sync_selection()
            self.cspace.sync()
        self.contacts.content = _contacts_text(page)
        self.mask.update(document=document)


#: Touching pairs listed under Collisions (of each kind; the rest are counted).
MAX_CONTACTS = 12


def _contacts_text(page: PageSurface) -> str:
    c = page.collisions
    if not c.contacts:
        return "No touching pairs at this pose."
    lines = [f"{len(c.checked)} colliding, {len(c.ignored)} ignored touching pair(s):", ""]
    for kind, items in (("**COLLIDING**", c.checked), ("ignored", c.ignored)):
        for x in items[:MAX_CONTACTS]:
            lines.append(
                f"- {kind} {code(x.frame_a)} ↔ {code(x.frame_b)}: {x.clearance * 1000:.1f} mm "
                f"({x.n_sphere_pairs} sphere pair(s))"
            )
        if len(items) > MAX_CONTACTS:
            lines.append(f"- … and {len(items) - MAX_CONTACTS} more {kind.strip('*').lower()}")
    return "\n".join(lines)


def _no_semantic_change(dirty: bool) -> str:
    """The review of a document the semantic diff finds equal to the file: nothing to save,
    or (``dirty``) a change below the diff's tolerance, which Confirm still writes."""
    if not dirty:
        return "**No changes** to save."
    return (
        "**No semantic change**: the document differs from the file only by less than the "
        "diff's tolerance (or in how a value is written). Confirm writes it as it is."
    )
