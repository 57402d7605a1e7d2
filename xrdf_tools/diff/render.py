"""Render an :class:`~xrdf_tools.diff.XrdfDiff` as text or JSON (strings; nothing is printed).

The JSON schema (``"schema": "xrdf-diff"``, ``"version": 1``) is documented in ``docs/diff.md``.
"""

from __future__ import annotations

import json
from collections.abc import Callable

from ..util.text import name_list
from . import Change, Detail, Level, XrdfDiff

#: How many per-sphere lines a text rendering shows under one change (the rest are counted).
MAX_DETAILS = 12
#: Defaults written at the value they have unset, noted one per line up to this many; more
#: are one line (a round trip through a cuRobo config writes one for each joint it locks:
#: 33 lines on the PR2).
MAX_UNSET_NOTES = 3

_MARK = {"added": "+", "removed": "-"}
_DETAIL_MARK = {"added": "+", "removed": "-", "radius-changed": "~", "moved": ">"}


def _marker(change: Change) -> str:
    return _MARK.get(change.kind.rsplit("-", 1)[-1], "~")


def _num(v: float) -> str:
    return repr(float(v))


def _vec(v: tuple[float, float, float]) -> str:
    return "[" + ", ".join(_num(c) for c in v) + "]"


def _detail_line(d: Detail) -> str:
    mark = _DETAIL_MARK.get(d.kind, "~")
    if d.before is None and d.after is not None:
        return f"{mark} center {_vec(d.after.center)} radius {_num(d.after.radius)}"
    if d.after is None and d.before is not None:
        return f"{mark} center {_vec(d.before.center)} radius {_num(d.before.radius)}"
    assert d.before is not None and d.after is not None
    if d.kind == "radius-changed":
        return (
            f"{mark} center {_vec(d.before.center)} radius {_num(d.before.radius)} -> "
            f"{_num(d.after.radius)}"
        )
    return (
        f"{mark} center {_vec(d.before.center)} -> {_vec(d.after.center)} "
        f"radius {_num(d.after.radius)}"
    )


def _side(label: str, path: str, version: str) -> str:
    return f"{label} {path or '<document>'} (XRDF {version})"


def render_text(diff: XrdfDiff, *, max_details: int = MAX_DETAILS) -> str:
    """Changes grouped by section with counts, then notes, then a one-line summary.

    Markers: ``+`` added, ``-`` removed, ``~`` changed; per-sphere lines also use ``>`` for a
    moved sphere. Minor (naming/format) changes end with ``[minor]``.
    """
    lines = [
        _side("---", diff.a.path, diff.a.format_version),
        _side("+++", diff.b.path, diff.b.format_version),
    ]
    for section, changes in diff.by_section():
        lines.append(f"{section}: {len(changes)} change{'' if len(changes) == 1 else 's'}")
        for c in changes:
            minor = " [minor]" if c.level is Level.MINOR else ""
            lines.append(f"  {_marker(c)} {c.message}{minor}")
            shown = c.details[:max_details]
            lines.extend(f"      {_detail_line(d)}" for d in shown)
            if len(c.details) > len(shown):
                lines.append(f"      … {len(c.details) - len(shown)} more")
    if diff.notes:
        lines.append("notes (not differences):")
        lines.extend(f"  i {message}" for message in _note_lines(diff.notes))
    if diff.is_equal:
        lines.append(f"identical (tolerance {diff.tolerance:g})")
    else:
        sections = len(diff.by_section())
        lines.append(
            f"different: {len(diff.changes)} change{'' if len(diff.changes) == 1 else 's'} "
            f"({len(diff.major_changes)} major, {len(diff.minor_changes)} minor) in "
            f"{sections} section{'' if sections == 1 else 's'} "
            f"(tolerance {diff.tolerance:g})"
        )
    return "\n".join(lines) + "\n"


def _note_lines(notes: tuple[Change, ...]) -> list[str]:
    """The notes' messages; those on defaults written at their unset value are one line per
    side (added, removed), where the first of them was, when there are more than
    :data:`MAX_UNSET_NOTES` (JSON keeps each)."""
    sides: dict[str, list[str]] = {"added": [], "removed": []}
    for n in notes:
        if n.kind == "default-as-unset":
            sides[_unset_side(n)].append(n.subject)
    out: list[str] = []
    for n in notes:
        joints = sides[_unset_side(n)] if n.kind == "default-as-unset" else []
        if len(joints) <= MAX_UNSET_NOTES:
            out.append(n.message)
        elif n.subject == joints[0]:
            out.append(
                f"{len(joints)} default positions {_unset_side(n)} at the value each joint has "
                f"unset (0 clamped to its limits), so they change nothing: "
                f"{name_list(joints, 6)} (--format json lists each)"
            )
    return out


def _unset_side(note: Change) -> str:
    return "removed" if note.after is None else "added"


def render_json(diff: XrdfDiff) -> str:
    """Stable JSON (``XrdfDiff.to_dict``), indented, one trailing newline."""
    return json.dumps(diff.to_dict(), indent=2, ensure_ascii=False) + "\n"


#: The one table of the diff's renderers: format name → ``(diff) → text``.
RENDERERS: dict[str, Callable[[XrdfDiff], str]] = {"text": render_text, "json": render_json}
