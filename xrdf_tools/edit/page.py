"""The ``xrdf edit`` page: a viser server whose GUI drives an :class:`EditState`.

Everything the page changes goes through :meth:`EditorPage.apply` (an
:class:`~xrdf_tools.edit.edits.Edit` on the state), :meth:`EditorPage.set_pose` or
:meth:`EditorPage.save`; the page holds no editing logic of its own. GUI callbacks run in
viser's worker threads, so the state is guarded by a lock. Saving writes only to the path given
when the page was made (no path comes from the browser).
"""

from __future__ import annotations

import contextlib
import io
import os
import threading
from collections.abc import Callable, Hashable
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..util.errors import XrdfToolsError
from ..util.fileio import check_output_path, read_input_bytes
from ..util.numbers import REPORT_SAMPLES
from .edits import Edit
from .guard import WILDCARD_HOSTS, RequestGuard, check_address, start_guarded
from .notices import Notices
from .robot import Collisions, EditRobot
from .state import EditState, save
from .view import RobotView

if TYPE_CHECKING:
    from ..diagnostics import Diagnostic
    from ..robot.core import Robot
    from ..robot.packages import PackagePaths
    from .panels import Panels

__all__ = ["EditorPage"]


class EditorPage:
    """A running editor: viser server, 3D view and GUI panels over one document.

    ``target`` is the only file :meth:`save` writes; ``readonly`` disables saving.
    ``configs`` is a configurations file whose rows can be posed from the page. Only the
    page this server serves may drive it (:mod:`.guard`); ``on_refused`` hears, in one line,
    why another request was refused or a malformed one dropped (viser and websockets printed
    a traceback).
    """

    def __init__(
        self,
        robot: Robot,
        state: EditState,
        *,
        target: str | os.PathLike[str],
        host: str = "127.0.0.1",
        port: int = 8080,
        readonly: bool = False,
        configs: str | os.PathLike[str] | None = None,
        package_paths: PackagePaths | None = None,
        meshes: str = "collision",
        report_samples: int = REPORT_SAMPLES,
        on_refused: Callable[[str], None] | None = None,
    ) -> None:
        import viser

        from .panels import Panels

        self.lock = threading.RLock()
        self.robot = EditRobot(robot, state.xrdf)
        self.state = replace(state, robot=self.robot)  # edits are checked against the robot
        self.target = Path(target)
        #: The file the saved document was read from or last written to (the diff's old side).
        self.saved_path = state.saved.source.path or str(self.target)
        self.readonly = readonly
        #: The samples the page's report starts with (``xrdf report``'s default).
        self.report_samples = report_samples
        #: The target's bytes as last read or written (None: it did not exist), to tell when
        #: another program changed it since.
        self.on_disk = _read_bytes(self.target)
        self.configs: np.ndarray[Any, Any] | None = None
        if configs is not None:
            from ..selfcollision.configurations import load_configurations

            self.configs = load_configurations(configs, self.robot.kin, state.xrdf)
        self.q = self.robot.default_pose(state.xrdf)
        self.collisions = Collisions()
        # the link the Spheres panel shows first is selected: a buffer typed for it is set
        self.selected: tuple[str, int | None] | None = (self.robot.frame_names[0], None)
        self.message = ""
        self._stop = threading.Event()
        #: What every request passes before viser sees it: only this server's own page.
        self.guard = RequestGuard(host, on_refused)
        self.on_refused = on_refused
        check_address(host)
        with contextlib.redirect_stdout(io.StringIO()):  # viser prints its own banner
            self.server = start_guarded(
                lambda: viser.ViserServer(host=host, port=port, verbose=False),
                self.guard,
                close=_stop_server,
            )
        try:
            self.server.get_event_loop().call_soon_threadsafe(
                self.server.get_event_loop().set_exception_handler, self.guard.loop_error
            )
            self._configure()
            self.view = RobotView(
                self.server, self.robot, on_pick=self.pick, package_paths=package_paths
            )
            self.view.set_meshes(meshes)  # type: ignore[arg-type]
            self.view.set_tool_frames(state.xrdf.tool_frames or ())
            self.notices = Notices(self.server)
            self.panels: Panels = Panels(self)
            self.refresh(pose=True, document=True)
        except BaseException:
            self.close()
            raise

    def _configure(self) -> None:
        """Theme, camera and ground; no public share link (the page edits local files)."""
        server = self.server
        server.gui.configure_theme(control_width="large", show_share_button=False, show_logo=False)

        def no_share(*_: object, **__: object) -> None:
            return None

        server.request_share_url = no_share  # type: ignore[method-assign]
        server.scene.set_up_direction("+z")
        server.scene.add_grid("/ground", width=2.0, height=2.0, cell_size=0.1)
        reach = self.robot.reach(self.q)
        d = max(reach, 0.5) * 1.6
        server.initial_camera.position = (d, d * 0.8, d * 0.7)
        server.initial_camera.look_at = (0.0, 0.0, reach * 0.4)

    # --- facts -----------------------------------------------------------------------------
    @property
    def url(self) -> str:
        host = self.server.get_host()
        shown = "127.0.0.1" if host in WILDCARD_HOSTS else host
        if ":" in shown:
            shown = f"[{shown}]"
        return f"http://{shown}:{self.server.get_port()}"

    @property
    def diagnostics(self) -> list[Diagnostic]:
        return [*self.robot.diagnostics, *self.view.diagnostics]

    # --- driving the state -----------------------------------------------------------------
    def apply(self, edit: Edit, *, merge_key: Hashable | None = None) -> bool:
        """Make ``edit``; a refused edit becomes the page's message. True when it was made."""
        with self.lock:
            try:
                new = self.state.apply(edit, merge_key=merge_key)
            except XrdfToolsError as e:
                self.say(f"not done: {e}")
                if self.selected is not None:  # the fields show the document, not the refusal
                    self.panels.sync_selection()
                return False
            changed = new is not self.state
            self.state = new
            if changed:
                self.say(f"done: {edit.describe()}")
                self.refresh(document=True)
            elif merge_key is None:  # a button, not a drag or a slider passing the same value
                self.say(f"no change: {edit.describe()} (the document has it already)")
            return changed

    def undo(self) -> None:
        with self.lock:
            label = self.state.undo_label
            self.state = self.state.undo()
            self.say(f"undone: {label}" if label else "nothing to undo")
            self.refresh(document=True)

    def redo(self) -> None:
        with self.lock:
            label = self.state.redo_label
            self.state = self.state.redo()
            self.say(f"redone: {label}" if label else "nothing to redo")
            self.refresh(document=True)

    def set_pose(self, q: np.ndarray[Any, Any], *, sliders: bool = True) -> None:
        """Pose the robot at ``q`` (every actuated joint); ``sliders`` moves the sliders too."""
        with self.lock:
            self.q = np.array(q, dtype=np.float64)
            if sliders:
                self.panels.sync_sliders()
            self.refresh(pose=True)

    def pick(self, frame: str, index: int | None) -> None:
        """Select a link (and one of its spheres) -- from a click or the GUI."""
        with self.lock:
            self.selected = (frame, index)
            self.state = self.state.end_merge()
            self.panels.sync_selection()
            self.view.color_spheres(self.collisions, self.selected)

    def save(self) -> bool:
        """Write the document to the target file. Refused when read-only (``--readonly``, or
        a target file without write permission); a failure is said on the page and to
        ``on_refused`` (the terminal), and leaves the file as it was."""
        with self.lock:
            if self.readonly:
                self.say("read-only: saving is disabled (started with --readonly)")
                return False
            why = self.cannot_save()
            if why is None:
                try:
                    self.state = save(self.state, self.target)
                except (XrdfToolsError, OSError) as e:
                    why = str(e)
            if why is not None:
                self.say(f"not saved: {why}")
                if self.on_refused is not None:
                    self.on_refused(f"not saved: {why}")
                return False
            self.saved_path = str(self.target)
            self.on_disk = _read_bytes(self.target)
            self.say(f"saved {self.target}")
            self.refresh(document=True)
            return True

    def cannot_save(self) -> str | None:
        """Why Save would not write the target, known before trying (a file nobody may write,
        a directory: :func:`~xrdf_tools.util.fileio.check_output_path`)."""
        try:
            check_output_path(self.target)
        except XrdfToolsError as e:
            return str(e)
        return None

    def disk_bytes(self) -> bytes | None:
        """The target's bytes now (None: no file there)."""
        return _read_bytes(self.target)

    def overwrite_warning(self) -> str | None:
        """What Save would replace that the page has not shown: the target changed on disk
        since it was read or saved (another program wrote it), or it is another existing file
        (``-o``). None when Save only replaces what the page read."""
        now = _read_bytes(self.target)
        if now is None or (now == self.on_disk and self.saved_path == str(self.target)):
            return None
        if self.on_disk is None:
            return (
                f"{self.target} was written by another program since the page started; "
                "saving replaces it"
            )
        if now != self.on_disk:
            return f"{self.target} changed on disk since the page read it; saving replaces it"
        return f"{self.target} exists; saving replaces it"

    def say(self, message: str) -> None:
        """Record ``message`` in the Document panel and, when the user must see it (a refusal,
        a warning, a save), show it over the view in every tab (:mod:`.notices`)."""
        with self.lock:
            self.message = message
            if hasattr(self, "panels"):
                self.panels.show_message(message)
                self.notices.show(message)

    # --- redrawing -------------------------------------------------------------------------
    def refresh(self, *, pose: bool = False, document: bool = False) -> None:
        """Bring the view and the panels up to date after a pose and/or document change."""
        with self.lock:
            if document:
                self._follow_document()
                self.view.set_spheres(self.state.xrdf, self.state.group)
                sel = self.selected
                if sel is not None and sel[1] is not None:
                    n = len(self.state.xrdf.resolved_spheres(self.state.group).get(sel[0], ()))
                    if sel[1] >= n:
                        self.selected = (sel[0], n - 1 if n else None)
            if pose:
                self.view.set_pose(self.q)
            self.collisions = self.robot.collisions(self.state.xrdf, self.q)
            self.view.color_spheres(self.collisions, self.selected)
            self.panels.update(document=document)

    def _follow_document(self) -> None:
        """After an edit, undo or redo: the sliders follow the c-space (a joint left out goes
        back to its default position, as every reader holds it) and the view the tool
        frames."""
        x = self.state.xrdf
        if self.robot.follow(x):
            q = self.robot.default_pose(x)
            q[self.robot.cspace_index] = self.q[self.robot.cspace_index]
            self.q = q
            self.panels.rebuild_sliders()
            self.view.set_pose(self.q)
        tools = tuple(x.tool_frames or ())
        if tools != self.view.shown_tool_frames:
            self.view.set_tool_frames(tools)

    # --- running ---------------------------------------------------------------------------
    def serve_forever(self) -> None:
        """Serve until Ctrl-C (or :meth:`stop`), then shut the server down."""
        try:
            while not self._stop.wait(0.25):
                pass
        except KeyboardInterrupt:
            pass
        finally:
            self.close()

    def stop(self) -> None:
        self._stop.set()

    def close(self) -> None:
        self._stop.set()
        _stop_server(self.server)


def _stop_server(server: Any) -> None:
    with contextlib.redirect_stdout(io.StringIO()):  # viser says it stopped
        server.stop()


def _read_bytes(path: Path) -> bytes | None:
    """The target's bytes through the guarded reader (a FIFO or device put there is not
    opened), None when there is no file to read."""
    try:
        return read_input_bytes(path)
    except XrdfToolsError:
        return None
