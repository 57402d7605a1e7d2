"""XRDF ``self_collision.ignore`` → MoveIt SRDF: a sync of the SRDF's collision mask.

:func:`sync_srdf` makes the SRDF's disabled pairs exactly the XRDF's ignore pairs (unordered):

* a ``disable_collisions`` whose pair the XRDF still ignores is kept as it is (element,
  attribute order, ``reason``, link order);
* one whose pair the XRDF no longer ignores is removed and returned in ``removed``;
* a pair the XRDF ignores and the SRDF does not disable gets a new ``disable_collisions``
  after the last existing one (else at the end of ``<robot>``), indented like the file, with
  the reason from ``reasons`` (see :func:`reasons_from_report`) or ``User``;
* ``disable_default_collisions{link}`` disables ``link`` against every link: a pair it covers
  is already disabled, so nothing is added for it. A covered pair the XRDF no longer ignores
  gets an ``enable_collisions`` (srdfdom: "re-enable collision after having disabled it via a
  default") and is returned in ``removed``; an ``enable_collisions`` of a pair the XRDF ignores
  is removed (returned in ``added``). ``disable_default_collisions`` itself is never removed.

Everything else is kept: groups, states, end effectors, virtual/passive joints, comments,
processing instructions, the XML declaration, the DOCTYPE and entity references; the file's
bytes are kept wherever nothing changed (see :mod:`xrdf_tools.export.srdf_xml`), so an unchanged
robot round-trips byte for byte. Pure: returns bytes and diagnostics, prints nothing.
"""

from __future__ import annotations

from collections.abc import Collection, Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from ..convert.sources.srdf_parse import refuse_urdf, trimmed
from ..diagnostics import Diagnostic, Severity
from ..robot.tree import RobotTree
from ..util.errors import ConversionError, SourceError
from ..util.text import name_list, pair_text
from ..xrdf.model import Xrdf
from .srdf_held import HeldPairs, held_pairs
from .srdf_reasons import REPORT_REASONS, USER, Pair, load_report_reasons, reasons_from_report
from .srdf_xml import XmlDocument, insert_after, last_child, remove_element

__all__ = [
    "REPORT_REASONS",
    "PairChange",
    "SrdfSync",
    "load_report_reasons",
    "reasons_from_report",
    "sync_srdf",
    "to_srdf",
]

_NEW = b'<?xml version="1.0" encoding="UTF-8"?>\n<robot name=""/>\n'

#: Pairs of the merged SRDF naming a link the URDF does not have.
RULE_FOREIGN = "export-srdf-unknown-link"


@dataclass(frozen=True)
class PairChange:
    """One pair of the sync: ``element`` is the SRDF element kept, added or removed."""

    link1: str
    link2: str
    reason: str | None
    line: int | None = None
    element: str = "disable_collisions"


@dataclass(frozen=True)
class SrdfSync:
    """The synced SRDF (``data`` in the file's encoding) and what changed."""

    data: bytes
    encoding: str
    robot_name: str
    kept: tuple[PairChange, ...]
    added: tuple[PairChange, ...]
    removed: tuple[PairChange, ...]
    diagnostics: tuple[Diagnostic, ...]

    @property
    def text(self) -> str:
        return self.data.decode(self.encoding)


