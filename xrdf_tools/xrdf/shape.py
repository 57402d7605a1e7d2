"""The shape of an XRDF document, described once: keys per section, which are required, the type
of every value, fixed list lengths, where null is accepted and which keys exist in one XRDF
version only.

It is written in the shape vocabulary of every YAML input (:class:`~xrdf_tools.yaml.shape.Shape`):
``fields`` sections (of which ``required`` keys must be present), ``dict`` mappings from names to
values, lists (of a fixed ``length`` when set), names (``str``), finite numbers (``num``; with
``metres``: a length or coordinate within ±:data:`MAX_LENGTH`), and the kinds only an XRDF has:
``groupref`` (a group name, or a one-item list of one), ``buffers`` (a ``dict`` of lengths or a
single length) and ``modifier`` (a one-key mapping naming one of :data:`MODIFIERS`).
``versions`` says in which XRDF versions a key exists; ``length_rule`` which lint rule reports a
list of the wrong length (``sphere-center`` words it for sphere centres).

Two consumers read this description, each with its own wording:

* the strict reader (:mod:`xrdf_tools.xrdf.read`) takes required keys, nullability, list lengths
  and the lengths-in-metres bound from it and raises one
  :class:`~xrdf_tools.util.errors.SchemaError` at the first departure it meets while building the
  model;
* lint's all-errors walker (:func:`xrdf_tools.lint.schema.walk`) reports every departure as a
  ``wrong-type``, ``unknown-key`` or ``required-key`` finding, and ``version-key`` asks
  :func:`exists_in`.

``python -m xrdf_tools.xrdf.schema`` turns this description into ``docs/xrdf.schema.json``.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace

from ..util.numbers import MAX_LENGTH
from ..yaml.io import YNode, YScalar
from ..yaml.shape import Shape, is_name, is_number

__all__ = [
    "DOCUMENT",
    "MAX_LENGTH",
    "MODIFIERS",
    "SUPPORTED_VERSIONS",
    "Shape",
    "exists_in",
    "is_name",
    "is_number",
    "version_string",
]

#: The XRDF versions there are (``format_version``).
SUPPORTED_VERSIONS = ("1.0", "2.0")


def version_string(node: YNode | None) -> str | None:
    """Normalise ``format_version`` (``1.0``, ``1``, ``"2.0"``) to ``"1.0"``/``"2.0"``."""
    if not isinstance(node, YScalar) or isinstance(node.value, bool) or node.value is None:
        return None
    v = node.value
    try:
        f = float(v)
    except (TypeError, ValueError, OverflowError):  # OverflowError: an integer past 1e308
        return str(v)
    return f"{f:.1f}" if f.is_integer() else str(v)


def exists_in(section: Shape, key: str, version: str) -> bool:
    """Whether ``key`` of ``section`` exists in XRDF ``version`` (unknown keys: False)."""
    sub = section.fields.get(key)
    return sub is not None and (not sub.versions or version in sub.versions)


NUM = Shape("num", nullable=False)
LENGTH = Shape("num", nullable=False, metres=True)
STR = Shape("str", nullable=False)
NAMES = Shape("list", values=STR)
VEC3 = Shape("list", values=NUM, length=3, nullable=False)
POSITION = Shape("list", values=LENGTH, length=3, nullable=False)

ORIENTATION = Shape(
    "fields",
    {
        "w": NUM,
        "xyz": VEC3,
        "quaternion": Shape("list", values=NUM, length=4, nullable=False),
        "euler_rpy": VEC3,
    },
)
FIXED_TRANSFORM = Shape(
    "fields",
    {"position": POSITION, "orientation": ORIENTATION},
    required=("position",),
    nullable=False,
)
ADD_FRAME = Shape(
    "fields",
    {
        "frame_name": STR,
        "parent_frame_name": STR,
        "joint_name": STR,
        "joint_type": STR,
        "fixed_transform": FIXED_TRANSFORM,
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
        "velocity_limit": Shape("num"),  # cuRobo's singular spelling, read as velocity_limits
    },
    required=("joint_name",),
    nullable=False,
    versions=("2.0",),
)
#: The modifiers, by the one key each list item has.
MODIFIERS: Mapping[str, Shape] = {
    "add_frame": ADD_FRAME,
    "set_base_frame": STR,
    "remove_mimic_attributes": REMOVE_MIMIC,
}
CSPACE = Shape(
    "fields",
    {
        "joint_names": NAMES,
        "acceleration_limits": Shape("list", values=NUM),
        "jerk_limits": Shape("list", values=NUM),
    },
    required=("joint_names", "acceleration_limits", "jerk_limits"),
    nullable=False,
)
GROUP_REF = Shape("groupref", nullable=False)
BUFFERS = Shape("buffers", values=LENGTH)
WORLD = Shape(
    "fields",
    {"geometry": GROUP_REF, "buffer_distance": BUFFERS},
    required=("geometry",),
    nullable=False,
)
SELF = Shape(
    "fields",
    {
        "geometry": GROUP_REF,
        "buffer_distance": BUFFERS,
        "ignore": Shape("dict", values=NAMES),
    },
    required=("geometry",),
    nullable=False,
)
SPHERE = Shape(
    "fields",
    {
        "center": Shape(
            "list", values=LENGTH, length=3, nullable=False, length_rule="sphere-center"
        ),
        "radius": LENGTH,
    },
    required=("center", "radius"),
    nullable=False,
)
GROUP = Shape(
    "fields",
    {
        "spheres": Shape("dict", values=Shape("list", values=SPHERE)),
        "clone": replace(NAMES, versions=("2.0",)),
    },
)
#: The whole document. ``format`` and ``format_version`` are required (their values are judged
#: by the reader and by the ``format-key``/``format-version`` rules, in their own words);
#: ``cspace`` is required of a robot description but not of a geometry-only fragment, so
#: ``required-key`` judges it and the reader accepts a file without it.
DOCUMENT = Shape(
    "fields",
    {
        "format": Shape("any"),
        "format_version": Shape("any"),
        "modifiers": Shape("list", values=Shape("modifier", nullable=False)),
        "default_joint_positions": Shape("dict", values=NUM),
        "cspace": CSPACE,
        "tool_frames": NAMES,
        "collision": replace(WORLD, versions=("1.0",)),
        "world_collision": replace(WORLD, versions=("2.0",)),
        "self_collision": SELF,
        "geometry": Shape("dict", values=GROUP),
    },
    required=("format", "format_version"),
    nullable=False,
)
