"""The generic comparisons every section of the diff is written with.

* :class:`MappingRule` with :func:`diff_mapping`: two mappings compared key by key. A key only
  in B is *added*, a key only in A is *removed*, a key in both whose values are not
  :attr:`~MappingRule.same` (within the tolerance) is *changed*. The rule says, per outcome,
  which ``kind`` and message the :class:`~xrdf_tools.diff.result.Change` gets, and, per key, its
  ``subject``, ``key_path`` and JSON ``before``/``after`` values. Default joint positions,
  buffers, ignore pairs, tool frames, c-space joints, modifiers, unused geometry groups, unknown
  top-level keys and the optional sections themselves are all such mappings.
* :class:`FieldRule` with :func:`diff_fields`: two versions of one item (an ``add_frame``, a
  joint's limits, the document itself) compared field by field, each field with its own kind,
  equality and level, and optionally a note when the values are equal but written differently.
* :func:`order_change`: the one change for lists whose order matters (c-space joints, tool
  frames, modifiers) when the entries both lists share come in another order.

Notes come back in the same lists as changes, with level :attr:`Level.INFO`; the caller splits
them off.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any, Generic, TypeVar, final

from .result import Change, Level
from .values import exact, names, relative_order

K = TypeVar("K")
V = TypeVar("V")
R = TypeVar("R")


@final
class Missing:
    """The type of :data:`MISSING`: "the key is not there"."""

    def __repr__(self) -> str:
        return "MISSING"


#: Stands for "the key is not there" (``None`` can be a real value, e.g. in unknown keys).
MISSING = Missing()


def as_is(value: object) -> object:
    """The value itself as ``before``/``after`` (the default)."""
    return value


@dataclass(frozen=True)
class OneSided(Generic[K, V]):
    """How a key found on one side only is reported.

    ``message(key, value)`` gets the value of the side that has it; ``key_path``, when given,
    replaces the rule's (a key may sit elsewhere in A than in B, e.g. ``collision`` in 1.0).
    """

    kind: str
    message: Callable[[K, V], str]
    key_path: Callable[[K], str] | None = None


@dataclass(frozen=True)
class Changed(Generic[K, V]):
    """How a key whose values differ is reported: ``message(key, before, after)``."""

    kind: str
    message: Callable[[K, V, V], str]


@dataclass(frozen=True)
class MappingRule(Generic[K, V]):
    """How one mapping of a section is compared and reported.

    ``same(before, after, tolerance)`` decides whether a key present on both sides changed;
    ``changed`` reports it (``None``: keys on both sides are not compared). A rule whose items
    have several fields to report on gives ``compare`` instead, which returns the changes (and
    notes) for one key present on both sides. ``missing``, when set, is the value an absent key
    stands for (a buffer that is not listed is 0.0): an added or removed key equal to it is no
    change, and it is the absent side's ``before``/``after``. ``value`` turns a value into the
    JSON ``before``/``after``.
    """

    section: str
    key_path: Callable[[K], str]
    added: OneSided[K, V]
    removed: OneSided[K, V]
    changed: Changed[K, V] | None = None
    same: Callable[[V, V, float], bool] = exact
    compare: Callable[[K, V, V, float], Iterable[Change]] | None = None
    level: Level = Level.MAJOR
    subject: Callable[[K], str] = str
    value: Callable[[V], Any] = as_is
    missing: V | Missing = MISSING


def diff_mapping(
    rule: MappingRule[K, V],
    a: Mapping[K, V],
    b: Mapping[K, V],
    tol: float,
    *,
    order_a: Iterable[K] | None = None,
    order_b: Iterable[K] | None = None,
) -> list[Change]:
    """Changes from ``a`` to ``b`` under ``rule``, in document order.

    The keys of ``a`` come first (removed or changed), then the keys only ``b`` has (added).
    ``order_a``/``order_b`` walk the keys of a list instead of the mapping's: a c-space or
    tool-frame list that names an entry twice reports it twice.
    """
    out: list[Change] = []
    for key in a if order_a is None else order_a:
        out.extend(diff_key(rule, key, a[key], b.get(key, MISSING), tol))
    for key in b if order_b is None else order_b:
        if key not in a:
            out.extend(diff_key(rule, key, MISSING, b[key], tol))
    return out


def diff_key(
    rule: MappingRule[K, V], key: K, before: V | Missing, after: V | Missing, tol: float
) -> list[Change]:
    """The changes for one key: added, removed, changed (or compared field by field), or none."""
    if isinstance(before, Missing):
        return [] if isinstance(after, Missing) else _one_sided(rule, key, after, True, tol)
    if isinstance(after, Missing):
        return _one_sided(rule, key, before, False, tol)
    if rule.compare is not None:
        return list(rule.compare(key, before, after, tol))
    if rule.changed is None or rule.same(before, after, tol):
        return []
    message = rule.changed.message(key, before, after)
    return [
        _change(
            rule,
            rule.changed.kind,
            message,
            key,
            rule.key_path,
            rule.value(before),
            rule.value(after),
        )
    ]


def diff_optional(
    rule: MappingRule[K, V], key: K, a: V | None, b: V | None, tol: float
) -> list[Change]:
    """An optional item (a section) as a mapping of at most one key: added, removed, compared."""
    return diff_key(rule, key, MISSING if a is None else a, MISSING if b is None else b, tol)


def _one_sided(
    rule: MappingRule[K, V], key: K, present: V, added: bool, tol: float
) -> list[Change]:
    """A key only B has (``added``) or only A has; ``present`` is its value there."""
    missing = rule.missing
    absent: Any = None
    if not isinstance(missing, Missing):
        if rule.same(missing, present, tol) if added else rule.same(present, missing, tol):
            return []
        absent = rule.value(missing)
    report = rule.added if added else rule.removed
    message = report.message(key, present)
    key_path = report.key_path or rule.key_path
    value = rule.value(present)
    before, after = (absent, value) if added else (value, absent)
    return [_change(rule, report.kind, message, key, key_path, before, after)]


def _change(
    rule: MappingRule[K, V],
    kind: str,
    message: str,
    key: K,
    key_path: Callable[[K], str],
    before: Any,
    after: Any,
) -> Change:
    return Change(
        rule.section,
        kind,
        message,
        level=rule.level,
        subject=rule.subject(key),
        key_path=key_path(key),
        before=before,
        after=after,
    )


@dataclass(frozen=True)
class FieldRule(Generic[R, V]):
    """One field of an item, compared on its own.

    ``get`` reads the field from A's and B's item; when the values are not ``same`` (within
    the tolerance) a change of ``kind`` is made, its message ``message(subject, before, after)``
    and its ``key_path`` taken from B's item. ``then`` is looked at only when the field is the
    same: typically a note (level ``INFO``) that the value is written differently.
    """

    kind: str
    get: Callable[[R], V]
    message: Callable[[str, V, V], str]
    key_path: Callable[[R], str]
    same: Callable[[V, V, float], bool] = exact
    level: Level = Level.MAJOR
    value: Callable[[V], Any] = as_is
    then: FieldRule[R, Any] | None = None


def diff_fields(
    section: str, subject: str, fields: Sequence[FieldRule[R, Any]], a: R, b: R, tol: float
) -> list[Change]:
    """The changes (and notes) between two versions ``a`` and ``b`` of one item, field order."""
    out: list[Change] = []
    for rule in fields:
        field: FieldRule[R, Any] | None = rule
        while field is not None:
            x, y = field.get(a), field.get(b)
            if not field.same(x, y, tol):
                out.append(
                    Change(
                        section,
                        field.kind,
                        field.message(subject, x, y),
                        level=field.level,
                        subject=subject,
                        key_path=field.key_path(b),
                        before=field.value(x),
                        after=field.value(y),
                    )
                )
                break
            field = field.then
    return out


def order_change(
    section: str,
    kind: str,
    a: Sequence[K],
    b: Sequence[K],
    message: Callable[[str, str], str],
    *,
    subject: str,
    key_path: str,
    level: Level = Level.MAJOR,
    label: Callable[[K], str] = str,
) -> list[Change]:
    """One change when the entries ``a`` and ``b`` share are listed in another order.

    Added and removed entries are left out (their own rules report them). ``message`` gets
    the two orders written as ``[x, y, …]``; ``before``/``after`` are the lists of ``label``.
    """
    common = set(a) & set(b)
    ra, rb = relative_order(a, common), relative_order(b, common)
    if ra == rb:
        return []
    la, lb = [label(k) for k in ra], [label(k) for k in rb]
    return [
        Change(
            section,
            kind,
            message(names(la), names(lb)),
            level=level,
            subject=subject,
            key_path=key_path,
            before=la,
            after=lb,
        )
    ]
