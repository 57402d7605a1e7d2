"""The edits ``xrdf edit`` makes to a document: small frozen values and one pure function.

:func:`apply_edit` turns an :class:`~xrdf_tools.xrdf.model.Xrdf` and an :data:`Edit` into a new
``Xrdf`` (the model is frozen; nothing is changed in place). Sphere edits name a sphere by its
frame and its position in the frame's *resolved* list of the edited geometry group (clones
included, the order every reader and :mod:`xrdf_tools.viz.scene` use); the sphere is changed in
the group that owns it, so a group cloned from another is edited where its spheres are written.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace

from ..util.errors import XrdfToolsError
from ..util.frozen import FrozenMap
from ..util.numbers import bound_reason
from ..xrdf.model import (
    CSpace,
    GeometryGroup,
    SelfCollisionSection,
    Sphere,
    Vec3,
    Xrdf,
    clone_order,
)

__all__ = [
    "AddSphere",
    "DeleteSphere",
    "DuplicateSphere",
    "Edit",
    "EditError",
    "MoveSphere",
    "ReplaceSpheres",
    "SetBuffer",
    "SetCspace",
    "SetDefaults",
    "SetIgnored",
    "SetMask",
    "SetRadius",
    "SetToolFrames",
    "apply_edit",
]


class EditError(XrdfToolsError):
    """An edit that does not fit the document (unknown sphere, no self_collision section)."""


@dataclass(frozen=True)
class MoveSphere:
    """Move sphere ``index`` of ``frame`` to ``center`` (frame coordinates, metres)."""

    frame: str
    index: int
    center: Vec3

    def describe(self) -> str:
        x, y, z = self.center
        return f"move {self.frame}[{self.index}] to ({x:.4f}, {y:.4f}, {z:.4f})"


@dataclass(frozen=True)
class SetRadius:
    """Set the radius of sphere ``index`` of ``frame`` (metres)."""

    frame: str
    index: int
    radius: float

    def describe(self) -> str:
        return f"radius of {self.frame}[{self.index}] to {self.radius:.4f}"


@dataclass(frozen=True)
class AddSphere:
    """Append ``sphere`` to ``frame``'s spheres."""

    frame: str
    sphere: Sphere

    def describe(self) -> str:
        return f"add a sphere to {self.frame}"


@dataclass(frozen=True)
class DuplicateSphere:
    """Append a copy of sphere ``index`` of ``frame``, shifted by half its radius along x so
    that it can be seen and grabbed."""

    frame: str
    index: int

    def describe(self) -> str:
        return f"duplicate {self.frame}[{self.index}]"


@dataclass(frozen=True)
class DeleteSphere:
    """Remove sphere ``index`` of ``frame``."""

    frame: str
    index: int

    def describe(self) -> str:
        return f"delete {self.frame}[{self.index}]"


@dataclass(frozen=True)
class ReplaceSpheres:
    """Replace every sphere of ``frame`` (a refit)."""

    frame: str
    spheres: tuple[Sphere, ...]

    def describe(self) -> str:
        return f"replace the spheres of {self.frame} ({len(self.spheres)} sphere(s))"


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
    what any document needs: at least one joint, no joint twice, one positive finite limit of
    each kind per joint. ``label`` says what changed (shown in the undo history)."""

    cspace: CSpace
    label: str = "set the c-space"

    def describe(self) -> str:
        return self.label


@dataclass(frozen=True)
class SetToolFrames:
    """Replace ``tool_frames`` (the frames a planner can put a goal on), in order."""

    frames: tuple[str, ...]

    def describe(self) -> str:
        return f"tool frames to {', '.join(self.frames) or '(none)'}"


Edit = (
    MoveSphere
    | SetRadius
    | AddSphere
    | DuplicateSphere
    | DeleteSphere
    | ReplaceSpheres
    | SetIgnored
    | SetMask
    | SetBuffer
    | SetDefaults
    | SetCspace
    | SetToolFrames
)


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
                k: _number(f"default position of {k}", v, metres=False)
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
    return _edit_spheres(xrdf, group, edit)


def _checked_cspace(cspace: CSpace) -> CSpace:
    """``cspace`` with plain float limits, or :class:`EditError`: no joint, a joint named
    twice, lists of other lengths, or a limit that is not a positive number a file can hold."""
    names = tuple(cspace.joint_names)
    if not names:
        raise EditError("the c-space needs at least one joint (every reader refuses an empty one)")
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
            v = _number(f"{kind} limit of {name}", value, metres=False)
            if not v > 0:
                raise EditError(f"the {kind} limit of {name} must be more than 0, not {v:g}")
            checked.append(v)
        limits.append(tuple(checked))
    return CSpace(names, limits[0], limits[1])


# --------------------------------------------------------------------------------------------
# Spheres
# --------------------------------------------------------------------------------------------
def _owner(xrdf: Xrdf, group: str, frame: str, index: int) -> tuple[str, int]:
    """The group that holds sphere ``index`` of ``frame``'s resolved list, and its position
    in that group's own list."""
    geometry = xrdf.geometry or FrozenMap()
    offset = index
    for name in clone_order(geometry, group):
        own = geometry[name].spheres.get(frame, ())
        if offset < len(own):
            return name, offset
        offset -= len(own)
    raise EditError(f"no sphere {index} on frame '{frame}' in geometry group '{group}'")