# ------------------------------------------------------------------------------------------
# The sync
# ------------------------------------------------------------------------------------------
def sync_srdf(
    x: Xrdf,
    existing: str | bytes | None = None,
    *,
    urdf: RobotTree | None = None,
    robot_name: str | None = None,
    reasons: Mapping[Pair, str] | None = None,
    srdf_path: str = "<srdf>",
) -> SrdfSync:
    """Sync ``x``'s ignore pairs into ``existing`` SRDF text (or a new SRDF when ``None``).

    ``<robot name>``: with ``urdf`` it is the URDF robot's name (a differing name in
    ``existing`` is corrected, with a warning); without it a new SRDF is named ``robot_name``
    and an existing one keeps its name (a note says it was not checked). With ``urdf``, ignore
    pairs naming a frame that is neither a URDF link nor an XRDF ``add_frame`` raise
    :class:`ConversionError`; pairs with ``add_frame`` frames are left out (MoveIt does not know
    those frames), with a warning.
    """
    if existing is not None:
        _refuse_xacro(existing, srdf_path)
    diags: list[Diagnostic] = []
    pairs = _wanted_pairs(x, urdf, diags, srdf_path)
    new = existing is None
    doc = XmlDocument.parse(_NEW if existing is None else existing, srdf_path)
    refuse_urdf(doc.root, srdf_path)
    name = _sync_name(doc.root, urdf, robot_name, diags, srdf_path, new=new)
    universe = _universe(x, urdf, doc.root)
    links = set(urdf.links) if urdf is not None else None
    held = held_pairs(x, urdf, pairs) if urdf is not None else HeldPairs(())
    plan = _plan(doc.root, pairs, dict(reasons or {}), universe, links, held.keys())
    plan.apply(doc.root)
    diags.extend(_removed_diag(ch, srdf_path) for ch in plan.removed)
    held_diag = held.diagnostic(srdf_path, plan.held)
    diags.extend([held_diag] if held_diag is not None else [])
    diags.extend(_foreign_diags(plan.foreign, urdf, srdf_path))
    diags.sort(key=lambda d: (d.line is None, d.line or 0))
    if plan.added:
        diags.append(_added_diag(plan.added, srdf_path))
    return SrdfSync(
        data=doc.serialize(),
        encoding=doc.encoding,
        robot_name=name,
        kept=tuple(plan.kept),
        added=tuple(plan.added),
        removed=tuple(plan.removed),
        diagnostics=tuple(diags),
    )


def _refuse_xacro(existing: str | bytes, srdf_path: str) -> None:
    """An SRDF xacro cannot be synced in place: its ``disable_collisions`` may come from
    includes and macros (MoveIt configurations' ``robot.srdf.xacro``), so pairs would be
    added twice and pairs to remove left where they are."""
    from ..robot.xacro_source import uses_xacro
    from ..util.textpos import line_col

    data = existing.encode("utf-8") if isinstance(existing, str) else existing
    if not uses_xacro(data):
        return
    line, col = line_col(data.decode("utf-8", errors="replace"), data.index(b"<xacro:"))
    raise SourceError(
        "a xacro file: its disable_collisions may be made by includes and macros, which a "
        f"sync cannot edit; expand it first (xrdf expand {srdf_path} -o robot.srdf, with the "
        "same --xacro-arg and --package-path) and merge into that SRDF",
        path=srdf_path,
        line=line,
        col=col,
    )


def to_srdf(x: Xrdf, robot_name: str, existing: str | bytes | None = None) -> str:
    """SRDF text of :func:`sync_srdf` (no URDF, no report: new pairs get reason ``User``)."""
    return sync_srdf(x, existing, robot_name=robot_name).text


def _diag(path: str, line: int | None, rule: str, sev: Severity, msg: str) -> Diagnostic:
    return Diagnostic(path, line, None, rule, sev, msg, "")


def _names(names: list[str], limit: int = 8) -> str:
    return name_list((repr(n) for n in names), limit)


def _ordered_pairs(x: Xrdf) -> list[tuple[str, str]]:
    """The XRDF's ignore pairs once each, in the order the XRDF lists them."""
    out: list[tuple[str, str]] = []
    seen: set[Pair] = set()
    if x.self_collision is not None:
        for a, bs in x.self_collision.ignore.items():
            for b in bs:
                key = frozenset((a, b))
                if a != b and key not in seen:
                    seen.add(key)
                    out.append((a, b))
    return out


def _wanted_pairs(
    x: Xrdf, urdf: RobotTree | None, diags: list[Diagnostic], path: str
) -> list[tuple[str, str]]:
    pairs = _ordered_pairs(x)
    added = {m.frame_name for m in x.added_frames()}
    links = set(urdf.links) if urdf is not None else None
    unknown = sorted(
        {n for p in pairs for n in p if links is not None and n not in links and n not in added}
    )
    if unknown:
        raise ConversionError(
            f"self_collision.ignore names {_names(unknown)}, not "
            f"link(s) of the URDF '{urdf.name if urdf else ''}'; MoveIt cannot disable them",
            path=x.source.path,
        )
    skipped = [p for p in pairs if added & set(p)]
    if skipped:
        frames = sorted(added & {n for p in skipped for n in p})
        diags.append(
            _diag(
                path,
                None,
                "export-srdf-added-frame",
                Severity.WARNING,
                f"{len(skipped)} ignore pair(s) with add_frame frame(s) {', '.join(frames)} "
                "not written: MoveIt does not know these frames",
            )
        )
    return [p for p in pairs if not added & set(p)]


