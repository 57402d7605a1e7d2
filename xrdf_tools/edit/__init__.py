"""``xrdf edit``: edit spheres, the self-collision mask, the c-space and default positions in a
browser.

The editing logic is library code, usable from Python and tested without a browser:

* :mod:`.edits` -- the edits (move/resize/add/delete/connect/scale spheres and refit a link:
  :mod:`.sphere_edits`; mask pairs, buffers, default positions, c-space joints and limits,
  tool frames) as frozen values, and :func:`apply_edit`;
* :mod:`.state` -- :class:`EditState`: the document, undo/redo, the diff against what was
  saved, and :func:`save` (canonical, atomic);
* :mod:`.robot` -- :class:`EditRobot`: poses, forward kinematics and the self-collisions at a
  pose with the project's engine;
* :mod:`.fit` -- :func:`propose_fit`: refit one link, with metrics before accepting.

The page (:mod:`.page`, built on viser, the ``edit`` extra) only drives these.
"""

from __future__ import annotations

from .edits import (
    AddSphere,
    ConnectSpheres,
    DeleteSphere,
    DuplicateSphere,
    Edit,
    EditError,
    MoveSphere,
    ReplaceSpheres,
    ScaleSpheres,
    SetBuffer,
    SetCspace,
    SetDefaults,
    SetIgnored,
    SetMask,
    SetRadius,
    SetToolFrames,
    apply_edit,
)
from .robot import Collisions, EditRobot
from .state import EditState, save

__all__ = [
    "AddSphere",
    "Collisions",
    "ConnectSpheres",
    "DeleteSphere",
    "DuplicateSphere",
    "Edit",
    "EditError",
    "EditRobot",
    "EditState",
    "MoveSphere",
    "ReplaceSpheres",
    "ScaleSpheres",
    "SetBuffer",
    "SetCspace",
    "SetDefaults",
    "SetIgnored",
    "SetMask",
    "SetRadius",
    "SetToolFrames",
    "apply_edit",
    "save",
]
