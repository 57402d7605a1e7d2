"""The shape of an XRDF document as data, and one walk over the tree that reports where the file
departs from it.

The walk yields :class:`SchemaEvent` items of three kinds, each consumed by one rule:
``type`` (``wrong-type``), ``missing`` (``required-key``) and ``unknown`` (``unknown-key``).
Version-specific keys (``collision``/``world_collision``, ``clone``,
``remove_mimic_attributes``) are part of the shape for both versions; ``version-key`` judges them.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from typing import Literal

from ..xrdf_io import describe
from ..yaml_io import YMap, YNode, YScalar, YSeq, key_of

Kind = Literal["fields", "dict", "list", "str", "num", "groupref", "buffers", "modifier", "any"]


@dataclass(frozen=True)
class Shape:
    """Expected shape of a node.

    ``fields``: a mapping with known keys (``fields``, of which ``required`` must be present);
    ``dict``: a mapping from names to ``values``; ``list``: a list of ``values`` (``length``
    items when set); ``str``: a name; ``num``: a finite number; ``groupref``: a group name (or a
    one-item list of one); ``buffers``: a ``dict`` of numbers or a single number;
    ``modifier``: a one-key mapping naming a modifier. ``nullable``: null is accepted.
    """

    kind: Kind
    fields: Mapping[str, Shape] = field(default_factory=dict)
    required: tuple[str, ...] = ()
    values: Shape | None = None
    length: int | None = None
    nullable: bool = True


NUM = Shape("num", nullable=False)
STR = Shape("str", nullable=False)
NAMES = Shape("list", values=STR)
VEC3 = Shape("list", values=NUM, length=3, nullable=False)

ORIENTATION = Shape(
    "fields",
    {
        "w": NUM,
        "xyz": VEC3,
        "quaternion": Shape("list", values=NUM, length=4, nullable=False),
        "euler_rpy": VEC3,
    },
)
ADD_FRAME = Shape(
    "fields",
    {
        "frame_name": STR,
        "parent_frame_name": STR,
        "joint_name": STR,
        "joint_type": STR,
        "fixed_transform": Shape(
            "fields",
            {"position": VEC3, "orientation": ORIENTATION},
            required=("position",),
            nullable=False,
        ),
    },
    required=("frame_name", "parent_frame_name", "joint_name", "fixed_transform"),
    nullable=False,
)
REMOVE_MIMIC = Shape(
    "fields",
    {
        "joint_name": STR,
        "position_limits": Shape("list", values=NUM, length=2),
        "velocity_limits": Shape("num"),
        "velocity_limit": Shape("num"),
    },
    required=("joint_name",),
    nullable=False,
)
MODIFIERS: Mapping[str, Shape] = {
    "add_frame": ADD_FRAME,
    "set_base_frame": STR,
    "remove_mimic_attributes": REMOVE_MIMIC,
}
WORLD = Shape(
    "fields",
    {"geometry": Shape("groupref", nullable=False), "buffer_distance": Shape("buffers")},
    required=("geometry",),
    nullable=False,
)
SELF = Shape(
    "fields",
    {
        "geometry": Shape("groupref", nullable=False),
        "buffer_distance": Shape("buffers"),
        "ignore": Shape("dict", values=NAMES),
    },
    required=("geometry",),
    nullable=False,
)
SPHERE = Shape(
    "fields",
    {"center": Shape("list", values=NUM, nullable=False), "radius": NUM},
    required=("center", "radius"),
    nullable=False,
)
GROUP = Shape(
    "fields",
    {"spheres": Shape("dict", values=Shape("list", values=SPHERE)), "clone": NAMES},
)
DOCUMENT = Shape(
    "fields",
    {
        "format": Shape("any"),
        "format_version": Shape("any"),
        "modifiers": Shape("list", values=Shape("modifier", nullable=False)),
        "default_joint_positions": Shape("dict", values=NUM),
        "cspace": Shape(
            "fields",
            {
                "joint_names": NAMES,
                "acceleration_limits": Shape("list", values=NUM),
                "jerk_limits": Shape("list", values=NUM),
            },
            required=("joint_names", "acceleration_limits", "jerk_limits"),
            nullable=False,
        ),
        "tool_frames": NAMES,
        "collision": WORLD,
        "world_collision": WORLD,
        "self_collision": SELF,
        "geometry": Shape("dict", values=GROUP),
    },
    nullable=False,
)

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


def _is_name(node: YNode) -> bool:
    if isinstance(node, YScalar):
        v = node.value
        if isinstance(v, str):
            return v != ""
        return isinstance(v, (int, float)) and not isinstance(v, bool)
    return False


def _is_num(node: YNode) -> bool:
    return (
        isinstance(node, YScalar)
        and isinstance(node.value, (int, float))
        and not isinstance(node.value, bool)
        and math.isfinite(node.value)
    )


def walk(node: YNode | None, shape: Shape = DOCUMENT, kp: str = "") -> Iterator[SchemaEvent]:
    """Every departure of ``node`` from ``shape`` (nothing for a missing optional node)."""
    if node is None:
        return
    what = kp or "the document"
    null = isinstance(node, YScalar) and node.value is None
    if null:
        if not shape.nullable:
            yield SchemaEvent("type", node, kp, f"{what} must not be null")
        return
    k = shape.kind
    if k == "any":
        return
    if k == "num":
        if not _is_num(node):
            v = node.value if isinstance(node, YScalar) else None
            if isinstance(v, float) and not math.isfinite(v):
                yield SchemaEvent("type", node, kp, f"{what} must be a finite number, not {v}")
            else:
                yield SchemaEvent(
                    "type", node, kp, f"{what} must be a number, not {describe(node)}"
                )
        return
    if k == "str":
        if not _is_name(node):
            yield SchemaEvent(
                "type", node, kp, f"{what} must be a non-empty name, not {describe(node)}"
            )
        return
    if k == "groupref":
        if isinstance(node, YSeq) and len(node) == 1 and _is_name(node.items[0]):
            return
        if not _is_name(node):
            yield SchemaEvent(
                "type", node, kp, f"{what} must name a geometry group, not {describe(node)}"
            )
        return
    if k == "buffers":
        if _is_num(node):
            return  # a single number for every frame (cuRobo style); see unconfirmed-syntax
        yield from walk(node, Shape("dict", values=NUM), kp)
        return
    if k == "list":
        if not isinstance(node, YSeq):
            yield SchemaEvent("type", node, kp, f"{what} must be a list, not {describe(node)}")
            return
        if shape.length is not None and len(node) != shape.length:
            yield SchemaEvent(
                "type",
                node,
                kp,
                f"{what} must have exactly {shape.length} items, found {len(node)}",
            )
        if shape.values is not None:
            for i, item in enumerate(node.items):
                yield from walk(item, shape.values, f"{kp}[{i}]")
        return
    if not isinstance(node, YMap):
        yield SchemaEvent("type", node, kp, f"{what} must be a mapping, not {describe(node)}")
        return
    if k == "modifier":
        keys = [key_of(kn) for kn, _ in node.pairs]
        if len(keys) != 1:
            yield SchemaEvent(
                "type",
                node,
                kp,
                f"{what} must have exactly one key (one of {', '.join(MODIFIERS)}), "
                f"found {len(keys)}",
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
        return
    if k == "dict":
        for kn, val in node.pairs:
            if not _is_name(kn):
                yield SchemaEvent(
                    "type", kn, kp, f"a key of {what} must be a name, not {describe(kn)}"
                )
                continue
            if shape.values is not None:
                yield from walk(val, shape.values, _child(kp, key_of(kn)))
        return
    # fields
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
