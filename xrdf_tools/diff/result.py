"""Semantic difference between two XRDF documents.

:func:`diff_xrdf` compares what the documents *mean*, not how they are written:

* mapping order is ignored everywhere (frames, joints, buffers, groups);
* ``collision`` (1.0) and ``world_collision`` (2.0) are the same section; a version change is
  reported once, in the ``format`` section;
* geometry is compared as the *effective* sphere sets of the world and self collision sections,
  with ``clone`` resolved first; a group that is only renamed is a minor (naming) change;
* spheres are compared per frame as multisets within ``tolerance`` (maximum matching), and what
  is left over is reported as radius changes (same centre), moves (same radius, centre moved by
  at most that radius) or additions and removals;
* attached-object slots (radius ≤ −1, cuRobo's ``extra_collision_spheres``) are *not geometry*
  until an object is attached, so they are left out of the sphere comparison and mentioned in
  ``notes`` when the two files carry a different number; a small negative radius (the seed
  UR10e's ``tool0``: −0.01) is a real sphere once buffered and is compared like any other;
* ignore pairs are a symmetric set (``a: [b]`` is the same pair as ``b: [a]``);
* buffers are compared per frame, a missing buffer being 0.0;
* c-space joint order and tool-frame order matter (the first tool frame is the end effector);
  a reorder is reported apart from additions and removals; limits are compared per joint;
* ``add_frame`` transforms are compared within ``tolerance``, orientations as rotations
  (any written form; ``q`` and ``-q`` are the same rotation).

Numbers are equal when ``|x - y| ≤ tolerance`` (per component for vectors and quaternions).

The module is pure: it returns an :class:`XrdfDiff`; :mod:`xrdf_tools.diff_render` turns it into
text or JSON. See ``docs/diff.md``.
"""

from __future__ import annotations

import bisect
import math
import os
from collections import Counter, deque
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from enum import Enum
from typing import Any, TypeVar

from .errors import GeometryGroupError
from .frozen import FrozenMap
from .model import (
    AddFrame,
    GeometryGroup,
    Modifier,
    RemoveMimicAttributes,
    SetBaseFrame,
    Sphere,
    Xrdf,
    resolve_group,
)
from .xrdf_io import load_xrdf

K = TypeVar("K")

DEFAULT_TOLERANCE = 1e-9

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
    are :class:`~xrdf_tools.model.Sphere` or ``None``.
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


JSON_SCHEMA_VERSION = 1


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


# --- public entry points ------------------------------------------------------------------------


def diff_files(
    path_a: str | os.PathLike[str],
    path_b: str | os.PathLike[str],
    tolerance: float = DEFAULT_TOLERANCE,
    *,
    root_frame: str | None = None,
) -> XrdfDiff:
    """Load two XRDF files and diff them. Load errors raise :class:`XrdfToolsError`."""
    return diff_xrdf(load_xrdf(path_a), load_xrdf(path_b), tolerance, root_frame=root_frame)


def diff_xrdf(
    a: Xrdf,
    b: Xrdf,
    tolerance: float = DEFAULT_TOLERANCE,
    *,
    root_frame: str | None = None,
) -> XrdfDiff:
    """Semantic difference from ``a`` to ``b`` (see the module docstring for the rules).

    ``root_frame`` is the URDF's root link when known: ``set_base_frame`` on it is a no-op, so
    a file that has it and one that does not are equal (a note says so).

    Raises :class:`ValueError` for a negative or non-finite ``tolerance`` and
    :class:`~xrdf_tools.errors.GeometryGroupError` when a collision section's group (or a clone)
    is undefined or cyclic, because its effective spheres cannot be known.
    """
    if not (math.isfinite(tolerance) and tolerance >= 0):
        raise ValueError(f"tolerance must be a finite number ≥ 0, not {tolerance!r}")
    d = _Differ(a, b, tolerance, root_frame)
    d.run()
    order = {s: i for i, s in enumerate(SECTION_ORDER)}
    changes = sorted(d.changes, key=lambda c: order[c.section])  # stable within a section
    notes = sorted(d.notes, key=lambda c: order[c.section])
    return XrdfDiff(
        DocumentInfo(a.source.path, a.format_version),
        DocumentInfo(b.source.path, b.format_version),
        tolerance,
        tuple(changes),
        tuple(notes),
    )


# --- numbers -------------------------------------------------------------------------------------


def _close(x: float | None, y: float | None, tol: float) -> bool:
    if x is None or y is None:
        return x is y
    if x == y or (math.isnan(x) and math.isnan(y)):
        return True
    return abs(x - y) <= tol


