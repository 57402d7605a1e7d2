"""The ``geometry`` section: effective sphere sets, per frame and per collision scope.

Each collision section's group is resolved with every ``clone`` merged in, attached-object
slots are left out (:func:`~xrdf_tools.diff.spheres.effective`), and the spheres of each frame
are compared as multisets (:func:`~xrdf_tools.diff.spheres.compare_spheres`). A frame that
differs the same way in the world and the self set is reported once, scope ``world+self``.
Groups that no collision section uses are a mapping of their own: added, removed, or compared
frame by frame like the others, all minor.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

from ..util.errors import GeometryGroupError
from ..util.frozen import FrozenMap
from ..xrdf.model import GeometryGroup, Sphere, Xrdf, resolve_group
from .mapping import MappingRule, OneSided, diff_mapping
from .result import Change, Detail, Level
from .spheres import FrameSpheres, compare_spheres, effective
from .values import plural, union

_SCOPE_LABEL = {"world": "world", "self": "self", "world+self": "world and self"}


def resolved(x: Xrdf, group: str, sec: str) -> FrozenMap[str, tuple[Sphere, ...]]:
    """Spheres per frame of ``group`` in ``x``, clones merged in.

    An undefined or cyclic group raises :class:`GeometryGroupError` located at
    ``<sec>.geometry``: the effective spheres, and so the diff, cannot be known.
    """
    try:
        return resolve_group(x.geometry or FrozenMap(), group)
    except GeometryGroupError as exc:
        line, col = x.source.position(f"{sec}.geometry")
        raise GeometryGroupError(
            f"cannot compare the spheres of {sec}: {exc.message}",
            path=x.source.path or None,
            line=line,
            col=col,
        ) from None


def sphere_count(x: Xrdf, group: str, sec: str) -> int:
    """How many effective spheres (slots left out) ``group`` has in ``x``."""
    return sum(len(effective(s)[0]) for s in resolved(x, group, sec).values())


@dataclass(frozen=True)
class _FrameDiff:
    """One frame of one scope: how its spheres differ, and its attached-object slots."""

    spheres: FrameSpheres
    slots_a: int
    slots_b: int
    group: str  # B's group, for the key path

    def same_as(self, other: _FrameDiff) -> bool:
        """The same difference (the group may differ: world and self use their own)."""
        return (self.spheres, self.slots_a, self.slots_b) == (
            other.spheres,
            other.slots_a,
            other.slots_b,
        )


def _frames(
    ra: Mapping[str, Sequence[Sphere]], rb: Mapping[str, Sequence[Sphere]], group: str, tol: float
) -> dict[str, _FrameDiff]:
    """Every frame of either side compared (a frame one side lacks has no spheres there)."""
    out = {}
    for frame in union(ra, rb):
        ea, pa = effective(ra.get(frame, ()))
        eb, pb = effective(rb.get(frame, ()))
        out[frame] = _FrameDiff(compare_spheres(ea, eb, tol), pa, pb, group)
    return out


def _scope(a: Xrdf, b: Xrdf, scope: str, tol: float) -> dict[str, _FrameDiff] | None:
    """The frames of the world or the self set; ``None`` unless both files have the section."""
    sec = f"{scope}_collision"
    sa = a.world_collision if scope == "world" else a.self_collision
    sb = b.world_collision if scope == "world" else b.self_collision
    if sa is None or sb is None:
        return None
    return _frames(resolved(a, sa.geometry, sec), resolved(b, sb.geometry, sec), sb.geometry, tol)


def _summary(frame: str, fs: FrameSpheres, label: str) -> tuple[str, dict[str, int]]:
    """``panda_link5 (world and self): +3 spheres, radius changed on 2`` and its counts."""
    counts = {
        "added": len(fs.added),
        "removed": len(fs.removed),
        "radius_changed": len(fs.radius_changed),
        "moved": len(fs.moved),
    }
    words = {
        "added": f"+{plural(counts['added'], 'sphere')}",
        "removed": f"-{plural(counts['removed'], 'sphere')}",
        "radius_changed": f"radius changed on {counts['radius_changed']}",
        "moved": f"moved {counts['moved']}",
    }
    counts = {k: n for k, n in counts.items() if n}
    return f"{frame} ({label}): {', '.join(words[k] for k in counts)}", counts


def _details(fs: FrameSpheres) -> tuple[Detail, ...]:
    return (
        *(Detail("removed", s, None) for s in fs.removed),
        *(Detail("added", None, s) for s in fs.added),
        *(Detail("radius-changed", x, y) for x, y in fs.radius_changed),
        *(Detail("moved", x, y) for x, y in fs.moved),
    )


def _report(frames: Mapping[str, _FrameDiff], scope: str, level: Level) -> list[Change]:
    """Per frame: a ``spheres-changed`` change, and a note when the slot counts differ."""
    label = _SCOPE_LABEL.get(scope, scope.replace("group:", "unused group "))
    out = []
    for frame, d in frames.items():
        kp = f"geometry.{d.group}.spheres.{frame}"
        if d.spheres:
            message, counts = _summary(frame, d.spheres, label)
            out.append(
                Change(
                    "geometry",
                    "spheres-changed",
                    message,
                    level=level,
                    subject=frame,
                    key_path=kp,
                    scope=scope,
                    counts=FrozenMap(counts),
                    details=_details(d.spheres),
                )
            )
        if d.slots_a != d.slots_b:
            out.append(
                Change(
                    "geometry",
                    "placeholder-spheres",
                    f"{frame} ({label}): {plural(d.slots_a, 'attached-object slot')} "
                    f"(radius ≤ −1) in A, {d.slots_b} in B; slots are not geometry until cuRobo "
                    "attaches an object (2.0 cannot express them) and are not compared as spheres",
                    level=Level.INFO,
                    subject=frame,
                    key_path=kp,
                    scope=scope,
                    before=d.slots_a,
                    after=d.slots_b,
                )
            )
    return out


def used_groups(x: Xrdf) -> set[str]:
    """Groups whose spheres a collision section uses (directly or through clones)."""
    used: set[str] = set()
    geometry = x.geometry or FrozenMap[str, GeometryGroup]()
    for section in (x.world_collision, x.self_collision):
        if section is None:
            continue
        stack = [section.geometry]
        while stack:
            g = stack.pop()
            if g in used:
                continue
            used.add(g)
            if g in geometry:
                stack.extend(geometry[g].clone)
    return used


def _unused_groups(a: Xrdf, b: Xrdf, tol: float) -> list[Change]:
    """Groups no collision section uses in either file: a mapping of names, all minor.

    A group used in either file is left out here: its spheres are compared under its section
    (and a used group is always defined, or resolving it has already failed).
    """
    used = used_groups(a) | used_groups(b)
    ga = {n: n for n in a.geometry or () if n not in used}
    gb = {n: n for n in b.geometry or () if n not in used}

    def compare(name: str, _a: str, _b: str, tol: float) -> list[Change]:
        sec = f"geometry.{name}"
        frames = _frames(resolved(a, name, sec), resolved(b, name, sec), name, tol)
        return _report(frames, f"group:{name}", Level.MINOR)

    rule: MappingRule[str, str] = MappingRule(
        section="geometry",
        key_path=lambda name: f"geometry.{name}",
        added=OneSided("group-added", lambda name, _: f"unused geometry group '{name}' added"),
        removed=OneSided(
            "group-removed", lambda name, _: f"unused geometry group '{name}' removed"
        ),
        compare=compare,
        level=Level.MINOR,
    )
    return diff_mapping(rule, ga, gb, tol)


def diff_geometry(a: Xrdf, b: Xrdf, tol: float) -> list[Change]:
    """The ``geometry`` section: the world and self sphere sets, then the unused groups."""
    world = _scope(a, b, "world", tol)
    self_ = _scope(a, b, "self", tol)
    both: dict[str, _FrameDiff] = {}
    if world is not None and self_ is not None:
        both = {f: d for f, d in world.items() if f in self_ and self_[f].same_as(d)}
    out = _report(both, "world+self", Level.MAJOR)
    for scope, frames in (("world", world), ("self", self_)):
        if frames is not None:
            rest = {f: d for f, d in frames.items() if f not in both}
            out += _report(rest, scope, Level.MAJOR)
    return out + _unused_groups(a, b, tol)
