"""What the editor's panels see of the page: its state, its locks and its actions.

:class:`PageSurface` is the page as the panels use it (a structural type: ``EditorPage``
satisfies it without naming it), so that the panels depend on this small contract rather
than on the page that builds them. :func:`from_browser` tells an event sent by a browser from
a value the page set itself.
"""

from __future__ import annotations

from collections.abc import Hashable
from pathlib import Path
from typing import TYPE_CHECKING, Any, Protocol

if TYPE_CHECKING:
    import threading

    import numpy as np

    from .edits import Edit
    from .robot import Collisions, EditRobot
    from .state import EditState
    from .view import RobotView

__all__ = ["PageSurface", "from_browser"]


def from_browser(event: Any) -> bool:
    """The event comes from a browser (not from the page setting a value) and holds a value
    its control offers: a choice that is not one of a dropdown's options (a client sends any
    value it likes; the page's own sends none such) is put back to the first option and
    ignored, as the page could only fail on it."""
    if getattr(event, "client", None) is None:
        return False
    target: Any = getattr(event, "target", None)
    options = getattr(target, "options", None)
    if isinstance(options, tuple) and options and target.value not in options:
        target.value = options[0]
        return False
    return True


class PageSurface(Protocol):
    """The editor page as its panels use it."""

    lock: threading.RLock
    robot: EditRobot
    state: EditState
    target: Path
    saved_path: str
    readonly: bool
    report_samples: int
    configs: np.ndarray[Any, Any] | None
    q: np.ndarray[Any, Any]
    collisions: Collisions
    selected: tuple[str, int | None] | None
    message: str
    server: Any
    view: RobotView

    def apply(self, edit: Edit, *, merge_key: Hashable | None = None) -> bool: ...

    def undo(self) -> None: ...

    def redo(self) -> None: ...

    def set_pose(self, q: np.ndarray[Any, Any], *, sliders: bool = True) -> None: ...

    def pick(self, frame: str, index: int | None) -> None: ...

    def save(self) -> bool: ...

    def say(self, message: str) -> None: ...

    def overwrite_warning(self) -> str | None: ...

    def cannot_save(self) -> str | None: ...

    def disk_bytes(self) -> bytes | None: ...

    def refresh(self, *, pose: bool = False, document: bool = False) -> None: ...
