"""The all-errors walker of the shape vocabulary (:mod:`xrdf_tools.yaml.shape`): one walk over an
XRDF tree that reports every place where the file departs from its shape.

The shape itself is described once, in :mod:`xrdf_tools.xrdf.shape` (the strict reader uses the
same description; readers of foreign YAML use the first-error walker,
:func:`xrdf_tools.yaml.shape.check_shape`). The walk yields :class:`SchemaEvent` items of
three kinds, each consumed by one rule: ``type`` (``wrong-type``), ``missing``
(``required-key``) and ``unknown`` (``unknown-key``). Version-specific keys
(``collision``/``world_collision``, ``clone``, ``remove_mimic_attributes``) are part of the
shape for both versions; ``version-key`` judges them.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import Literal

from ..util.numbers import MAX_LENGTH, bound_problem
from ..xrdf.nodes import FINITE, plain_number
from ..xrdf.shape import DOCUMENT, LENGTH, MODIFIERS, NUM, Shape, is_name, is_number
from ..yaml.io import YMap, YNode, YPlainSeq, YScalar, YSeq, describe_node, key_of
from ..yaml.shape import MAPPINGS

__all__ = ["DOCUMENT", "MODIFIERS", "SchemaEvent", "Shape", "walk"]

EventKind = Literal["type", "missing", "unknown"]


@dataclass(frozen=True)
class SchemaEvent:
    """``node`` is the offending node (for ``missing``: the mapping that lacks ``key``)."""

    kind: EventKind
    node: YNode
    key_path: str
    message: str
    key: str = ""
    choices: tuple[str, ...] = ()


def _child(kp: str, key: object) -> str:
    return f"{kp}.{key}" if kp else str(key)


def walk(node: YNode | None, shape: Shape = DOCUMENT, kp: str = "") -> Iterator[SchemaEvent]:
    """Every departure of ``node`` from ``shape`` (nothing for a missing optional node)."""
    if node is None:
        return
    what = kp or "the document"
    if isinstance(node, YScalar) and node.value is None:
        if not shape.nullable:
            yield SchemaEvent("type", node, kp, f"{what} must not be null")
        return
    if shape.kind in MAPPINGS and not isinstance(node, YMap):
        yield SchemaEvent("type", node, kp, f"{what} must be a mapping, not {describe_node(node)}")
        return
    yield from _WALKERS[shape.kind](node, shape, kp, what)


_Walker = Callable[[YNode, Shape, str, str], Iterator[SchemaEvent]]


def _walk_any(node: YNode, shape: Shape, kp: str, what: str) -> Iterator[SchemaEvent]:
    return iter(())


def _walk_num(node: YNode, shape: Shape, kp: str, what: str) -> Iterator[SchemaEvent]:
    if is_number(node) and not shape.metres:
        return
    v = node.value if isinstance(node, YScalar) else None
    if isinstance(v, (int, float)) and not isinstance(v, bool):
        problem = bound_problem(v, metres=shape.metres)
        if problem is not None:
            yield SchemaEvent("type", node, kp, f"{what} {problem}")
    else:
        yield SchemaEvent("type", node, kp, f"{what} must be a number, not {describe_node(node)}")


def _walk_str(node: YNode, shape: Shape, kp: str, what: str) -> Iterator[SchemaEvent]:
    if not is_name(node):
        yield SchemaEvent(
            "type", node, kp, f"{what} must be a non-empty name, not {describe_node(node)}"
        )


def _walk_groupref(node: YNode, shape: Shape, kp: str, what: str) -> Iterator[SchemaEvent]:
    if isinstance(node, YSeq) and len(node) == 1 and is_name(node.items[0]):
        return
    if not is_name(node):
        yield SchemaEvent(
            "type", node, kp, f"{what} must name a geometry group, not {describe_node(node)}"
        )


def _walk_buffers(node: YNode, shape: Shape, kp: str, what: str) -> Iterator[SchemaEvent]:
    if is_number(node, finite=False):  # one length for every frame (cuRobo style)
        yield from _walk_num(node, LENGTH, kp, what)  # see unconfirmed-syntax for the style
        return
    yield from walk(node, Shape("dict", values=shape.values or NUM), kp)


def _walk_list(node: YNode, shape: Shape, kp: str, what: str) -> Iterator[SchemaEvent]:
    if not isinstance(node, YSeq):
        yield SchemaEvent("type", node, kp, f"{what} must be a list, not {describe_node(node)}")
        return
    wrong_length = shape.length is not None and len(node) != shape.length
    if wrong_length and shape.length_rule == "wrong-type":  # else that rule words it
        yield SchemaEvent(
            "type", node, kp, f"{what} must have exactly {shape.length} items, found {len(node)}"
        )
    if shape.values is not None and not _plain_items_fit(node, shape.values):
        for i, item in enumerate(node.items):
            if not _quiet(item, shape.values):
                yield from walk(item, shape.values, f"{kp}[{i}]")


# --- what the walk would not report, known cheaply (a big file is mostly lists of spheres) ---
def _plain_items_fit(node: YSeq, shape: Shape) -> bool:
    """Whether every item of a list of plain scalars (:class:`YPlainSeq`) fits ``shape``
    (a number or a name), known from the values alone; False when unsure."""
    if type(node) is not YPlainSeq:
        return False
    if shape.kind == "num":
        bound = MAX_LENGTH if shape.metres else FINITE
        return all(plain_number(v, bound) is not None for v in node.values)
    if shape.kind == "str":
        return all(_is_name_value(v) for v in node.values)
    return False


def _is_name_value(v: object) -> bool:
    return (type(v) is str and v != "") or type(v) is int or type(v) is float


def _quiet(node: YNode, shape: Shape) -> bool:
    """Whether :func:`walk` yields nothing for ``node``: decided for scalars, lists and
    ``fields`` sections of them (a sphere); False when unsure (the node is then walked)."""
    kind = shape.kind
    if type(node) is YScalar:
        v = node.value
        if v is None:
            return shape.nullable
        if kind == "num":
            return plain_number(v, MAX_LENGTH if shape.metres else FINITE) is not None
        return kind == "any" or (kind == "str" and _is_name_value(v))
    if kind == "list" and isinstance(node, YSeq):
        wrong_length = shape.length is not None and len(node) != shape.length
        if wrong_length and shape.length_rule == "wrong-type":
            return False
        values = shape.values
        return (
            values is None
            or _plain_items_fit(node, values)
            or (type(node) is not YPlainSeq and all(_quiet(i, values) for i in node.items))
        )
    if kind == "fields" and type(node) is YMap and len(node.pairs) <= len(shape.fields):
        for req in shape.required:
            if req not in node:
                return False
        for k, val in node.pairs:
            key = k.value if type(k) is YScalar else None
            sub = shape.fields.get(key) if isinstance(key, str) else None
            if sub is None or not _quiet(val, sub):
                return False
        return True
    return False


def _walk_modifier(node: YNode, shape: Shape, kp: str, what: str) -> Iterator[SchemaEvent]:
    assert isinstance(node, YMap)
    if len(node.pairs) != 1:
        yield SchemaEvent(
            "type",
            node,
            kp,
            f"{what} must have exactly one key (one of {', '.join(MODIFIERS)}), "
            f"found {len(node.pairs)}",
        )
    for kn, val in node.pairs:
        key = key_of(kn)
        sub = MODIFIERS.get(key) if isinstance(key, str) else None
        if sub is None:
            yield SchemaEvent(
                "unknown",
                kn,
                _child(kp, key),
                f"unknown modifier '{key}'",
                str(key),
                tuple(MODIFIERS),
            )
        else:
            yield from walk(val, sub, _child(kp, key))


def _walk_dict(node: YNode, shape: Shape, kp: str, what: str) -> Iterator[SchemaEvent]:
    assert isinstance(node, YMap)
    for kn, val in node.pairs:
        if not is_name(kn):
            yield SchemaEvent(
                "type", kn, kp, f"a key of {what} must be a name, not {describe_node(kn)}"
            )
            continue
        if shape.values is not None:
            yield from walk(val, shape.values, _child(kp, key_of(kn)))


def _walk_fields(node: YNode, shape: Shape, kp: str, what: str) -> Iterator[SchemaEvent]:
    assert isinstance(node, YMap)
    for req in shape.required:
        if req not in node:
            yield SchemaEvent("missing", node, kp, f"{what} is missing required key '{req}'", req)
    for kn, val in node.pairs:
        key = key_of(kn)
        sub = shape.fields.get(key) if isinstance(key, str) else None
        if sub is None:
            yield SchemaEvent(
                "unknown",
                kn,
                _child(kp, key),
                f"unknown key '{key}' in {what}",
                str(key),
                tuple(shape.fields),
            )
            continue
        yield from walk(val, sub, _child(kp, key))


_WALKERS: dict[str, _Walker] = {
    "any": _walk_any,
    "num": _walk_num,
    "str": _walk_str,
    "groupref": _walk_groupref,
    "buffers": _walk_buffers,
    "list": _walk_list,
    "modifier": _walk_modifier,
    "dict": _walk_dict,
    "fields": _walk_fields,
}
