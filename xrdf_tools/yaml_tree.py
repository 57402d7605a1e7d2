"""The tree :mod:`xrdf_tools.yaml_io` builds: :class:`YScalar`, :class:`YSeq` and :class:`YMap`
nodes, each with the 1-based line and column where it starts, and the helpers that read them.

Nodes are frozen dataclasses with ``__slots__`` (a 16 MiB file holds millions of them). The
readers in :mod:`xrdf_tools.yaml_build` create them through :func:`new_scalar`,
:func:`new_seq` and :func:`new_map`, which fill the slots without the frozen ``__init__``'s
per-field ``object.__setattr__`` calls (half the cost of a node); the nodes are the same.
"""

from __future__ import annotations

from array import array
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field
from typing import Any

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


def shown_text(text: str, limit: int = 60) -> str:
    """A value from a file, safe for a one-line message: control characters (newlines
    included) escaped, long values cut to ``limit`` characters."""
    out = "".join(c if c.isprintable() else repr(c)[1:-1] for c in text[: limit + 1])
    return out if len(out) <= limit and len(text) <= limit else out[: limit - 3] + "..."


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
    :func:`xrdf_tools.yaml_positions.positions_of` can find it without indexing the tree.
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


_set_line, _set_col, _set_value, _set_quoted = (
    _setter(YScalar, f) for f in ("line", "col", "value", "quoted")
)
_set_seq_line, _set_seq_col, _set_items, _set_seq_flow = (
    _setter(YSeq, f) for f in ("line", "col", "items", "flow")
)
_set_map_line, _set_map_col, _set_pairs, _set_map_flow = (
    _setter(YMap, f) for f in ("line", "col", "pairs", "flow")
)


def new_scalar(line: int, col: int, value: Scalar, quoted: bool) -> YScalar:
    """``YScalar(line, col, value, quoted)``, made faster."""
    node: YScalar = _new(YScalar)
    _set_line(node, line)
    _set_col(node, col)
    _set_value(node, value)
    _set_quoted(node, quoted)
    return node


def new_seq(line: int, col: int, items: tuple[YNode, ...], flow: bool) -> YSeq:
    """``YSeq(line, col, items, flow)``, made faster."""
    node: YSeq = _new(YSeq)
    _set_seq_line(node, line)
    _set_seq_col(node, col)
    _set_items(node, items)
    _set_seq_flow(node, flow)
    return node


def new_map(line: int, col: int, pairs: tuple[tuple[YNode, YNode], ...], flow: bool) -> YMap:
    """``YMap(line, col, pairs, flow)``, made faster."""
    node: YMap = _new(YMap)
    _set_map_line(node, line)
    _set_map_col(node, col)
    _set_pairs(node, pairs)
    _set_map_flow(node, flow)
    return node


_COL_BITS = 32
_COL_MASK = (1 << _COL_BITS) - 1


class YPlainSeq(YSeq):
    """A sequence whose items are all unquoted scalars (a list of numbers or names), kept
    compactly: ``values`` (the items' values) and their packed positions, not a node per
    item. ``items`` makes the :class:`YScalar` nodes when asked for; they, and this node, are
    equal to what a :class:`YSeq` of the same items holds (``==`` and ``hash`` agree).

    Readers that only need the values (a list of numbers) read ``values``. Made by the
    one-pass reader (:mod:`xrdf_tools.yaml_build`) through :func:`new_plain_seq`.
    """

    __slots__ = ("_positions", "values")
    values: tuple[Scalar, ...]
    _positions: bytes | array[int]

    @property  # type: ignore[override]
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
    node: YPlainSeq = _new(YPlainSeq)
    _set_seq_line(node, line)
    _set_seq_col(node, col)
    _set_items(node, ())
    _set_seq_flow(node, flow)
    _set_plain_values(node, values)
    _set_plain_positions(node, positions)
    return node