def _close_all(xs: Sequence[float], ys: Sequence[float], tol: float) -> bool:
    return len(xs) == len(ys) and all(_close(x, y, tol) for x, y in zip(xs, ys, strict=True))


def _num(v: float | None) -> str:
    return "none" if v is None else repr(float(v))


def _vec(v: Sequence[float]) -> str:
    return "[" + ", ".join(repr(float(c)) for c in v) + "]"


def _sphere(s: Sphere) -> str:
    return f"center {_vec(s.center)} radius {_num(s.radius)}"


def _plural(n: int, word: str) -> str:
    return f"{n} {word}" + ("" if n == 1 else "s")


def _names(names: Iterable[str]) -> str:
    return "[" + ", ".join(names) + "]"


# --- sphere matching -----------------------------------------------------------------------------


def _max_matching(adj: Sequence[Sequence[int]], nb: int) -> list[tuple[int, int]]:
    """Maximum bipartite matching (greedy start, then BFS augmenting paths); ``(i, j)`` pairs."""
    match_a = [-1] * len(adj)
    match_b = [-1] * nb
    for i, js in enumerate(adj):
        for j in js:
            if match_b[j] < 0:
                match_a[i], match_b[j] = j, i
                break
    for i in range(len(adj)):
        if match_a[i] >= 0 or not adj[i]:
            continue
        parent: dict[int, int] = {}
        seen = {i}
        queue = deque([i])
        free = -1
        while queue and free < 0:
            u = queue.popleft()
            for j in adj[u]:
                if j in parent:
                    continue
                parent[j] = u
                if match_b[j] < 0:
                    free = j
                    break
                w = match_b[j]
                if w not in seen:
                    seen.add(w)
                    queue.append(w)
        j = free
        while j >= 0:
            u = parent[j]
            previous = match_a[u]
            match_a[u], match_b[j] = j, u
            j = previous if u != i else -1
    return [(i, j) for i, j in enumerate(match_a) if j >= 0]


@dataclass(frozen=True)
class _FrameSpheres:
    """How the effective spheres of one frame differ."""

    added: tuple[Sphere, ...] = ()
    removed: tuple[Sphere, ...] = ()
    radius_changed: tuple[tuple[Sphere, Sphere], ...] = ()
    moved: tuple[tuple[Sphere, Sphere], ...] = ()

    def __bool__(self) -> bool:
        return bool(self.added or self.removed or self.radius_changed or self.moved)


def compare_spheres(a: Sequence[Sphere], b: Sequence[Sphere], tol: float) -> _FrameSpheres:
    """Multiset comparison of two sphere lists within ``tol``.

    1. equal spheres (centre and radius within ``tol``) are paired by a maximum matching;
    2. leftovers with the same centre are *radius changes* (maximum matching);
    3. leftovers with the same radius whose centres are at most one radius apart (the new
       centre lies inside the old sphere) are *moves*, nearest first;
    4. anything else is added or removed.
    """
    ia = list(range(len(a)))
    ib = list(range(len(b)))

    def same_center(x: Sphere, y: Sphere) -> bool:
        return _close_all(x.center, y.center, tol)

    def stage(ok: Callable[[Sphere, Sphere], bool]) -> list[tuple[int, int]]:
        # Both stages need equal centres, so candidates are found in a window on x.
        nonlocal ia, ib
        adj = _candidates([a[i] for i in ia], [b[j] for j in ib], ok, tol)
        pairs = [(ia[p], ib[q]) for p, q in _max_matching(adj, len(ib))]
        used_a = {i for i, _ in pairs}
        used_b = {j for _, j in pairs}
        ia = [i for i in ia if i not in used_a]
        ib = [j for j in ib if j not in used_b]
        return sorted(pairs)

    stage(lambda x, y: same_center(x, y) and _close(x.radius, y.radius, tol))
    radius = stage(same_center)
    # Moves: equal radius, centres within one radius, nearest first (ties by index).
    candidates = sorted(
        (math.dist(a[i].center, b[j].center), i, j)
        for i in ia
        for j in ib
        if _close(a[i].radius, b[j].radius, tol)
        and math.dist(a[i].center, b[j].center) <= max(a[i].radius, tol)
    )
    moved: list[tuple[int, int]] = []
    used_a: set[int] = set()
    used_b: set[int] = set()
    for _, i, j in candidates:
        if i not in used_a and j not in used_b:
            used_a.add(i)
            used_b.add(j)
            moved.append((i, j))
    moved.sort()
    return _FrameSpheres(
        added=tuple(b[j] for j in ib if j not in used_b),
        removed=tuple(a[i] for i in ia if i not in used_a),
        radius_changed=tuple((a[i], b[j]) for i, j in radius),
        moved=tuple((a[i], b[j]) for i, j in moved),
    )


