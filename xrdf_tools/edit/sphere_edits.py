"""The sphere edits of ``xrdf edit``: move, resize, add, duplicate, delete, connect, scale and
replace a link's spheres, as frozen values, and :func:`edit_spheres`, which makes one.

A sphere is named by its frame and its position in the frame's *resolved* list of the edited
geometry group (clones included, the order every reader and :mod:`xrdf_tools.viz.scene` use);
the sphere is changed in the group that owns it, so a group cloned from another is edited
where its spheres are written.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

from ..util.frozen import FrozenMap
from ..xrdf.model import GeometryGroup, Sphere, Vec3, Xrdf, clone_order
from .checks import EditError, checked_number

__all__ = [
    "MAX_CONNECT",
    "AddSphere",
    "ConnectSpheres",
    "DeleteSphere",
    "DuplicateSphere",
    "MoveSphere",
    "ReplaceSpheres",
    "ScaleSpheres",
    "SetRadius",
    "SphereEdit",
    "edit_spheres",
]

#: The most spheres one :class:`ConnectSpheres` puts between two.
MAX_CONNECT = 32


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
class ConnectSpheres:
    """Put ``count`` spheres between spheres ``first`` and ``second`` of ``frame``: centres
    evenly spaced on the segment between theirs, radii interpolated (a chain along a finger
    or a rod). The new spheres are appended."""

    frame: str
    first: int
    second: int
    count: int

    def describe(self) -> str:
        return (
            f"connect {self.frame}[{self.first}] and {self.frame}[{self.second}] "
            f"with {self.count} sphere(s)"
        )


@dataclass(frozen=True)
class ScaleSpheres:
    """Multiply the radius of every sphere of ``frame`` by ``factor`` (centres stay)."""

    frame: str
    factor: float

    def describe(self) -> str:
        return f"scale the spheres of {self.frame} by {self.factor:g}"


@dataclass(frozen=True)
class ReplaceSpheres:
    """Replace every sphere of ``frame`` (a refit)."""

    frame: str
    spheres: tuple[Sphere, ...]

    def describe(self) -> str:
        return f"replace the spheres of {self.frame} ({len(self.spheres)} sphere(s))"


SphereEdit = (
    MoveSphere
    | SetRadius
    | AddSphere
    | DuplicateSphere
    | DeleteSphere
    | ReplaceSpheres
    | ConnectSpheres
    | ScaleSpheres
)


def _owner(xrdf: Xrdf, group: str, frame: str, index: int) -> tuple[str, int]:
    """The group that holds sphere ``index`` of ``frame``'s resolved list, and its position
    in that group's own list. A negative ``index`` names no sphere (not one counted from the
    end)."""
    geometry = xrdf.geometry or FrozenMap()
    offset = index
    for name in clone_order(geometry, group) if index >= 0 else ():
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


def _check_sphere(sphere: Sphere, *, new_radius: bool = True) -> Sphere:
    """``sphere`` with plain float values, or :class:`EditError`. A radius the edit sets
    (``new_radius``) must be more than 0 (XRDF 2.0 and lint refuse 0); a sphere that only
    moves keeps its radius, even the negative one of a 1.0 attach slot."""
    c = tuple(
        checked_number(f"sphere centre {axis}", v)
        for axis, v in zip("xyz", sphere.center, strict=True)
    )
    radius = checked_number("sphere radius", sphere.radius)
    if new_radius and not radius > 0:
        raise EditError(f"a sphere radius must be more than 0, not {radius:g}")
    return Sphere((c[0], c[1], c[2]), radius)


def _connected(xrdf: Xrdf, group: str, edit: ConnectSpheres) -> tuple[Sphere, ...]:
    """The spheres :class:`ConnectSpheres` adds (validated)."""
    spheres = xrdf.resolved_spheres(group).get(edit.frame, ())
    for k in (edit.first, edit.second):
        if not 0 <= k < len(spheres):
            raise EditError(f"no sphere {k} on frame '{edit.frame}' in geometry group '{group}'")
    if edit.first == edit.second:
        raise EditError("connect two different spheres")
    if not 1 <= edit.count <= MAX_CONNECT:
        raise EditError(f"connect with 1 to {MAX_CONNECT} spheres, not {edit.count}")
    a, b = spheres[edit.first], spheres[edit.second]
    out = []
    for i in range(1, edit.count + 1):
        t = i / (edit.count + 1)
        c = tuple(round(p + t * (q - p), 6) for p, q in zip(a.center, b.center, strict=True))
        r = round(a.radius + t * (b.radius - a.radius), 6)
        out.append(_check_sphere(Sphere((c[0], c[1], c[2]), r)))
    return tuple(out)


def _scaled(xrdf: Xrdf, group: str, edit: ScaleSpheres) -> Xrdf:
    """Every sphere :class:`ScaleSpheres` names, in the group that holds it, scaled."""
    factor = checked_number("scale factor", edit.factor, metres=False)
    if not factor > 0:
        raise EditError(f"a scale factor must be more than 0, not {factor:g}")
    geometry = xrdf.geometry or FrozenMap()
    if not xrdf.resolved_spheres(group).get(edit.frame):
        raise EditError(f"frame '{edit.frame}' has no spheres to scale in group '{group}'")
    out = xrdf
    for name in clone_order(geometry, group):
        own = geometry[name].spheres.get(edit.frame)
        if own:
            new = tuple(_check_sphere(Sphere(s.center, round(s.radius * factor, 6))) for s in own)
            out = _with_group_spheres(out, name, edit.frame, new)
    return out


def edit_spheres(xrdf: Xrdf, group: str, edit: SphereEdit) -> Xrdf:
    geometry = xrdf.geometry or FrozenMap()
    if group not in geometry:
        raise EditError(f"geometry group '{group}' is not defined")
    if isinstance(edit, ScaleSpheres):
        return _scaled(xrdf, group, edit)
    if isinstance(edit, ConnectSpheres):
        added = _connected(xrdf, group, edit)
        name = _holder(xrdf, group, edit.frame)
        own = geometry[name].spheres.get(edit.frame, ()) if name in geometry else ()
        return _with_group_spheres(xrdf, name, edit.frame, (*own, *added))
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
