"""The ``modifiers`` section: the base frame, added frames, mimic removals, and their order.

``set_base_frame`` is compared by its effect (the last one wins; on the URDF's root link it is
no change). The other modifiers are a mapping keyed by what they act on (``add_frame`` by
``frame_name``, ``remove_mimic_attributes`` by joint): added, removed, or compared — an added
frame field by field, with rotations compared as rotations. A different order of the same
modifiers is a minor change.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Callable, Sequence
from typing import Any

from ..xrdf.model import AddFrame, Modifier, Orientation, RemoveMimicAttributes, SetBaseFrame, Xrdf
from .mapping import (
    MISSING,
    Changed,
    FieldRule,
    MappingRule,
    OneSided,
    diff_fields,
    diff_key,
    order_change,
)
from .result import Change, Level
from .values import close, close_all, names, num, union, vec

#: A modifier's identity: (modifier kind, what it acts on, how many of those came before).
_Key = tuple[str, str, int]


def _keyed(mods: Sequence[Modifier]) -> dict[_Key, Modifier]:
    seen: Counter[tuple[str, str]] = Counter()
    out: dict[_Key, Modifier] = {}
    for m in mods:
        if isinstance(m, AddFrame):
            base = ("add_frame", m.frame_name)
        elif isinstance(m, SetBaseFrame):
            base = ("set_base_frame", "")
        else:
            base = ("remove_mimic_attributes", m.joint_name)
        out[base[0], base[1], seen[base]] = m
        seen[base] += 1
    return out


def _label(key: _Key) -> str:
    kind, name, _ = key
    return f"{kind}({name})" if name else kind


# --- set_base_frame --------------------------------------------------------------------------


def _base_frame(a: Xrdf, b: Xrdf, root_frame: str | None) -> list[Change]:
    """The effective (last) base frame; on the URDF root it is the same as none (a note)."""
    base_a = [m.frame for m in a.modifiers if isinstance(m, SetBaseFrame)]
    base_b = [m.frame for m in b.modifiers if isinstance(m, SetBaseFrame)]
    if base_a == base_b:
        return []
    ea = base_a[-1] if base_a and base_a[-1] != root_frame else None
    eb = base_b[-1] if base_b and base_b[-1] != root_frame else None

    def change(kind: str, message: str, level: Level, before: Any, after: Any) -> list[Change]:
        return [
            Change(
                "modifiers",
                kind,
                message,
                level=level,
                subject="set_base_frame",
                key_path="modifiers",
                before=before,
                after=after,
            )
        ]

    if ea is None and eb is None:
        message = (
            f"set_base_frame {names(base_a)} -> {names(base_b)}: "
            f"'{root_frame}' is the URDF root, so this changes nothing"
        )
        return change("base-frame-is-root", message, Level.INFO, None, None)
    if ea == eb:
        message = (
            f"set_base_frame list {names(base_a)} -> {names(base_b)} "
            f"(effective base '{eb}' unchanged)"
        )
        return change("base-frame-changed", message, Level.MINOR, base_a, base_b)
    message = f"set_base_frame {ea or '(none, URDF root)'} -> {eb or '(none, URDF root)'}"
    if root_frame is None and (ea is None or eb is None):
        # cuRobo configs name their base even when it is the root: a round trip through one
        # gains a set_base_frame that only the URDF can show to be no change.
        message += f" (with --urdf: none if '{ea or eb}' is the URDF's root link)"
    return change("base-frame-changed", message, Level.MAJOR, ea, eb)


# --- add_frame -------------------------------------------------------------------------------


def _frame_path(field: str) -> Callable[[AddFrame], str]:
    return lambda m: f"modifiers.add_frame.{m.frame_name}.{field}"


def _same_rotation(x: Orientation, y: Orientation, tol: float) -> bool:
    """The same rotation in any written form: ``q`` and ``-q`` are equal."""
    qa, qb = x.as_wxyz(), y.as_wxyz()
    return close_all(qa, qb, tol) or close_all(qa, tuple(-c for c in qb), tol)


_FRAME_FIELDS: tuple[FieldRule[AddFrame, Any], ...] = (
    FieldRule[AddFrame, str](
        "frame-parent-changed",
        get=lambda m: m.parent_frame_name,
        message=lambda n, x, y: f"add_frame '{n}': parent '{x}' -> '{y}'",
        key_path=_frame_path("parent_frame_name"),
    ),
    FieldRule[AddFrame, str](
        "frame-joint-renamed",
        get=lambda m: m.joint_name,
        message=lambda n, x, y: f"add_frame '{n}': joint_name '{x}' -> '{y}'",
        key_path=_frame_path("joint_name"),
        level=Level.MINOR,
    ),
    FieldRule[AddFrame, str](
        "frame-joint-type-changed",
        get=lambda m: m.joint_type,
        message=lambda n, x, y: f"add_frame '{n}': joint_type '{x}' -> '{y}'",
        key_path=_frame_path("joint_type"),
        same=lambda x, y, _: x.lower() == y.lower(),
        then=FieldRule[AddFrame, str](
            "joint-type-spelling",
            get=lambda m: m.joint_type,
            message=lambda n, x, y: (
                f"add_frame '{n}': joint_type spelled '{x}' -> '{y}' (same type)"
            ),
            key_path=_frame_path("joint_type"),
            level=Level.INFO,
        ),
    ),
    FieldRule[AddFrame, tuple[float, float, float]](
        "frame-position-changed",
        get=lambda m: m.position,
        message=lambda n, x, y: f"add_frame '{n}': position {vec(x)} -> {vec(y)}",
        key_path=_frame_path("fixed_transform.position"),
        same=close_all,
    ),
    FieldRule[AddFrame, Orientation](
        "frame-orientation-changed",
        get=lambda m: m.orientation,
        message=lambda n, x, y: (
            f"add_frame '{n}': orientation (w, x, y, z) {vec(x.as_wxyz())} -> {vec(y.as_wxyz())}"
        ),
        key_path=_frame_path("fixed_transform.orientation"),
        same=_same_rotation,
        value=lambda o: o.as_wxyz(),
        then=FieldRule[AddFrame, str](
            "orientation-form",
            get=lambda m: m.orientation.form,
            message=lambda n, x, y: (
                f"add_frame '{n}': orientation written as {x} -> {y} (same rotation)"
            ),
            key_path=_frame_path("fixed_transform.orientation"),
            level=Level.INFO,
        ),
    ),
)


def _frame_dict(m: AddFrame) -> dict[str, Any]:
    return {
        "frame_name": m.frame_name,
        "parent_frame_name": m.parent_frame_name,
        "joint_name": m.joint_name,
        "joint_type": m.joint_type,
        "position": list(m.position),
        "orientation_wxyz": list(m.orientation.as_wxyz()),
    }


_ADD_FRAME = MappingRule[_Key, AddFrame](
    section="modifiers",
    key_path=lambda k: f"modifiers.add_frame.{k[1]}",
    subject=lambda k: k[1],
    added=OneSided(
        "frame-added", lambda k, m: f"add_frame '{k[1]}' added (parent '{m.parent_frame_name}')"
    ),
    removed=OneSided(
        "frame-removed",
        lambda k, m: f"add_frame '{k[1]}' removed (parent '{m.parent_frame_name}')",
    ),
    compare=lambda k, x, y, tol: diff_fields("modifiers", k[1], _FRAME_FIELDS, x, y, tol),
    value=_frame_dict,
)


# --- remove_mimic_attributes -----------------------------------------------------------------


def _same_mimic(x: RemoveMimicAttributes, y: RemoveMimicAttributes, tol: float) -> bool:
    pa, pb = x.position_limits, y.position_limits
    same_p = (pa is None and pb is None) or (
        pa is not None and pb is not None and close_all(pa, pb, tol)
    )
    return same_p and close(x.velocity_limits, y.velocity_limits, tol)


def _mimic_message(key: _Key, x: RemoveMimicAttributes, y: RemoveMimicAttributes) -> str:
    pa, pb = x.position_limits, y.position_limits
    return (
        f"remove_mimic_attributes '{key[1]}': position_limits "
        f"{vec(pa) if pa else 'none'} -> {vec(pb) if pb else 'none'}, velocity_limits "
        f"{num(x.velocity_limits)} -> {num(y.velocity_limits)}"
    )


def _mimic_dict(m: RemoveMimicAttributes) -> dict[str, Any]:
    return {
        "joint_name": m.joint_name,
        "position_limits": list(m.position_limits) if m.position_limits else None,
        "velocity_limits": m.velocity_limits,
    }


_REMOVE_MIMIC = MappingRule[_Key, RemoveMimicAttributes](
    section="modifiers",
    key_path=lambda k: f"modifiers.remove_mimic_attributes.{k[1]}",
    subject=lambda k: k[1],
    added=OneSided(
        "mimic-removal-added", lambda k, _: f"remove_mimic_attributes for joint '{k[1]}' added"
    ),
    removed=OneSided(
        "mimic-removal-removed",
        lambda k, _: f"remove_mimic_attributes for joint '{k[1]}' removed",
    ),
    changed=Changed("mimic-removal-changed", _mimic_message),
    same=_same_mimic,
    value=_mimic_dict,
)


# --- the section -----------------------------------------------------------------------------


def diff_modifiers(a: Xrdf, b: Xrdf, tol: float, root_frame: str | None) -> list[Change]:
    """The base frame, then frames and mimic removals in document order, then the order."""
    ka, kb = _keyed(a.modifiers), _keyed(b.modifiers)
    frames_a = {k: m for k, m in ka.items() if isinstance(m, AddFrame)}
    frames_b = {k: m for k, m in kb.items() if isinstance(m, AddFrame)}
    mimic_a = {k: m for k, m in ka.items() if isinstance(m, RemoveMimicAttributes)}
    mimic_b = {k: m for k, m in kb.items() if isinstance(m, RemoveMimicAttributes)}
    out = _base_frame(a, b, root_frame)
    # One walk over both kinds keeps the changes in document order.
    for key in union(ka, kb):
        if key[0] == "add_frame":
            out += diff_key(
                _ADD_FRAME, key, frames_a.get(key, MISSING), frames_b.get(key, MISSING), tol
            )
        elif key[0] == "remove_mimic_attributes":
            out += diff_key(
                _REMOVE_MIMIC, key, mimic_a.get(key, MISSING), mimic_b.get(key, MISSING), tol
            )
    out += order_change(
        "modifiers",
        "modifiers-reordered",
        list(ka),
        list(kb),
        lambda x, y: f"modifiers reordered: {x} -> {y}",
        subject="modifiers",
        key_path="modifiers",
        level=Level.MINOR,
        label=_label,
    )
    return out
