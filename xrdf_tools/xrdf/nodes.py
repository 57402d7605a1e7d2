"""Typed access to the nodes of a YAML tree for the strict XRDF reader: each helper returns a
plain value or raises one :class:`SchemaError` at the node's file:line:col.

The ``Shape``-taking helpers (:meth:`NodeReader.section`, :meth:`~NodeReader.get`,
:meth:`~NodeReader.num`, :meth:`~NodeReader.nums`) take nullability, required keys, list
lengths and the metres bound from the XRDF shape description (:mod:`xrdf_tools.xrdf.shape`);
the wording of the errors is the reader's.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TypeVar

from ..util.errors import SchemaError
from ..util.frozen import FrozenMap
from ..util.numbers import MAX_LENGTH, MAX_NUMBER, bound_problem
from ..yaml.io import YMap, YNode, YPlainSeq, YScalar, YSeq, describe_node
from .shape import Shape, is_name, is_number

T = TypeVar("T")

#: The bound of :func:`plain_numbers` for a number that is not a length.
FINITE = MAX_NUMBER


def plain_number(value: object, bound: float) -> float | None:
    """``value`` as a float when it is a YAML number (not a boolean) within ±``bound``
    (``FINITE``: any finite number); None when the checks of :class:`NodeReader` must look at
    it (and word the error)."""
    if isinstance(value, (int, float)) and type(value) is not bool and -bound <= value <= bound:
        return float(value)
    return None


def plain_numbers(node: YNode | None, bound: float) -> tuple[float, ...] | None:
    """The values of a list of plain numbers (a :class:`YPlainSeq`), each within ±``bound``,
    as floats, without a node per item; None for anything else (the item-by-item checks then
    read it, with their messages)."""
    if type(node) is not YPlainSeq:
        return None
    out: list[float] = []
    for v in node.values:
        f = plain_number(v, bound)
        if f is None:
            return None
        out.append(f)
    return tuple(out)


def describe(node: YNode | None) -> str:
    """Human name of a node's type: 'a mapping', 'a list', 'the number 0.1', 'null' …
    (strings escaped and shortened: see :func:`xrdf_tools.yaml.io.describe_node`)."""
    return describe_node(node)


def is_null(node: YNode | None) -> bool:
    """Whether ``node`` is a YAML null (``key:``, ``key: null``, ``key: ~``)."""
    return isinstance(node, YScalar) and node.value is None


class NodeReader:
    """Type-checking helpers that raise :class:`SchemaError` at the node's position."""

    def __init__(self, path: str) -> None:
        self.path = path

    def fail(self, node: YNode | None, message: str) -> SchemaError:
        return SchemaError(
            message,
            path=self.path,
            line=node.line if node is not None else None,
            col=node.col if node is not None else None,
        )

    def mapping(self, node: YNode | None, what: str, *, nullable: bool = True) -> YMap | None:
        if node is None or is_null(node):
            if nullable:
                return None
            raise self.fail(node, f"{what} must be a mapping, not null")
        if not isinstance(node, YMap):
            raise self.fail(node, f"{what} must be a mapping, not {describe(node)}")
        return node

    def sequence(self, node: YNode | None, what: str, *, nullable: bool = True) -> YSeq | None:
        if node is None or is_null(node):
            if nullable:
                return None
            raise self.fail(node, f"{what} must be a list, not null")
        if not isinstance(node, YSeq):
            raise self.fail(node, f"{what} must be a list, not {describe(node)}")
        return node

    def string(self, node: YNode | None, what: str) -> str:
        if isinstance(node, YScalar) and is_name(node):
            # A frame called 1 is legal YAML-wise; keep its text form.
            return node.value if isinstance(node.value, str) else str(node.value)
        raise self.fail(node, f"{what} must be a non-empty string, not {describe(node)}")

    def number(self, node: YNode | None, what: str, *, metres: bool = False) -> float:
        """A usable number: finite (NaN and infinities poison FK and JSON) and within the bounds
        of :mod:`xrdf_tools.util.numbers` (``metres``: a length or coordinate)."""
        if isinstance(node, YScalar) and is_number(node, finite=False):
            assert isinstance(node.value, (int, float))
            problem = bound_problem(node.value, metres=metres)
            if problem is not None:
                raise self.fail(node, f"{what} {problem}")
            return float(node.value)
        raise self.fail(node, f"{what} must be a number, not {describe(node)}")

    def length(self, node: YNode | None, what: str) -> float:
        """A number that is a length or coordinate in metres: finite and within
        ±:data:`MAX_LENGTH` (beyond that, squared distances overflow)."""
        return self.number(node, what, metres=True)

    def strings(self, node: YNode | None, what: str) -> tuple[str, ...]:
        seq = self.sequence(node, what)
        if seq is None:
            return ()
        return tuple(self.string(item, f"{what}[{i}]") for i, item in enumerate(seq))

    def frame_map(
        self, node: YNode | None, what: str, value: Callable[[YNode, str], T]
    ) -> FrozenMap[str, T]:
        m = self.mapping(node, what)
        if m is None:
            return FrozenMap()
        out: dict[str, T] = {}
        for k, v in m.pairs:
            name = self.string(k, f"a key of {what}")
            out[name] = value(v, f"{what}.{name}")
        return FrozenMap(out)

    # --- driven by the shape description ---------------------------------------------------
    def section(self, node: YNode | None, shape: Shape, what: str) -> YMap | None:
        """A mapping section; null is None when ``shape`` accepts it, else an error."""
        return self.mapping(node, what, nullable=shape.nullable)

    def get(self, m: YMap, shape: Shape, key: str, what: str) -> YNode | None:
        """The value of ``key`` in section ``m`` (None when absent); a required key of
        ``shape`` that is absent is an error at ``m``."""
        assert key in shape.fields, f"{key!r} is not a key of this section"
        node = m.get(key)
        if node is None and key in shape.required:
            raise self.fail(m, f"{what} is missing required key '{key}'")
        return node

    def num(self, node: YNode | None, shape: Shape, what: str) -> float:
        """A number; a length within ±:data:`MAX_LENGTH` when ``shape.metres``."""
        return self.length(node, what) if shape.metres else self.number(node, what)

    def nums(self, node: YNode | None, shape: Shape, what: str) -> tuple[float, ...]:
        """A list of numbers (``()`` for null when ``shape`` accepts it), of ``shape.length``
        items when set."""
        seq = self.sequence(node, what, nullable=shape.nullable)
        if seq is None:
            return ()
        if shape.length is not None and len(seq) != shape.length:
            raise self.fail(
                seq, f"{what} must have exactly {shape.length} numbers, found {len(seq)}"
            )
        item = shape.values
        assert item is not None
        fast = plain_numbers(seq, MAX_LENGTH if item.metres else FINITE)
        if fast is not None:
            return fast
        return tuple(self.num(n, item, f"{what}[{i}]") for i, n in enumerate(seq))