def _candidates(
    a: Sequence[Sphere], b: Sequence[Sphere], ok: Callable[[Sphere, Sphere], bool], tol: float
) -> list[list[int]]:
    """For each sphere of ``a``, the indices of ``b`` with ``ok``; only spheres whose centre x
    lies within ``tol`` are tried (all of them when a coordinate is not finite)."""
    if not all(math.isfinite(s.center[0]) for s in (*a, *b)):
        return [[j for j, y in enumerate(b) if ok(x, y)] for x in a]
    order = sorted(range(len(b)), key=lambda j: b[j].center[0])
    xs = [b[j].center[0] for j in order]
    out = []
    for x in a:
        lo = bisect.bisect_left(xs, x.center[0] - tol)
        hi = bisect.bisect_right(xs, x.center[0] + tol)
        out.append(sorted(order[k] for k in range(lo, hi) if ok(x, b[order[k]])))
    return out


def _effective(spheres: Sequence[Sphere]) -> tuple[tuple[Sphere, ...], int]:
    """Spheres that are geometry, and how many attached-object slots (radius ≤ −1) were left
    out."""
    kept = tuple(s for s in spheres if s.radius > -1)
    return kept, len(spheres) - len(kept)


def _frame_summary(frame: str, fs: _FrameSpheres, scope_label: str) -> tuple[str, dict[str, int]]:
    parts = []
    counts: dict[str, int] = {}
    if fs.added:
        parts.append(f"+{_plural(len(fs.added), 'sphere')}")
        counts["added"] = len(fs.added)
    if fs.removed:
        parts.append(f"-{_plural(len(fs.removed), 'sphere')}")
        counts["removed"] = len(fs.removed)
    if fs.radius_changed:
        parts.append(f"radius changed on {len(fs.radius_changed)}")
        counts["radius_changed"] = len(fs.radius_changed)
    if fs.moved:
        parts.append(f"moved {len(fs.moved)}")
        counts["moved"] = len(fs.moved)
    return f"{frame} ({scope_label}): {', '.join(parts)}", counts


def _details(fs: _FrameSpheres) -> tuple[Detail, ...]:
    return (
        *(Detail("removed", s, None) for s in fs.removed),
        *(Detail("added", None, s) for s in fs.added),
        *(Detail("radius-changed", x, y) for x, y in fs.radius_changed),
        *(Detail("moved", x, y) for x, y in fs.moved),
    )


# --- the differ ----------------------------------------------------------------------------------


def _union(a: Iterable[K], b: Iterable[K]) -> list[K]:
    """Keys of ``a`` then the new keys of ``b``, each once (deterministic document order)."""
    out = dict.fromkeys(a)
    out.update(dict.fromkeys(b))
    return list(out)


def _relative_order(names: Sequence[str], keep: set[str]) -> list[str]:
    seen: set[str] = set()
    out = []
    for n in names:
        if n in keep and n not in seen:
            seen.add(n)
            out.append(n)
    return out


_SCOPE_LABEL = {"world": "world", "self": "self", "world+self": "world and self"}


