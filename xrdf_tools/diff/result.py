"""What a diff returns: :class:`XrdfDiff`, a list of :class:`Change` values, and their JSON form.

Plain frozen values with no comparison logic; :mod:`xrdf_tools.diff` builds them and
:mod:`xrdf_tools.diff.render` turns them into text or JSON.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from enum import Enum
from typing import Any

from ..util.frozen import FrozenMap
from ..xrdf.model import Sphere

#: Sections in report order. ``world_collision`` is ``collision`` in 1.0 files.
SECTION_ORDER = (
    "format",
    "modifiers",
    "default_joint_positions",
    "cspace",
    "tool_frames",
    "world_collision",
    "self_collision",
    "geometry",
    "extra",
)

#: Version of the JSON document of :meth:`XrdfDiff.to_dict` (``docs/diff.md``).
JSON_SCHEMA_VERSION = 1


class Level(str, Enum):
    """How much a change matters.

    ``major``: what a planner does with the robot changes (spheres, limits, joints, masks …).
    ``minor``: naming or format only (version, group names, modifier order, unknown keys).
    ``info``: not a difference at all; only used for :attr:`XrdfDiff.notes`.
    """

    MAJOR = "major"
    MINOR = "minor"
    INFO = "info"


@dataclass(frozen=True)
class Detail:
    """One item inside a grouped change, e.g. one sphere of a frame's sphere-set change.

    ``kind`` is ``added``, ``removed``, ``radius-changed`` or ``moved``; ``before``/``after``
    are :class:`~xrdf_tools.xrdf.model.Sphere` or ``None``.
    """

    kind: str
    before: Sphere | None
    after: Sphere | None


@dataclass(frozen=True)
class Change:
    """One difference (or, in :attr:`XrdfDiff.notes`, one remark) between document A and B.

    ``section`` is one of :data:`SECTION_ORDER`; ``kind`` is a stable kebab-case id (listed in
    ``docs/diff.md``); ``subject`` names the frame, joint, pair or key concerned; ``key_path``
    is the dotted path in B (in A for removals); ``scope`` says which sphere set a geometry change
    belongs to (``world``, ``self``, ``world+self`` or ``group:<name>`` for groups that no section
    uses). ``before``/``after`` are the values in A and B (``None`` when absent). ``counts`` and
    ``details`` break grouped changes down (``{"added": 3, "radius_changed": 2}``).
    """

    section: str
    kind: str
    message: str
    level: Level = Level.MAJOR
    subject: str = ""
    key_path: str = ""
    scope: str = ""
    before: Any = None
    after: Any = None
    counts: FrozenMap[str, int] = field(default_factory=FrozenMap)
    details: tuple[Detail, ...] = ()

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready form (the schema of ``docs/diff.md``)."""
        return {
            "section": self.section,
            "kind": self.kind,
            "level": self.level.value,
            "subject": self.subject,
            "key_path": self.key_path,
            "scope": self.scope,
            "message": self.message,
            "before": jsonable(self.before),
            "after": jsonable(self.after),
            "counts": dict(self.counts),
            "details": [
                {"kind": d.kind, "before": jsonable(d.before), "after": jsonable(d.after)}
                for d in self.details
            ],
        }


@dataclass(frozen=True)
class DocumentInfo:
    """Which document a side of the diff is: its path (may be empty) and format version."""

    path: str
    format_version: str


@dataclass(frozen=True)
class XrdfDiff:
    """The result of :func:`diff_xrdf`: differences (``changes``) and remarks (``notes``).

    ``changes`` are sorted by section (:data:`SECTION_ORDER`), then in document order.
    """

    a: DocumentInfo
    b: DocumentInfo
    tolerance: float
    changes: tuple[Change, ...] = ()
    notes: tuple[Change, ...] = ()

    @property
    def is_equal(self) -> bool:
        """True when the documents mean the same thing (notes do not count)."""
        return not self.changes

    @property
    def major_changes(self) -> tuple[Change, ...]:
        return tuple(c for c in self.changes if c.level is Level.MAJOR)

    @property
    def minor_changes(self) -> tuple[Change, ...]:
        return tuple(c for c in self.changes if c.level is Level.MINOR)

    def by_section(self) -> list[tuple[str, tuple[Change, ...]]]:
        """Non-empty sections in :data:`SECTION_ORDER` with their changes."""
        out = []
        for section in SECTION_ORDER:
            items = tuple(c for c in self.changes if c.section == section)
            if items:
                out.append((section, items))
        return out

    def section_counts(self) -> dict[str, int]:
        return {s: len(items) for s, items in self.by_section()}

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready form; the schema is documented in ``docs/diff.md`` (``version`` 1)."""
        return {
            "schema": "xrdf-diff",
            "version": JSON_SCHEMA_VERSION,
            "a": {"path": self.a.path, "format_version": self.a.format_version},
            "b": {"path": self.b.path, "format_version": self.b.format_version},
            "tolerance": self.tolerance,
            "equal": self.is_equal,
            "summary": {
                "changes": len(self.changes),
                "major": len(self.major_changes),
                "minor": len(self.minor_changes),
                "notes": len(self.notes),
                "sections": self.section_counts(),
            },
            "sections": [
                {
                    "section": section,
                    "count": len(items),
                    "changes": [c.to_dict() for c in items],
                }
                for section, items in self.by_section()
            ],
            "notes": [n.to_dict() for n in self.notes],
        }


def jsonable(value: Any) -> Any:
    """Plain JSON data for a change value (spheres become ``{center, radius}``)."""
    if isinstance(value, Sphere):
        return {"center": [jsonable(c) for c in value.center], "radius": jsonable(value.radius)}
    if isinstance(value, float):
        return value if math.isfinite(value) else repr(value)
    if isinstance(value, (frozenset, set)):
        return sorted((jsonable(v) for v in value), key=repr)
    if isinstance(value, Mapping):
        return {str(k): jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [jsonable(v) for v in value]
    return value
