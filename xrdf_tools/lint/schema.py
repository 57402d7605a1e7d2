"""One walk over an XRDF tree that reports where the file departs from its shape.

The shape itself is described once, in :mod:`xrdf_tools.xrdf_shape` (the strict reader uses the
same description). The walk yields :class:`SchemaEvent` items of three kinds, each consumed by
one rule: ``type`` (``wrong-type``), ``missing`` (``required-key``) and ``unknown``
(``unknown-key``). Version-specific keys (``collision``/``world_collision``, ``clone``,
``remove_mimic_attributes``) are part of the shape for both versions; ``version-key`` judges them.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import Literal

from ..xrdf_shape import DOCUMENT, MODIFIERS, NUM, Shape, is_name, is_number
from ..yaml_io import YMap, YNode, YScalar, YSeq, describe_node, key_of

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
    if shape.kind in _MAPPING_KINDS and not isinstance(node, YMap):
        yield SchemaEvent("type", node, kp, f"{what} must be a mapping, not {describe_node(node)}")
        return
    yield from _WALKERS[shape.kind](node, shape, kp, what)


_Walker = Callable[[YNode, Shape, str, str], Iterator[SchemaEvent]]


def _walk_any(node: YNode, shape: Shape, kp: str, what: str) -> Iterator[SchemaEvent]:
    return iter(())


def _walk_num(node: YNode, shape: Shape, kp: str, what: str) -> Iterator[SchemaEvent]:
    if is_number(node):
        return
    v = node.value if isinstance(node, YScalar) else None
    if isinstance(v, float) and not math.isfinite(v):
        yield SchemaEvent("type", node, kp, f"{what} must be a finite number, not {v}")
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
    if is_number(node):
        return  # a single number for every frame (cuRobo style); see unconfirmed-syntax
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
    if shape.values is not None:
        for i, item in enumerate(node.items):
            yield from walk(item, shape.values, f"{kp}[{i}]")


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


_MAPPING_KINDS = frozenset({"fields", "dict", "modifier"})
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