def _sync_name(
    root: Any,
    urdf: RobotTree | None,
    fallback: str | None,
    diags: list[Diagnostic],
    path: str,
    *,
    new: bool,
) -> str:
    current = root.get("name")
    if urdf is not None:
        if not new and current != urdf.name:
            diags.append(
                _diag(
                    path,
                    root.sourceline,
                    "export-srdf-robot-name",
                    Severity.WARNING,
                    f"<robot name='{current or ''}'> is not the URDF robot name "
                    f"'{urdf.name}' (MoveIt logs an error); corrected",
                )
            )
        if fallback is not None and fallback != urdf.name:
            diags.append(
                _diag(
                    path,
                    None,
                    "export-srdf-robot-name",
                    Severity.WARNING,
                    f"robot name '{fallback}' ignored: the SRDF takes the URDF's, '{urdf.name}'",
                )
            )
        if current != urdf.name:
            root.set("name", urdf.name)
        return urdf.name
    if new:
        name = fallback or "robot"
        root.set("name", name)
        msg = f"<robot name='{name}'> is not checked against the URDF; pass --urdf to use its name"
    else:
        name = current or ""
        msg = f"<robot name='{name}'> kept, not checked against the URDF (pass --urdf)"
    diags.append(_diag(path, None, "export-srdf-robot-name", Severity.INFO, msg))
    return name


def _universe(x: Xrdf, urdf: RobotTree | None, root: Any) -> set[str]:
    """Links a ``disable_default_collisions`` can pair with: the URDF's, else every name the
    XRDF (``add_frame`` frames aside) and the SRDF's collision elements mention."""
    if urdf is not None:
        return set(urdf.links)
    names = {n for p in _ordered_pairs(x) for n in p} | set(x.self_collision_spheres())
    names -= {m.frame_name for m in x.added_frames()}
    for el in root:
        for attr in ("link", "link1", "link2"):
            v = trimmed(el, attr) if isinstance(el.tag, str) else None
            if v:
                names.add(v)
    return names


def _foreign_diags(
    kept: Sequence[PairChange], urdf: RobotTree | None, path: str
) -> list[Diagnostic]:
    """An info per link the URDF does not have (an SRDF shared with a variant that has more
    sensors), at its first pair, counting the pairs naming it: they are kept, since no XRDF of
    this URDF can say whether to check them."""
    named: dict[str, list[PairChange]] = {}
    for ch in kept:
        for link in (ch.link1, ch.link2):
            if urdf is not None and link not in urdf.links:
                named.setdefault(link, []).append(ch)
    return [
        _diag(
            path,
            changes[0].line,
            RULE_FOREIGN,
            Severity.INFO,
            f"'{link}' is not a link of the URDF '{urdf.name if urdf else ''}': "
            f"{len(changes)} disable_collisions naming it kept (first "
            f"{pair_text(changes[0].link1, changes[0].link2)}); no XRDF of this URDF can say "
            "whether to check them",
        )
        for link, changes in named.items()
    ]


def _removed_diag(ch: PairChange, path: str) -> Diagnostic:
    if ch.element == "enable_collisions":
        msg = (
            f"{pair_text(ch.link1, ch.link2)} is no longer ignored by the XRDF but is covered by "
            "disable_default_collisions: enable_collisions added"
        )
    else:
        why = f" (reason {ch.reason})" if ch.reason else ""
        msg = f"{pair_text(ch.link1, ch.link2)}{why} is no longer ignored by the XRDF: removed"
    return _diag(path, ch.line, "export-srdf-removed", Severity.WARNING, msg)


def _added_diag(added: Iterable[PairChange], path: str) -> Diagnostic:
    counts: dict[str, int] = {}
    for ch in added:
        key = "enable_collisions removed" if ch.element == "enable_collisions" else ch.reason
        counts[key or USER] = counts.get(key or USER, 0) + 1
    detail = ", ".join(f"{n} {k}" for k, n in counts.items())
    total = sum(counts.values())
    return _diag(path, None, "export-srdf-added", Severity.INFO, f"{total} pair(s) added: {detail}")


