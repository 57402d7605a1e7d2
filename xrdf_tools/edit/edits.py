"""The edits ``xrdf edit`` makes to a document: small frozen values and one pure function.

:func:`apply_edit` turns an :class:`~xrdf_tools.xrdf.model.Xrdf` and an :data:`Edit` into a new
``Xrdf`` (the model is frozen; nothing is changed in place). The sphere edits are
:mod:`xrdf_tools.edit.sphere_edits` (re-exported here); the mask, buffer, default position,
c-space and tool frame edits are here.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace

from ..util.frozen import FrozenMap
from ..xrdf.model import CSpace, SelfCollisionSection, Xrdf
from .checks import EditError, checked_number
from .sphere_edits import (
    AddSphere,
    ConnectSpheres,
    DeleteSphere,
    DuplicateSphere,
    MoveSphere,
    ReplaceSpheres,
    ScaleSpheres,
    SetRadius,
    SphereEdit,
    edit_spheres,
)

__all__ = [
    "AddSphere",
    "ConnectSpheres",
    "DeleteSphere",
    "DuplicateSphere",
    "Edit",
    "EditError",
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
]


@dataclass(frozen=True)
class SetIgnored:
    """Ignore (or check again) the self-collision frame pair ``frame_a``/``frame_b``."""

    frame_a: str
    frame_b: str
    ignored: bool

    def describe(self) -> str:
        verb = "ignore" if self.ignored else "check"
        return f"{verb} {self.frame_a} <-> {self.frame_b}"


@dataclass(frozen=True)
class SetMask:
    """Replace the whole ``self_collision.ignore`` mask (e.g. a report's recommendation)."""

    ignore: Mapping[str, tuple[str, ...]]
    label: str = "replace the self-collision mask"

    def describe(self) -> str:
        return self.label


@dataclass(frozen=True)
class SetBuffer:
    """Set the self-collision buffer distance of ``frame`` (metres)."""

    frame: str
    distance: float

    def describe(self) -> str:
        return f"buffer of {self.frame} to {self.distance:.4f}"


@dataclass(frozen=True)
class SetDefaults:
    """Set ``default_joint_positions`` of the given joints (others are kept)."""

    positions: Mapping[str, float]

    def describe(self) -> str:
        return f"default positions of {len(self.positions)} joint(s)"


@dataclass(frozen=True)
class SetCspace:
    """Replace the c-space: its joints (in order) with their acceleration and jerk limits.

    Which joints a robot can have in its c-space is the robot's to say
    (:meth:`xrdf_tools.edit.robot.EditRobot.cspace_joint_choices`); the edit itself checks
    what any document needs: no joint twice, one positive finite limit of each kind per
    joint. ``label`` says what changed (shown in the undo history)."""

    cspace: CSpace
    label: str = "set the c-space"

    def describe(self) -> str:
        return self.label


@dataclass(frozen=True)
class SetToolFrames:
    """Replace ``tool_frames`` (the frames a planner can put a goal on), in order."""

    frames: tuple[str, ...]
    label: str = ""

    def describe(self) -> str:
        return self.label or f"tool frames to {', '.join(self.frames) or '(none)'}"


Edit = SphereEdit | SetIgnored | SetMask | SetBuffer | SetDefaults | SetCspace | SetToolFrames


def apply_edit(xrdf: Xrdf, group: str, edit: Edit) -> Xrdf:
    """``xrdf`` with ``edit`` made; sphere edits act on geometry group ``group``.

    Raises :class:`EditError` for a sphere that does not exist, a radius set to 0 or less, a
    negative buffer, a number a saved file cannot hold (NaN, infinite, past the readers'
    bounds), or a mask edit without a ``self_collision`` section.
    """
    if isinstance(edit, (SetIgnored, SetMask, SetBuffer)):
        return _edit_self_collision(xrdf, edit)
    if isinstance(edit, SetDefaults):
        merged = dict(xrdf.default_joint_positions or {})
        merged.update(
            {
                k: checked_number(f"default position of {k}", v, metres=False)
                for k, v in edit.positions.items()
            }
        )
        return xrdf.replace(default_joint_positions=FrozenMap(merged))
    if isinstance(edit, SetCspace):
        return xrdf.replace(cspace=_checked_cspace(edit.cspace))
    if isinstance(edit, SetToolFrames):
        if len(set(edit.frames)) != len(edit.frames):
            raise EditError("a tool frame is named twice")
        return xrdf.replace(tool_frames=tuple(edit.frames))
    return edit_spheres(xrdf, group, edit)


def _checked_cspace(cspace: CSpace) -> CSpace:
    """``cspace`` with plain float limits, or :class:`EditError`: a joint named twice, lists
    of other lengths, or a limit that is not a positive number a file can hold. An empty
    c-space is valid XRDF (a document of a robot does not leave its last joint out: see
    :mod:`xrdf_tools.edit.robot_checks`)."""
    names = tuple(cspace.joint_names)
    twice = sorted({n for n in names if names.count(n) > 1})
    if twice:
        raise EditError(f"c-space joint '{twice[0]}' is named twice")
    limits: list[tuple[float, ...]] = []
    for kind, values in (
        ("acceleration", cspace.acceleration_limits),
        ("jerk", cspace.jerk_limits),
    ):
        if len(values) != len(names):
            raise EditError(f"{len(values)} {kind} limit(s) for {len(names)} c-space joint(s)")
        checked = []
        for name, value in zip(names, values, strict=True):
            v = checked_number(f"{kind} limit of {name}", value, metres=False)
            if not v > 0:
                raise EditError(f"the {kind} limit of {name} must be more than 0, not {v:g}")
            checked.append(v)
        limits.append(tuple(checked))
    return CSpace(names, limits[0], limits[1])


# --------------------------------------------------------------------------------------------
# Self-collision section
# --------------------------------------------------------------------------------------------
def _without(ignore: dict[str, list[str]], a: str, b: str) -> None:
    for x, y in ((a, b), (b, a)):
        if x in ignore:
            ignore[x] = [o for o in ignore[x] if o != y]
            if not ignore[x]:
                del ignore[x]


def _edit_self_collision(xrdf: Xrdf, edit: SetIgnored | SetMask | SetBuffer) -> Xrdf:
    sc = xrdf.self_collision
    if sc is None:
        raise EditError("the XRDF has no self_collision section: there is no mask to edit")
    if isinstance(edit, SetMask):
        ignore = FrozenMap((a, tuple(bs)) for a, bs in edit.ignore.items())
        return xrdf.replace(self_collision=replace(sc, ignore=ignore))
    if isinstance(edit, SetBuffer):
        distance = checked_number("buffer distance", edit.distance)
        if not distance >= 0:
            raise EditError(f"a buffer distance must be 0 or more, not {distance:g}")
        buffers = dict(sc.buffer_distance)
        if distance == 0 and edit.frame not in buffers:
            return xrdf
        buffers[edit.frame] = distance
        return xrdf.replace(self_collision=replace(sc, buffer_distance=FrozenMap(buffers)))
    a, b = edit.frame_a, edit.frame_b
    if a == b:
        raise EditError(f"a frame pair needs two different frames, got '{a}' twice")
    mask = {k: list(v) for k, v in sc.ignore.items()}
    if edit.ignored:
        if sc.is_ignored(a, b):
            return xrdf
        if a in mask or b not in mask:
            mask.setdefault(a, []).append(b)
        else:
            mask[b].append(a)
    else:
        _without(mask, a, b)
    new = SelfCollisionSection(
        sc.geometry, sc.buffer_distance, FrozenMap((k, tuple(v)) for k, v in mask.items())
    )
    return xrdf.replace(self_collision=new)