def _holder(xrdf: Xrdf, group: str, frame: str) -> str:
    """The group new spheres of ``frame`` go into: the first one (in clone order) that already
    has spheres on the frame, else ``group`` itself."""
    geometry = xrdf.geometry or FrozenMap()
    for name in clone_order(geometry, group):
        if frame in geometry[name].spheres:
            return name
    return group


def _with_group_spheres(
    xrdf: Xrdf, name: str, frame: str, spheres: tuple[Sphere, ...] | None
) -> Xrdf:
    """``xrdf`` with group ``name``'s spheres of ``frame`` set (None: the entry removed)."""
    geometry = dict(xrdf.geometry or {})
    old = geometry.get(name, GeometryGroup())
    per = dict(old.spheres)
    if spheres is None:
        per.pop(frame, None)
    else:
        per[frame] = spheres
    geometry[name] = replace(old, spheres=FrozenMap(per))
    return xrdf.replace(geometry=FrozenMap(geometry))


def _number(what: str, value: float, *, metres: bool = True) -> float:
    """``value`` as a float, or :class:`EditError` when a saved file could not hold it
    (not finite, or past the bound every reader applies: see :mod:`xrdf_tools.util.numbers`)."""
    v = float(value)
    reason = bound_reason(v, metres=metres)
    if reason is not None:
        raise EditError(f"{what} {v:g} cannot be saved: {reason}")
    return v


def _check_sphere(sphere: Sphere, *, new_radius: bool = True) -> Sphere:
    """``sphere`` with plain float values, or :class:`EditError`. A radius the edit sets
    (``new_radius``) must be more than 0 (XRDF 2.0 and lint refuse 0); a sphere that only
    moves keeps its radius, even the negative one of a 1.0 attach slot."""
    c = tuple(
        _number(f"sphere centre {axis}", v) for axis, v in zip("xyz", sphere.center, strict=True)
    )
    radius = _number("sphere radius", sphere.radius)
    if new_radius and not radius > 0:
        raise EditError(f"a sphere radius must be more than 0, not {radius:g}")
    return Sphere((c[0], c[1], c[2]), radius)


def _edit_spheres(
    xrdf: Xrdf,
    group: str,
    edit: MoveSphere | SetRadius | AddSphere | DuplicateSphere | DeleteSphere | ReplaceSpheres,
) -> Xrdf:
    geometry = xrdf.geometry or FrozenMap()
    if group not in geometry:
        raise EditError(f"geometry group '{group}' is not defined")
    if isinstance(edit, AddSphere):
        name = _holder(xrdf, group, edit.frame)
        own = geometry[name].spheres.get(edit.frame, ()) if name in geometry else ()
        return _with_group_spheres(xrdf, name, edit.frame, (*own, _check_sphere(edit.sphere)))
    if isinstance(edit, ReplaceSpheres):
        name = _holder(xrdf, group, edit.frame)
        out = xrdf
        for other in clone_order(geometry, group):
            if other != name and edit.frame in geometry[other].spheres:
                out = _with_group_spheres(out, other, edit.frame, None)
        new = tuple(_check_sphere(s) for s in edit.spheres)
        return _with_group_spheres(out, name, edit.frame, new)
    name, k = _owner(xrdf, group, edit.frame, edit.index)
    items = list(geometry[name].spheres[edit.frame])
    old = items[k]
    if isinstance(edit, MoveSphere):
        items[k] = _check_sphere(Sphere(edit.center, old.radius), new_radius=False)
    elif isinstance(edit, SetRadius):
        items[k] = _check_sphere(Sphere(old.center, edit.radius))
    elif isinstance(edit, DuplicateSphere):
        shift = max(old.radius, 0.0) * 0.5
        x, y, z = old.center
        copy = Sphere((round(x + shift, 6), y, z), old.radius)
        items.append(_check_sphere(copy, new_radius=False))
    else:  # DeleteSphere
        del items[k]
    return _with_group_spheres(xrdf, name, edit.frame, tuple(items))


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
        distance = _number("buffer distance", edit.distance)
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