# ------------------------------------------------------------------------------------------
# Planning: what to keep, add and remove
# ------------------------------------------------------------------------------------------
def _pair_of(el: Any) -> Pair:
    return frozenset((trimmed(el, "link1") or "", trimmed(el, "link2") or ""))


@dataclass
class _Plan:
    kept: list[PairChange]
    added: list[PairChange]
    removed: list[PairChange]
    new_disabled: list[tuple[str, str, str]]
    new_enabled: list[tuple[str, str]]
    drop: list[Any]
    #: Pairs naming a link the URDF does not have: kept as they are.
    foreign: list[PairChange]
    #: Pairs the XRDF ignores but not added: its mask held a joint between them.
    held: set[Pair]

    def apply(self, root: Any) -> None:
        from lxml import etree

        anchor = last_child(root, "disable_collisions")
        els = [
            etree.Element("disable_collisions", link1=a, link2=b, reason=r)
            for a, b, r in self.new_disabled
        ]
        insert_after(root, anchor, els)
        enables = [
            etree.Element("enable_collisions", link1=a, link2=b, reason=USER)
            for a, b in self.new_enabled
        ]
        after = last_child(root, "enable_collisions")
        if after is None:
            after = els[-1] if els else anchor
        insert_after(root, after, enables)
        for el in self.drop:
            remove_element(el)


def _plan(
    root: Any,
    pairs: list[tuple[str, str]],
    reasons: Mapping[Pair, str],
    universe: Collection[str],
    links: Collection[str] | None,
    held: Collection[Pair] = frozenset(),
) -> _Plan:
    """What the merge changes; ``links``: the URDF's (a pair naming another link is kept);
    ``held``: pairs the XRDF ignores that are not added (:mod:`.srdf_held`)."""
    want = {frozenset(p) for p in pairs}
    plan = _Plan([], [], [], [], [], [], [], set())
    present: set[Pair] = set()
    for el in root.iterchildren("disable_collisions"):
        pair = _pair_of(el)
        ch = _change(el, "disable_collisions")
        if pair in want:
            plan.kept.append(ch)
            present.add(pair)
        elif links is not None and not all(n in links for n in pair):
            plan.foreign.append(ch)
        else:
            plan.removed.append(ch)
            plan.drop.append(el)
    defaults = {trimmed(el, "link") for el in root.iterchildren("disable_default_collisions")}
    enabled: set[Pair] = set()
    for el in root.iterchildren("enable_collisions"):
        pair = _pair_of(el)
        if pair in want and pair in held:
            plan.held.add(pair)
            enabled.add(pair)
        elif pair in want:  # it would re-enable a pair the XRDF ignores
            plan.added.append(_change(el, "enable_collisions"))
            plan.drop.append(el)
        else:
            enabled.add(pair)
    new_added: dict[Pair, PairChange] = {}  # a pair listed twice: its last entry, last
    for a, b in pairs:
        pair = frozenset((a, b))
        if pair in present or (pair & defaults and pair not in enabled):
            continue
        if pair in held:
            plan.held.add(pair)
            continue
        reason = reasons.get(pair, USER)
        plan.new_disabled.append((a, b, reason))
        new_added.pop(pair, None)
        new_added[pair] = PairChange(a, b, reason)
    plan.added = [c for c in plan.added if frozenset((c.link1, c.link2)) not in new_added]
    plan.added.extend(new_added.values())
    _re_enable(plan, sorted(d for d in defaults if d), universe, want, enabled)
    return plan


def _re_enable(
    plan: _Plan, defaults: list[str], universe: Collection[str], want: set[Pair], enabled: set[Pair]
) -> None:
    """``enable_collisions`` for pairs a ``disable_default_collisions`` covers but the XRDF
    checks."""
    for link in defaults:
        for other in sorted(universe):
            pair = frozenset((link, other))
            if other != link and pair not in want and pair not in enabled:
                enabled.add(pair)
                plan.new_enabled.append((link, other))
                plan.removed.append(PairChange(link, other, None, None, "enable_collisions"))


def _change(el: Any, element: str) -> PairChange:
    return PairChange(
        trimmed(el, "link1") or "",
        trimmed(el, "link2") or "",
        el.get("reason"),
        el.sourceline,
        element,
    )
