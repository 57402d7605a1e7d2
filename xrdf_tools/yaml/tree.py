"""The tree :mod:`xrdf_tools.yaml.io` builds: :class:`YScalar`, :class:`YSeq` and :class:`YMap`
nodes, each with the 1-based line and column where it starts, and the helpers that read them.

Nodes are frozen dataclasses with ``__slots__`` (a 16 MiB file holds millions of them). The
readers in :mod:`xrdf_tools.yaml.build` create them through :func:`new_scalar`,
:func:`new_seq` and :func:`new_map`, which fill the slots without the frozen ``__init__``'s
per-field ``object.__setattr__`` calls (half the cost of a node); the nodes are the same.
"""

from __future__ import annotations

from array import array
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field
from typing import Any

from ..util.errors import shown_text
from ..util.numbers import MAX_NUMBER, within

Scalar = str | int | float | bool | None


@dataclass(frozen=True, slots=True)
class YNode:
    """Base class: every node knows where it starts (1-based line and column)."""

    line: int
    col: int


@dataclass(frozen=True, slots=True)
class YScalar(YNode):
    value: Scalar
    quoted: bool = False

    def to_python(self) -> Any:
        return self.value


@dataclass(frozen=True, slots=True)
class YSeq(YNode):
    items: tuple[YNode, ...] = ()
    flow: bool = False

    def __iter__(self) -> Iterator[YNode]:
        return iter(self.items)

    def __len__(self) -> int:
        return len(self.items)

    def item(self, index: int) -> YNode:
        """``items[index]`` (a :class:`YPlainSeq` makes only that node)."""
        return self.items[index]

    def to_python(self) -> list[Any]:
        return [to_python(i) for i in self.items]


@dataclass(frozen=True, slots=True)
class YMap(YNode):
    """A mapping. ``pairs`` keeps every key in file order, repeated ones included."""

    pairs: tuple[tuple[YNode, YNode], ...] = ()
    flow: bool = False

    def keys(self) -> list[Any]:
        return [key_of(k) for k, _ in self.pairs]

    def get(self, key: str) -> YNode | None:
        """The value of the *last* occurrence of ``key`` (PyYAML semantics), or None."""
        found: YNode | None = None
        for k, v in self.pairs:
            if (k.value if type(k) is YScalar else key_of(k)) == key:
                found = v
        return found

    def key_node(self, key: object) -> YNode | None:
        for k, _ in self.pairs:
            if (k.value if type(k) is YScalar else key_of(k)) == key:
                return k
        return None

    def __contains__(self, key: object) -> bool:
        return self.key_node(key) is not None

    def items(self) -> list[tuple[Any, YNode]]:
        return [(key_of(k), v) for k, v in self.pairs]

    def to_python(self) -> dict[Any, Any]:
        out: dict[Any, Any] = {}
        for k, v in self.pairs:
            key = key_of(k)
            if isinstance(key, list):
                key = tuple(key)
            out[key] = to_python(v)
        return out


def key_of(node: YNode) -> Any:
    """The Python value of a mapping key (scalars only in practice)."""
    if isinstance(node, YScalar):
        return node.value
    return to_python(node)


def is_finite(v: int | float) -> bool:
    """A usable number: finite and within ±:data:`~xrdf_tools.util.numbers.MAX_NUMBER`, the
    bound of every number read (YAML integers have no size limit: ``math.isfinite`` of a
    400-digit one raises ``OverflowError``; ``1e308`` overflows the first product)."""
    return within(v, MAX_NUMBER)


def describe_node(node: YNode | None) -> str:
    """Human name of a node's type: 'a mapping', 'a list', 'the number 0.1', 'null' …"""
    if node is None:
        return "missing"
    if isinstance(node, YMap):
        return "a mapping"
    if isinstance(node, YSeq):
        return "a list"
    assert isinstance(node, YScalar)
    v = node.value
    if v is None:
        return "null"
    if isinstance(v, bool):
        return f"the boolean {str(v).lower()}"
    if isinstance(v, (int, float)):
        return f"the number {shown_text(str(v))}"
    return f"the string '{shown_text(v)}'"


def to_python(node: YNode | None) -> Any:
    """Plain Python data (dicts, lists, scalars) for a node tree."""
    if node is None:
        return None
    if isinstance(node, (YScalar, YSeq, YMap)):
        return node.to_python()
    raise TypeError(type(node))


@dataclass(frozen=True)
class DuplicateKey:
    key: str
    first_line: int
    first_col: int
    line: int
    col: int
    key_path: str


@dataclass(frozen=True)
class YamlDocument:
    """A parsed file: its root node (None for an empty file) and any repeated keys.

    ``simple_keys``: every mapping key is a distinct, non-empty string without ``.``, ``[``,
    ``]`` or ``#``, so a key path (``a.b[0]``) names one node and
    :func:`xrdf_tools.yaml.positions.positions_of` can find it without indexing the tree.
    """

    path: str
    root: YNode | None
    duplicates: tuple[DuplicateKey, ...] = field(default=())
    simple_keys: bool = field(default=False, compare=False)


