"""The editing state of ``xrdf edit``: the document, its undo/redo history, what was saved.

:class:`EditState` is a frozen value: :meth:`EditState.apply`, :meth:`EditState.undo` and
:meth:`EditState.redo` return new states, so a caller (the browser page, a script, a test)
keeps whichever it wants. :meth:`EditState.diff` is the semantic difference
(:func:`xrdf_tools.diff.diff_xrdf`) between the saved document and the current one, and
:func:`save` writes the current document canonically (:func:`xrdf_tools.xrdf.io.dump_xrdf`)
through the atomic writer.
"""

from __future__ import annotations

import os
from collections.abc import Hashable
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING

from ..diff import XrdfDiff, diff_xrdf
from ..util.fileio import write_atomic
from ..viz.scene import choose_group
from ..xrdf.io import dump_xrdf
from ..xrdf.model import Xrdf
from .edits import Edit, apply_edit

if TYPE_CHECKING:
    from .robot import EditRobot

__all__ = ["EditState", "save"]


@dataclass(frozen=True)
class EditState:
    """A document being edited.

    ``xrdf`` is the current document, ``saved`` the one on disk (as loaded or last saved),
    ``group`` the geometry group sphere edits act on. ``undo_stack`` holds the earlier
    documents with the label of the edit made after each (most recent last); ``redo_stack``
    the undone ones. Consecutive edits with the same ``merge_key`` (a drag of one sphere, a
    radius slider) make one undo step. With a ``robot``, an edit that brings in a frame or
    joint the robot does not have, or a default position outside its joint's limits, is
    refused (:meth:`EditRobot.check_edit <xrdf_tools.edit.robot.EditRobot.check_edit>`).
    """

    xrdf: Xrdf
    saved: Xrdf
    group: str
    undo_stack: tuple[tuple[Xrdf, str], ...] = ()
    redo_stack: tuple[tuple[Xrdf, str], ...] = ()
    merge_key: Hashable | None = None
    robot: EditRobot | None = field(default=None, compare=False, repr=False)

    @classmethod
    def start(
        cls,
        xrdf: Xrdf,
        *,
        saved: Xrdf | None = None,
        group: str | None = None,
        robot: EditRobot | None = None,
    ) -> EditState:
        """A fresh state for ``xrdf``; ``saved`` is what is on disk (default: ``xrdf`` itself;
        pass an empty document for a draft that was never written). ``group`` defaults to
        the self-collision group (see :func:`xrdf_tools.viz.scene.choose_group`); ``robot``
        is the robot edits are checked against (the page's)."""
        saved = xrdf if saved is None else saved
        return cls(xrdf, saved, choose_group(xrdf, group), robot=robot)

    # --- history ---------------------------------------------------------------------------
    def apply(self, edit: Edit, *, merge_key: Hashable | None = None) -> EditState:
        """The state after ``edit``. An edit that changes nothing leaves the state as it is;
        raises :class:`~xrdf_tools.edit.edits.EditError` for an edit that does not fit the
        document (or its ``robot``)."""
        new = apply_edit(self.xrdf, self.group, edit)
        if new == self.xrdf:
            return self
        if self.robot is not None:
            self.robot.check_edit(self.xrdf, new)
        label = edit.describe()
        if merge_key is not None and merge_key == self.merge_key and self.undo_stack:
            undo = (*self.undo_stack[:-1], (self.undo_stack[-1][0], label))
        else:
            undo = (*self.undo_stack, (self.xrdf, label))
        return replace(self, xrdf=new, undo_stack=undo, redo_stack=(), merge_key=merge_key)

    def undo(self) -> EditState:
        """The state before the last edit (unchanged when there is nothing to undo)."""
        if not self.undo_stack:
            return self
        previous, label = self.undo_stack[-1]
        return replace(
            self,
            xrdf=previous,
            undo_stack=self.undo_stack[:-1],
            redo_stack=(*self.redo_stack, (self.xrdf, label)),
            merge_key=None,
        )

    def redo(self) -> EditState:
        """The state after the last undone edit (unchanged when there is none)."""
        if not self.redo_stack:
            return self
        following, label = self.redo_stack[-1]
        return replace(
            self,
            xrdf=following,
            undo_stack=(*self.undo_stack, (self.xrdf, label)),
            redo_stack=self.redo_stack[:-1],
            merge_key=None,
        )

    def end_merge(self) -> EditState:
        """The next edit starts a new undo step even if its merge key repeats."""
        return self if self.merge_key is None else replace(self, merge_key=None)

    @property
    def can_undo(self) -> bool:
        return bool(self.undo_stack)

    @property
    def can_redo(self) -> bool:
        return bool(self.redo_stack)

    @property
    def undo_label(self) -> str | None:
        return self.undo_stack[-1][1] if self.undo_stack else None

    @property
    def redo_label(self) -> str | None:
        return self.redo_stack[-1][1] if self.redo_stack else None

    # --- the change ------------------------------------------------------------------------
    @property
    def dirty(self) -> bool:
        """The current document differs from the saved one (as written: byte for byte)."""
        return self.text() != dump_xrdf(self.saved)

    def diff(self, *, root_frame: str | None = None) -> XrdfDiff:
        """The semantic difference from the saved document to the current one."""
        return diff_xrdf(self.saved, self.xrdf, root_frame=root_frame)

    def text(self) -> str:
        """The current document, canonically written."""
        return dump_xrdf(self.xrdf)


def save(state: EditState, path: str | os.PathLike[str]) -> EditState:
    """Write ``state``'s document to ``path`` (atomically, canonical form) and return the
    state with it as the saved document. The undo history is kept."""
    write_atomic(path, state.text())
    return replace(state, saved=state.xrdf, merge_key=None)