class _Differ:
    def __init__(self, a: Xrdf, b: Xrdf, tol: float, root_frame: str | None = None) -> None:
        self.a = a
        self.b = b
        self.tol = tol
        self.root_frame = root_frame
        self.changes: list[Change] = []
        self.notes: list[Change] = []

    def add(self, section: str, kind: str, message: str, **kw: Any) -> None:
        if "counts" in kw:
            kw["counts"] = FrozenMap(kw["counts"])
        self.changes.append(Change(section, kind, message, **kw))

    def note(self, section: str, kind: str, message: str, **kw: Any) -> None:
        self.notes.append(Change(section, kind, message, level=Level.INFO, **kw))

    def run(self) -> None:
        self.format()
        self.modifiers()
        self.defaults()
        self.cspace()
        self.tool_frames()
        self.collision_sections()
        self.geometry()
        self.extra()

    # --- format ---------------------------------------------------------------------------------
    def format(self) -> None:
        va, vb = self.a.format_version, self.b.format_version
        if va != vb:
            self.add(
                "format",
                "version-changed",
                f"format_version {va} -> {vb} (1.0 'collision' and 2.0 'world_collision' are "
                "compared as one section)",
                level=Level.MINOR,
                subject="format_version",
                key_path="format_version",
                before=va,
                after=vb,
            )

    # --- modifiers ------------------------------------------------------------------------------
    @staticmethod
    def _keyed(mods: Sequence[Modifier]) -> dict[tuple[str, str, int], Modifier]:
        seen: Counter[tuple[str, str]] = Counter()
        out: dict[tuple[str, str, int], Modifier] = {}
        for m in mods:
            if isinstance(m, AddFrame):
                base = ("add_frame", m.frame_name)
            elif isinstance(m, SetBaseFrame):
                base = ("set_base_frame", "")
            else:
                base = ("remove_mimic_attributes", m.joint_name)
            out[(*base, seen[base])] = m
            seen[base] += 1
        return out

    def modifiers(self) -> None:
        sec = "modifiers"
        ka, kb = self._keyed(self.a.modifiers), self._keyed(self.b.modifiers)
        base_a = [m.frame for m in self.a.modifiers if isinstance(m, SetBaseFrame)]
        base_b = [m.frame for m in self.b.modifiers if isinstance(m, SetBaseFrame)]
        ea = base_a[-1] if base_a and base_a[-1] != self.root_frame else None
        eb = base_b[-1] if base_b and base_b[-1] != self.root_frame else None
        if base_a != base_b and ea is None and eb is None:
            self.note(
                sec,
                "base-frame-is-root",
                f"set_base_frame {_names(base_a)} -> {_names(base_b)}: "
                f"'{self.root_frame}' is the URDF root, so this changes nothing",
                subject="set_base_frame",
                key_path="modifiers",
            )
        elif base_a != base_b:
            self.add(
                sec,
                "base-frame-changed",
                f"set_base_frame {ea or '(none, URDF root)'} -> {eb or '(none, URDF root)'}"
                if ea != eb
                else f"set_base_frame list {_names(base_a)} -> {_names(base_b)} "
                f"(effective base '{eb}' unchanged)",
                level=Level.MAJOR if ea != eb else Level.MINOR,
                subject="set_base_frame",
                key_path="modifiers",
                before=ea if ea != eb else base_a,
                after=eb if ea != eb else base_b,
            )
        for key in _union(ka, kb):
            kind, name, _ = key
            if kind == "set_base_frame":
                continue
            ma, mb = ka.get(key), kb.get(key)
            if isinstance(ma, AddFrame) or isinstance(mb, AddFrame):
                self._add_frame(ma, mb, name)
            else:
                self._remove_mimic(ma, mb, name)
        common = set(ka) & set(kb)
        order_a = [k for k in ka if k in common]
        order_b = [k for k in kb if k in common]
        if order_a != order_b:
            self.add(
                sec,
                "modifiers-reordered",
                "modifiers reordered: "
                f"{_names(_mod_label(k) for k in order_a)} -> "
                f"{_names(_mod_label(k) for k in order_b)}",
                level=Level.MINOR,
                subject="modifiers",
                key_path="modifiers",
                before=[_mod_label(k) for k in order_a],
                after=[_mod_label(k) for k in order_b],
            )

    def _add_frame(self, ma: Modifier | None, mb: Modifier | None, name: str) -> None:
        sec = "modifiers"
        kp = f"modifiers.add_frame.{name}"
        if not isinstance(ma, AddFrame):
            assert isinstance(mb, AddFrame)
            self.add(
                sec,
                "frame-added",
                f"add_frame '{name}' added (parent '{mb.parent_frame_name}')",
                subject=name,
                key_path=kp,
                after=_frame_dict(mb),
            )
            return
        if not isinstance(mb, AddFrame):
            self.add(
                sec,
                "frame-removed",
                f"add_frame '{name}' removed (parent '{ma.parent_frame_name}')",
                subject=name,
                key_path=kp,
                before=_frame_dict(ma),
            )
            return
        if ma.parent_frame_name != mb.parent_frame_name:
            self.add(
                sec,
                "frame-parent-changed",
                f"add_frame '{name}': parent '{ma.parent_frame_name}' -> '{mb.parent_frame_name}'",
                subject=name,
                key_path=f"{kp}.parent_frame_name",
                before=ma.parent_frame_name,
                after=mb.parent_frame_name,
            )
        if ma.joint_name != mb.joint_name:
            self.add(
                sec,
                "frame-joint-renamed",
                f"add_frame '{name}': joint_name '{ma.joint_name}' -> '{mb.joint_name}'",
                level=Level.MINOR,
                subject=name,
                key_path=f"{kp}.joint_name",
                before=ma.joint_name,
                after=mb.joint_name,
            )
        if ma.joint_type.lower() != mb.joint_type.lower():
            self.add(
                sec,
                "frame-joint-type-changed",
                f"add_frame '{name}': joint_type '{ma.joint_type}' -> '{mb.joint_type}'",
                subject=name,
                key_path=f"{kp}.joint_type",
                before=ma.joint_type,
                after=mb.joint_type,
            )
        elif ma.joint_type != mb.joint_type:
            self.note(
                sec,
                "joint-type-spelling",
                f"add_frame '{name}': joint_type spelled '{ma.joint_type}' -> "
                f"'{mb.joint_type}' (same type)",
                subject=name,
                key_path=f"{kp}.joint_type",
                before=ma.joint_type,
                after=mb.joint_type,
            )
        if not _close_all(ma.position, mb.position, self.tol):
            self.add(
                sec,
                "frame-position-changed",
                f"add_frame '{name}': position {_vec(ma.position)} -> {_vec(mb.position)}",
                subject=name,
                key_path=f"{kp}.fixed_transform.position",
                before=ma.position,
                after=mb.position,
            )
        qa, qb = ma.orientation.as_wxyz(), mb.orientation.as_wxyz()
        neg = tuple(-c for c in qb)
        if not (_close_all(qa, qb, self.tol) or _close_all(qa, neg, self.tol)):
            self.add(
                sec,
                "frame-orientation-changed",
                f"add_frame '{name}': orientation (w, x, y, z) {_vec(qa)} -> {_vec(qb)}",
                subject=name,
                key_path=f"{kp}.fixed_transform.orientation",
                before=qa,
                after=qb,
            )
        elif ma.orientation.form != mb.orientation.form:
            self.note(
                sec,
                "orientation-form",
                f"add_frame '{name}': orientation written as {ma.orientation.form} -> "
                f"{mb.orientation.form} (same rotation)",
                subject=name,
                key_path=f"{kp}.fixed_transform.orientation",
                before=ma.orientation.form,
                after=mb.orientation.form,
            )

    def _remove_mimic(self, ma: Modifier | None, mb: Modifier | None, name: str) -> None:
        sec = "modifiers"
        kp = f"modifiers.remove_mimic_attributes.{name}"
        if not isinstance(ma, RemoveMimicAttributes):
            self.add(
                sec,
                "mimic-removal-added",
                f"remove_mimic_attributes for joint '{name}' added",
                subject=name,
                key_path=kp,
                after=_mimic_dict(mb),
            )
            return
        if not isinstance(mb, RemoveMimicAttributes):
            self.add(
                sec,
                "mimic-removal-removed",
                f"remove_mimic_attributes for joint '{name}' removed",
                subject=name,
                key_path=kp,
                before=_mimic_dict(ma),
            )
            return
        pa, pb = ma.position_limits, mb.position_limits
        same_p = (pa is None and pb is None) or (
            pa is not None and pb is not None and _close_all(pa, pb, self.tol)
        )
        if not same_p or not _close(ma.velocity_limits, mb.velocity_limits, self.tol):
            self.add(
                sec,
                "mimic-removal-changed",
                f"remove_mimic_attributes '{name}': position_limits "
                f"{_vec(pa) if pa else 'none'} -> {_vec(pb) if pb else 'none'}, velocity_limits "
                f"{_num(ma.velocity_limits)} -> {_num(mb.velocity_limits)}",
                subject=name,
                key_path=kp,
                before=_mimic_dict(ma),
                after=_mimic_dict(mb),
            )

    # --- default_joint_positions ----------------------------------------------------------------
    def defaults(self) -> None:
        sec = "default_joint_positions"
        da = self.a.default_joint_positions or FrozenMap()
        db = self.b.default_joint_positions or FrozenMap()
        for joint in _union(da, db):
            kp = f"{sec}.{joint}"
            if joint not in da:
                self.add(
                    sec,
                    "default-added",
                    f"{joint} = {_num(db[joint])} added (was unset: 0 clamped to the limits)",
                    subject=joint,
                    key_path=kp,
                    after=db[joint],
                )
            elif joint not in db:
                self.add(
                    sec,
                    "default-removed",
                    f"{joint} = {_num(da[joint])} removed (now unset: 0 clamped to the limits)",
                    subject=joint,
                    key_path=kp,
                    before=da[joint],
                )
            elif not _close(da[joint], db[joint], self.tol):
                self.add(
                    sec,
                    "default-changed",
                    f"{joint} = {_num(da[joint])} -> {_num(db[joint])}",
                    subject=joint,
                    key_path=kp,
                    before=da[joint],
                    after=db[joint],
                )

    # --- cspace ---------------------------------------------------------------------------------
    def cspace(self) -> None:
        sec = "cspace"
        ca, cb = self.a.cspace, self.b.cspace
        if ca is None and cb is None:
            return
        if ca is None or cb is None:
            present = cb if ca is None else ca
            assert present is not None
            self.add(
                sec,
                "section-added" if ca is None else "section-removed",
                f"cspace {'added' if ca is None else 'removed'}: "
                f"{_plural(len(present.joint_names), 'joint')} {_names(present.joint_names)}",
                subject="cspace",
                key_path="cspace",
                before=None if ca is None else list(ca.joint_names),
                after=None if cb is None else list(cb.joint_names),
            )
            return
        na, nb = ca.joint_names, cb.joint_names
        limits_a = _joint_limits(na, ca.acceleration_limits, ca.jerk_limits)
        limits_b = _joint_limits(nb, cb.acceleration_limits, cb.jerk_limits)
        for j in na:
            if j not in limits_b:
                acc, jerk = limits_a[j]
                self.add(
                    sec,
                    "joint-removed",
                    f"joint {j} removed (was position {na.index(j)}; acceleration {_num(acc)}, "
                    f"jerk {_num(jerk)})",
                    subject=j,
                    key_path="cspace.joint_names",
                    before={"index": na.index(j), "acceleration": acc, "jerk": jerk},
                )
        for j in nb:
            if j not in limits_a:
                acc, jerk = limits_b[j]
                self.add(
                    sec,
                    "joint-added",
                    f"joint {j} added at position {nb.index(j)} (acceleration {_num(acc)}, "
                    f"jerk {_num(jerk)})",
                    subject=j,
                    key_path="cspace.joint_names",
                    after={"index": nb.index(j), "acceleration": acc, "jerk": jerk},
                )
        common = set(na) & set(nb)
        ra, rb = _relative_order(na, common), _relative_order(nb, common)
        if ra != rb:
            self.add(
                sec,
                "joints-reordered",
                f"c-space joint order {_names(ra)} -> {_names(rb)} (c-space vectors change "
                "meaning)",
                subject="joint_names",
                key_path="cspace.joint_names",
                before=ra,
                after=rb,
            )
        for j in rb:
            (acc_a, jerk_a), (acc_b, jerk_b) = limits_a[j], limits_b[j]
            for what, x, y in (("acceleration", acc_a, acc_b), ("jerk", jerk_a, jerk_b)):
                if not _close(x, y, self.tol):
                    self.add(
                        sec,
                        f"{what}-limit-changed",
                        f"{what} limit of {j}: {_num(x)} -> {_num(y)}",
                        subject=j,
                        key_path=f"cspace.{what}_limits[{nb.index(j)}]",
                        before=x,
                        after=y,
                    )

    # --- tool_frames ----------------------------------------------------------------------------
    def tool_frames(self) -> None:
        sec = "tool_frames"
        ta, tb = self.a.tool_frames or (), self.b.tool_frames or ()
        if ta == tb:
            return
        ea, eb = (ta or (None,))[0], (tb or (None,))[0]
        if ea != eb:
            self.add(
                sec,
                "end-effector-changed",
                f"end effector (first tool frame) {ea or '(none)'} -> {eb or '(none)'}",
                subject="tool_frames[0]",
                key_path="tool_frames[0]",
                before=ea,
                after=eb,
            )
        for f in ta:
            if f not in tb:
                self.add(
                    sec,
                    "tool-frame-removed",
                    f"tool frame {f} removed",
                    subject=f,
                    key_path="tool_frames",
                    before=f,
                )
        for f in tb:
            if f not in ta:
                self.add(
                    sec,
                    "tool-frame-added",
                    f"tool frame {f} added",
                    subject=f,
                    key_path="tool_frames",
                    after=f,
                )
        common = set(ta) & set(tb)
        ra, rb = _relative_order(ta, common), _relative_order(tb, common)
        if ra != rb:
            self.add(
                sec,
                "tool-frames-reordered",
                f"tool frame order {_names(ra)} -> {_names(rb)}",
                subject="tool_frames",
                key_path="tool_frames",
                before=ra,
                after=rb,
            )

    # --- world / self collision sections --------------------------------------------------------
    def collision_sections(self) -> None:
        wa, wb = self.a.world_collision, self.b.world_collision
        sa, sb = self.a.self_collision, self.b.self_collision
        self._section_presence("world_collision", wa is not None, wb is not None, self.a, self.b)
        self._section_presence("self_collision", sa is not None, sb is not None, self.a, self.b)
        if wa is not None and wb is not None:
            self._group_name("world_collision", wa.geometry, wb.geometry)
            self._buffers("world_collision", wa.buffer_distance, wb.buffer_distance)
        if sa is not None and sb is not None:
            self._group_name("self_collision", sa.geometry, sb.geometry)
            self._buffers("self_collision", sa.buffer_distance, sb.buffer_distance)
            pa, pb = sa.ignore_pairs(), sb.ignore_pairs()
            for kind, verb, pairs, before in (
                ("ignore-pair-removed", "removed", pa - pb, True),
                ("ignore-pair-added", "added", pb - pa, False),
            ):
                for pair in sorted(tuple(sorted(p)) for p in pairs):
                    x, y = pair
                    self.add(
                        "self_collision",
                        kind,
                        f"ignore pair {x} <-> {y} {verb}",
                        subject=f"{x} <-> {y}",
                        key_path="self_collision.ignore",
                        before=list(pair) if before else None,
                        after=None if before else list(pair),
                    )

    def _section_presence(self, sec: str, in_a: bool, in_b: bool, a: Xrdf, b: Xrdf) -> None:
        if in_a == in_b:
            return
        doc = b if in_b else a
        section = doc.world_collision if sec == "world_collision" else doc.self_collision
        assert section is not None
        spheres = self._resolved(doc, section.geometry, sec)
        n = sum(len(_effective(s)[0]) for s in spheres.values())
        key = doc.collision_key if sec == "world_collision" else sec
        self.add(
            sec,
            "section-added" if in_b else "section-removed",
            f"{key} section {'added' if in_b else 'removed'} (geometry '{section.geometry}', "
            f"{_plural(n, 'sphere')})",
            subject=sec,
            key_path=key,
            before=None if in_b else section.geometry,
            after=section.geometry if in_b else None,
        )

    def _group_name(self, sec: str, ga: str, gb: str) -> None:
        if ga == gb:
            return
        self.add(
            sec,
            "group-renamed",
            f"geometry group '{ga}' -> '{gb}' (naming only; the effective spheres are compared "
            "under geometry)",
            level=Level.MINOR,
            subject="geometry",
            key_path=f"{sec}.geometry",
            before=ga,
            after=gb,
        )

    def _buffers(self, sec: str, ba: Mapping[str, float], bb: Mapping[str, float]) -> None:
        for frame in _union(ba, bb):
            x, y = ba.get(frame), bb.get(frame)
            if _close(x if x is not None else 0.0, y if y is not None else 0.0, self.tol):
                continue
            kind = "buffer-changed"
            suffix = ""
            if x is None:
                kind, suffix = "buffer-added", " (was not listed; a missing buffer is 0.0)"
            elif y is None:
                kind, suffix = "buffer-removed", " (no longer listed; a missing buffer is 0.0)"
            self.add(
                sec,
                kind,
                f"buffer_distance of {frame}: {_num(x if x is not None else 0.0)} -> "
                f"{_num(y if y is not None else 0.0)}{suffix}",
                subject=frame,
                key_path=f"{sec}.buffer_distance.{frame}",
                before=x if x is not None else 0.0,
                after=y if y is not None else 0.0,
            )

    # --- geometry -------------------------------------------------------------------------------
    def _resolved(self, x: Xrdf, group: str, sec: str) -> FrozenMap[str, tuple[Sphere, ...]]:
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

    def _scope_diff(self, scope: str) -> dict[str, tuple[_FrameSpheres, int, int, str]] | None:
        """Per frame: (difference, placeholders in A, placeholders in B, B's group)."""
        sa = self.a.world_collision if scope == "world" else self.a.self_collision
        sb = self.b.world_collision if scope == "world" else self.b.self_collision
        if sa is None or sb is None:
            return None
        sec = "world_collision" if scope == "world" else "self_collision"
        return self._group_diff(
            self._resolved(self.a, sa.geometry, sec),
            self._resolved(self.b, sb.geometry, sec),
            sb.geometry,
        )

    def _group_diff(
        self,
        ra: Mapping[str, Sequence[Sphere]],
        rb: Mapping[str, Sequence[Sphere]],
        group_b: str,
    ) -> dict[str, tuple[_FrameSpheres, int, int, str]]:
        out = {}
        for frame in _union(ra, rb):
            ea, pa = _effective(ra.get(frame, ()))
            eb, pb = _effective(rb.get(frame, ()))
            out[frame] = (compare_spheres(ea, eb, self.tol), pa, pb, group_b)
        return out

    def _emit_frames(
        self, frames: Mapping[str, tuple[_FrameSpheres, int, int, str]], scope: str, level: Level
    ) -> None:
        label = _SCOPE_LABEL.get(scope, scope.replace("group:", "unused group "))
        for frame, (fs, pa, pb, group) in frames.items():
            kp = f"geometry.{group}.spheres.{frame}"
            if fs:
                message, counts = _frame_summary(frame, fs, label)
                self.add(
                    "geometry",
                    "spheres-changed",
                    message,
                    level=level,
                    subject=frame,
                    key_path=kp,
                    scope=scope,
                    counts=counts,
                    details=_details(fs),
                )
            if pa != pb:
                self.note(
                    "geometry",
                    "placeholder-spheres",
                    f"{frame} ({label}): {_plural(pa, 'attached-object slot')} (radius ≤ −1) in "
                    f"A, {pb} in B; slots are not geometry until cuRobo attaches an object "
                    "(2.0 cannot express them) and are not compared as spheres",
                    subject=frame,
                    key_path=kp,
                    scope=scope,
                    before=pa,
                    after=pb,
                )

    def geometry(self) -> None:
        world = self._scope_diff("world")
        self_ = self._scope_diff("self")
        if world is not None and self_ is not None:
            both = {f: v for f, v in world.items() if self_.get(f, (None,))[0] == v[0]}
            both = {f: v for f, v in both.items() if self_[f][1:3] == v[1:3]}
            self._emit_frames(both, "world+self", Level.MAJOR)
            self._emit_frames(
                {f: v for f, v in world.items() if f not in both}, "world", Level.MAJOR
            )
            self._emit_frames(
                {f: v for f, v in self_.items() if f not in both}, "self", Level.MAJOR
            )
        elif world is not None:
            self._emit_frames(world, "world", Level.MAJOR)
        elif self_ is not None:
            self._emit_frames(self_, "self", Level.MAJOR)
        self._groups()

    def _groups(self) -> None:
        """Groups that no collision section uses: added, removed, or changed (all minor)."""
        ga = self.a.geometry or FrozenMap[str, GeometryGroup]()
        gb = self.b.geometry or FrozenMap[str, GeometryGroup]()
        used_a = _used_groups(self.a)
        used_b = _used_groups(self.b)
        used = used_a | used_b
        for name in _union(ga, gb):
            if name in ga and name in gb:
                if name in used:
                    continue
                ra = self._resolved(self.a, name, f"geometry.{name}")
                rb = self._resolved(self.b, name, f"geometry.{name}")
                self._emit_frames(self._group_diff(ra, rb, name), f"group:{name}", Level.MINOR)
            elif name in ga and name not in used_a:
                self.add(
                    "geometry",
                    "group-removed",
                    f"unused geometry group '{name}' removed",
                    level=Level.MINOR,
                    subject=name,
                    key_path=f"geometry.{name}",
                    before=name,
                )
            elif name in gb and name not in used_b:
                self.add(
                    "geometry",
                    "group-added",
                    f"unused geometry group '{name}' added",
                    level=Level.MINOR,
                    subject=name,
                    key_path=f"geometry.{name}",
                    after=name,
                )

    # --- unknown top-level keys -----------------------------------------------------------------
    def extra(self) -> None:
        xa, xb = self.a.extra, self.b.extra
        for key in _union(xa, xb):
            if key not in xa:
                self.add(
                    "extra",
                    "key-added",
                    f"top-level key {key} added",
                    level=Level.MINOR,
                    subject=key,
                    key_path=key,
                    after=xb[key],
                )
            elif key not in xb:
                self.add(
                    "extra",
                    "key-removed",
                    f"top-level key {key} removed",
                    level=Level.MINOR,
                    subject=key,
                    key_path=key,
                    before=xa[key],
                )
            elif xa[key] != xb[key]:
                self.add(
                    "extra",
                    "key-changed",
                    f"top-level key {key} changed",
                    level=Level.MINOR,
                    subject=key,
                    key_path=key,
                    before=xa[key],
                    after=xb[key],
                )


def _used_groups(x: Xrdf) -> set[str]:
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


def _joint_limits(
    names: Sequence[str], acc: Sequence[float], jerk: Sequence[float]
) -> dict[str, tuple[float | None, float | None]]:
    out: dict[str, tuple[float | None, float | None]] = {}
    for i, n in enumerate(names):
        out.setdefault(n, (acc[i] if i < len(acc) else None, jerk[i] if i < len(jerk) else None))
    return out


def _mod_label(key: tuple[str, str, int]) -> str:
    kind, name, _ = key
    return f"{kind}({name})" if name else kind


def _frame_dict(m: AddFrame) -> dict[str, Any]:
    return {
        "frame_name": m.frame_name,
        "parent_frame_name": m.parent_frame_name,
        "joint_name": m.joint_name,
        "joint_type": m.joint_type,
        "position": list(m.position),
        "orientation_wxyz": list(m.orientation.as_wxyz()),
    }


def _mimic_dict(m: Modifier | None) -> dict[str, Any] | None:
    if not isinstance(m, RemoveMimicAttributes):
        return None
    return {
        "joint_name": m.joint_name,
        "position_limits": list(m.position_limits) if m.position_limits else None,
        "velocity_limits": m.velocity_limits,
    }
