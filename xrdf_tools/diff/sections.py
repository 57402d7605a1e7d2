"""The section rules other than ``modifiers`` and ``geometry``, each a few declarations.

Every section is one or more mappings (:class:`~xrdf_tools.diff.mapping.MappingRule`), fields
(:class:`~xrdf_tools.diff.mapping.FieldRule`) or an order
(:func:`~xrdf_tools.diff.mapping.order_change`); the ``diff_*`` functions here apply them to
two documents and return the changes in document order.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, replace

from ..util.frozen import FrozenMap
from ..xrdf.model import CollisionSection, CSpace, SelfCollisionSection, Xrdf
from .geometry import sphere_count
from .mapping import (
    Changed,
    FieldRule,
    MappingRule,
    OneSided,
    diff_fields,
    diff_mapping,
    diff_optional,
    order_change,
)
from .result import Change, Level
from .values import close, names, num, plural, relative_order

# --- format ----------------------------------------------------------------------------------

_VERSION = FieldRule[Xrdf, str](
    "version-changed",
    get=lambda x: x.format_version,
    message=lambda _, x, y: (
        f"format_version {x} -> {y} (1.0 'collision' and 2.0 "
        "'world_collision' are compared as one section)"
    ),
    key_path=lambda _: "format_version",
    level=Level.MINOR,
)


def diff_format(a: Xrdf, b: Xrdf, tol: float) -> list[Change]:
    """``format_version``, once (the 1.0 and 2.0 spellings of a section are not changes)."""
    return diff_fields("format", "format_version", (_VERSION,), a, b, tol)


# --- default_joint_positions -----------------------------------------------------------------

_DEFAULTS = MappingRule[str, float](
    section="default_joint_positions",
    key_path=lambda joint: f"default_joint_positions.{joint}",
    added=OneSided(
        "default-added", lambda j, v: f"{j} = {num(v)} added (was unset: 0 clamped to the limits)"
    ),
    removed=OneSided(
        "default-removed",
        lambda j, v: f"{j} = {num(v)} removed (now unset: 0 clamped to the limits)",
    ),
    changed=Changed("default-changed", lambda j, x, y: f"{j} = {num(x)} -> {num(y)}"),
    same=close,
)


def diff_defaults(
    a: Xrdf, b: Xrdf, tol: float, unset: Mapping[str, float] | None = None
) -> list[Change]:
    """Default positions: a map of joints (absent and empty are the same).

    ``unset`` is the value a joint's default has when it is not written (0 clamped to its
    URDF limits), when the URDF is known: a default added or removed at that value changes
    nothing, and a note says so (a round trip through a cuRobo config writes a default for
    every joint it locks)."""
    da = a.default_joint_positions or FrozenMap()
    db = b.default_joint_positions or FrozenMap()
    out: list[Change] = []
    for c in diff_mapping(_DEFAULTS, da, db, tol):
        value = c.after if c.kind == "default-added" else c.before
        if (
            unset is not None
            and c.kind in ("default-added", "default-removed")
            and c.subject in unset
            and close(value, unset[c.subject], tol)
        ):
            done = "added" if c.kind == "default-added" else "removed"
            message = (
                f"{c.subject} = {num(value)} {done}: the value it has unset (0 clamped to its "
                "limits), so this changes nothing"
            )
            c = replace(c, kind="default-as-unset", message=message, level=Level.INFO)
        elif unset is None and c.kind in ("default-added", "default-removed") and value == 0.0:
            # a round trip through a cuRobo config writes 0.0 for each joint it locks: only
            # the URDF can show that to be the value the joint has unset
            hint = "; with --urdf: no change if 0 is within its limits)"
            c = replace(c, message=c.message.removesuffix(")") + hint)
        out.append(c)
    return out


# --- cspace ----------------------------------------------------------------------------------


@dataclass(frozen=True)
class _Joint:
    """A c-space joint: where it is first listed, and its limits (``None`` past the list)."""

    index: int
    acceleration: float | None
    jerk: float | None


def _joints(c: CSpace) -> dict[str, _Joint]:
    acc, jerk = c.acceleration_limits, c.jerk_limits
    out: dict[str, _Joint] = {}
    for i, n in enumerate(c.joint_names):
        out.setdefault(
            n, _Joint(i, acc[i] if i < len(acc) else None, jerk[i] if i < len(jerk) else None)
        )
    return out


_JOINTS = MappingRule[str, _Joint](
    section="cspace",
    key_path=lambda _: "cspace.joint_names",
    added=OneSided(
        "joint-added",
        lambda j, v: (
            f"joint {j} added at position {v.index} (acceleration "
            f"{num(v.acceleration)}, jerk {num(v.jerk)})"
        ),
    ),
    removed=OneSided(
        "joint-removed",
        lambda j, v: (
            f"joint {j} removed (was position {v.index}; acceleration "
            f"{num(v.acceleration)}, jerk {num(v.jerk)})"
        ),
    ),
    value=lambda v: {"index": v.index, "acceleration": v.acceleration, "jerk": v.jerk},
)


def _limit(what: str, get: Callable[[_Joint], float | None]) -> FieldRule[_Joint, float | None]:
    """``acceleration`` or ``jerk`` limit of a joint (compared per joint name, so a reorder
    that moves the limits along with the joints changes no limit)."""
    return FieldRule(
        f"{what}-limit-changed",
        get=get,
        message=lambda n, x, y: f"{what} limit of {n}: {num(x)} -> {num(y)}",
        key_path=lambda j: f"cspace.{what}_limits[{j.index}]",
        same=close,
    )


_LIMITS = (_limit("acceleration", lambda j: j.acceleration), _limit("jerk", lambda j: j.jerk))


def _compare_cspace(_: str, ca: CSpace, cb: CSpace, tol: float) -> list[Change]:
    """Joints removed and added, a reorder of the shared ones, then their limits (B's order)."""
    na, nb = ca.joint_names, cb.joint_names
    ja, jb = _joints(ca), _joints(cb)
    out = diff_mapping(_JOINTS, ja, jb, tol, order_a=na, order_b=nb)
    out += order_change(
        "cspace",
        "joints-reordered",
        na,
        nb,
        lambda x, y: f"c-space joint order {x} -> {y} (c-space vectors change meaning)",
        subject="joint_names",
        key_path="cspace.joint_names",
    )
    for j in relative_order(nb, set(na) & set(nb)):
        out += diff_fields("cspace", j, _LIMITS, ja[j], jb[j], tol)
    return out


def _cspace_presence(verb: str) -> OneSided[str, CSpace]:
    return OneSided(
        f"section-{verb}",
        lambda _, c: f"cspace {verb}: {plural(len(c.joint_names), 'joint')} {names(c.joint_names)}",
    )


_CSPACE = MappingRule[str, CSpace](
    section="cspace",
    key_path=lambda _: "cspace",
    added=_cspace_presence("added"),
    removed=_cspace_presence("removed"),
    compare=_compare_cspace,
    value=lambda c: list(c.joint_names),
)


def diff_cspace(a: Xrdf, b: Xrdf, tol: float) -> list[Change]:
    """The c-space: the section itself added or removed, or its joints compared."""
    return diff_optional(_CSPACE, "cspace", a.cspace, b.cspace, tol)


# --- tool_frames -----------------------------------------------------------------------------

_END_EFFECTOR = FieldRule[tuple[str, ...], str | None](
    "end-effector-changed",
    get=lambda frames: frames[0] if frames else None,
    message=lambda _, x, y: f"end effector (first tool frame) {x or '(none)'} -> {y or '(none)'}",
    key_path=lambda _: "tool_frames[0]",
)

_TOOL_FRAMES = MappingRule[str, str](
    section="tool_frames",
    key_path=lambda _: "tool_frames",
    added=OneSided("tool-frame-added", lambda f, _: f"tool frame {f} added"),
    removed=OneSided("tool-frame-removed", lambda f, _: f"tool frame {f} removed"),
)


def diff_tool_frames(a: Xrdf, b: Xrdf, tol: float) -> list[Change]:
    """Tool frames: the first (the end effector), additions, removals, then a reorder."""
    ta, tb = a.tool_frames or (), b.tool_frames or ()
    out = diff_fields("tool_frames", "tool_frames[0]", (_END_EFFECTOR,), ta, tb, tol)
    fa, fb = {f: f for f in ta}, {f: f for f in tb}
    out += diff_mapping(_TOOL_FRAMES, fa, fb, tol, order_a=ta, order_b=tb)
    out += order_change(
        "tool_frames",
        "tool-frames-reordered",
        ta,
        tb,
        lambda x, y: f"tool frame order {x} -> {y}",
        subject="tool_frames",
        key_path="tool_frames",
    )
    return out


# --- world_collision / self_collision --------------------------------------------------------

_Section = CollisionSection | SelfCollisionSection
_Pair = tuple[str, str]

_IGNORE_PAIRS = MappingRule[_Pair, _Pair](
    section="self_collision",
    key_path=lambda _: "self_collision.ignore",
    subject=lambda p: f"{p[0]} <-> {p[1]}",
    added=OneSided("ignore-pair-added", lambda p, _: f"ignore pair {p[0]} <-> {p[1]} added"),
    removed=OneSided("ignore-pair-removed", lambda p, _: f"ignore pair {p[0]} <-> {p[1]} removed"),
    value=list,
)


def _ignore_pairs(s: SelfCollisionSection) -> dict[_Pair, _Pair]:
    """The ignore pairs as a set (names sorted in each pair, pairs sorted)."""
    return {p: p for p in sorted((min(p), max(p)) for p in s.ignore_pairs())}


def _buffers(sec: str) -> MappingRule[str, float]:
    """``buffer_distance`` per frame; a frame that is not listed has 0.0."""
    return MappingRule(
        section=sec,
        key_path=lambda frame: f"{sec}.buffer_distance.{frame}",
        added=OneSided(
            "buffer-added",
            lambda f, y: (
                f"buffer_distance of {f}: 0.0 -> {num(y)} (was not listed; a missing buffer is 0.0)"
            ),
        ),
        removed=OneSided(
            "buffer-removed",
            lambda f, x: (
                f"buffer_distance of {f}: {num(x)} -> 0.0 "
                "(no longer listed; a missing buffer is 0.0)"
            ),
        ),
        changed=Changed(
            "buffer-changed", lambda f, x, y: f"buffer_distance of {f}: {num(x)} -> {num(y)}"
        ),
        same=close,
        missing=0.0,
    )


def _group_name(sec: str) -> FieldRule[_Section, str]:
    return FieldRule(
        "group-renamed",
        get=lambda s: s.geometry,
        message=lambda _, x, y: (
            f"geometry group '{x}' -> '{y}' (naming only; the effective "
            "spheres are compared under geometry)"
        ),
        key_path=lambda _: f"{sec}.geometry",
        level=Level.MINOR,
    )


def _collision_rule(sec: str, a: Xrdf, b: Xrdf) -> MappingRule[str, _Section]:
    """One collision section as a one-key mapping: added, removed, or compared inside."""

    def key(doc: Xrdf) -> str:
        return doc.collision_key if sec == "world_collision" else sec

    def presence(doc: Xrdf, verb: str) -> OneSided[str, _Section]:
        def message(_: str, s: _Section) -> str:
            n = sphere_count(doc, s.geometry, sec)
            return f"{key(doc)} section {verb} (geometry '{s.geometry}', {plural(n, 'sphere')})"

        return OneSided(f"section-{verb}", message, key_path=lambda _: key(doc))

    def compare(_: str, sa: _Section, sb: _Section, tol: float) -> list[Change]:
        out = diff_fields(sec, "geometry", (_group_name(sec),), sa, sb, tol)
        out += diff_mapping(_buffers(sec), sa.buffer_distance, sb.buffer_distance, tol)
        if isinstance(sa, SelfCollisionSection) and isinstance(sb, SelfCollisionSection):
            out += diff_mapping(_IGNORE_PAIRS, _ignore_pairs(sa), _ignore_pairs(sb), tol)
        return out

    return MappingRule(
        section=sec,
        key_path=lambda _: sec,
        added=presence(b, "added"),
        removed=presence(a, "removed"),
        compare=compare,
        value=lambda s: s.geometry,
    )


def diff_collision_sections(a: Xrdf, b: Xrdf, tol: float) -> list[Change]:
    """``world_collision`` (``collision`` in 1.0) and ``self_collision``.

    Each: added or removed (with its sphere count), or its group name (minor; the spheres are
    the ``geometry`` section's), buffers (a missing one is 0.0) and ignore pairs (a set).
    """
    world, self_ = "world_collision", "self_collision"
    return [
        *diff_optional(
            _collision_rule(world, a, b), world, a.world_collision, b.world_collision, tol
        ),
        *diff_optional(
            _collision_rule(self_, a, b), self_, a.self_collision, b.self_collision, tol
        ),
    ]


# --- unknown top-level keys ------------------------------------------------------------------

_EXTRA = MappingRule[str, object](
    section="extra",
    key_path=lambda key: key,
    added=OneSided("key-added", lambda k, _: f"top-level key {k} added"),
    removed=OneSided("key-removed", lambda k, _: f"top-level key {k} removed"),
    changed=Changed("key-changed", lambda k, _x, _y: f"top-level key {k} changed"),
    level=Level.MINOR,
)


def diff_extra(a: Xrdf, b: Xrdf, tol: float) -> list[Change]:
    """Unknown top-level keys, compared as plain data (all minor)."""
    return diff_mapping(_EXTRA, a.extra, b.extra, tol)