# --- fast construction for the readers ------------------------------------------------------
# The slot descriptors of the frozen classes: setting through them skips the frozen
# ``__setattr__`` (nodes are still never changed after they are made).
_new = object.__new__


def _setter(cls: type, name: str) -> Callable[[object, Any], None]:
    """The ``__set__`` of the slot ``name`` of ``cls``."""
    setter: Callable[[object, Any], None] = getattr(cls, name).__set__
    return setter


def _filler(
    cls: type, names: tuple[str, str, str, str], slots_of: type | None = None
) -> Callable[[Any, Any, Any, Any], Any]:
    """``cls(*values)`` for the four slots ``names`` (of the class ``slots_of``, default
    ``cls``): a new node, its slots set directly."""
    set1, set2, set3, set4 = (_setter(slots_of or cls, name) for name in names)

    def fill(v1: Any, v2: Any, v3: Any, v4: Any) -> Any:
        node: Any = _new(cls)
        set1(node, v1)
        set2(node, v2)
        set3(node, v3)
        set4(node, v4)
        return node

    return fill


#: ``YScalar(line, col, value, quoted)``, made faster.
new_scalar: Callable[[int, int, Scalar, bool], YScalar] = _filler(
    YScalar, ("line", "col", "value", "quoted")
)
#: ``YSeq(line, col, items, flow)``, made faster.
new_seq: Callable[[int, int, tuple[YNode, ...], bool], YSeq] = _filler(
    YSeq, ("line", "col", "items", "flow")
)
#: ``YMap(line, col, pairs, flow)``, made faster.
new_map: Callable[[int, int, tuple[tuple[YNode, YNode], ...], bool], YMap] = _filler(
    YMap, ("line", "col", "pairs", "flow")
)


_COL_BITS = 32
_COL_MASK = (1 << _COL_BITS) - 1


class YPlainSeq(YSeq):
    """A sequence whose items are all unquoted scalars (a list of numbers or names), kept
    compactly: ``values`` (the items' values) and their packed positions, not a node per
    item. ``items`` makes the :class:`YScalar` nodes when asked for; they, and this node, are
    equal to what a :class:`YSeq` of the same items holds (``==`` and ``hash`` agree).

    Readers that only need the values (a list of numbers) read ``values``. Made by the
    one-pass reader (:mod:`xrdf_tools.yaml.build`) through :func:`new_plain_seq`.
    """

    __slots__ = ("_positions", "values")
    values: tuple[Scalar, ...]
    _positions: bytes | array[int]

    @property
    def items(self) -> tuple[YNode, ...]:
        positions = _unsigned(self._positions)
        return tuple(
            new_scalar(p >> _COL_BITS, p & _COL_MASK, v, False)
            for v, p in zip(self.values, positions, strict=True)
        )

    def item(self, index: int) -> YScalar:
        """``items[index]`` without making the other items."""
        p = _unsigned(self._positions)[index]
        return new_scalar(p >> _COL_BITS, p & _COL_MASK, self.values[index], False)

    def __len__(self) -> int:
        return len(self.values)

    def to_python(self) -> list[Any]:
        return list(self.values)

    def __eq__(self, other: object) -> bool:
        if isinstance(other, YSeq):
            return (self.line, self.col, self.flow, self.items) == (
                other.line,
                other.col,
                other.flow,
                other.items,
            )
        return NotImplemented

    def __hash__(self) -> int:
        return hash((self.line, self.col, self.items, self.flow))

    def __reduce__(self) -> tuple[Any, ...]:
        return (new_plain_seq, (self.line, self.col, self.values, self._positions, self.flow))


_new_plain = _filler(YPlainSeq, ("line", "col", "items", "flow"), YSeq)  # items: a property
_set_plain_values = _setter(YPlainSeq, "values")
_set_plain_positions = _setter(YPlainSeq, "_positions")


def _unsigned(positions: bytes | array[int]) -> Sequence[int]:
    return positions if isinstance(positions, array) else memoryview(positions).cast("Q")


def pack_position(line: int, col: int) -> int:
    """One int for a position, as :func:`new_plain_seq` takes them."""
    return (line << _COL_BITS) | col


def new_plain_seq(
    line: int, col: int, values: tuple[Scalar, ...], positions: bytes | array[int], flow: bool
) -> YPlainSeq:
    """A :class:`YPlainSeq`; ``positions``: the items' :func:`pack_position` as native
    unsigned 64-bit integers: an ``array("Q")`` (kept, not copied) or its ``tobytes()``
    (smaller for short lists)."""
    node: YPlainSeq = _new_plain(line, col, (), flow)
    _set_plain_values(node, values)
    _set_plain_positions(node, positions)
    return node
