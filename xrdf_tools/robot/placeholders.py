"""Links whose collision geometry is a placeholder: a part too small to plan around.

URDFs give frames that carry no real part a tiny collision primitive (UR's ``ee_link``: a
1 cm box) so that tools which expect every link to have geometry load them. A link whose
collision geometry spans less than :data:`PLACEHOLDER_SIZE` across is such a placeholder: the
fitter gives it one sphere (``spheres-placeholder``), and lint does not call it invisible to the
planner when a hand-written XRDF gives it none (NVIDIA's own UR XRDFs give ``ee_link`` none).

Read from the URDF's primitives alone (no mesh is opened, so lint stays light): a mesh part is
never judged a placeholder here. Each primitive counts as the box it fills, turned by its
origin; the size is the diagonal of the box around them all, as the fitter measures a link's
solid.
"""

from __future__ import annotations

import math
from typing import Any

from ..util.numbers import PLACEHOLDER_SIZE
from ..util.rotations import matrix_from_rpy
from .core import Robot

__all__ = ["placeholder_links", "primitive_half_extents"]


def placeholder_links(robot: Robot) -> dict[str, float]:
    """``{link: size across in metres}`` of the links whose every collision element is a
    primitive and which together span less than :data:`PLACEHOLDER_SIZE`."""
    if robot.document is None:
        return {}
    out: dict[str, float] = {}
    for link in robot.document.findall("link"):
        size = _link_size(link.findall("collision"))
        if size is not None and size < PLACEHOLDER_SIZE:
            out[str(link.get("name"))] = size
    return out


def _link_size(collisions: list[Any]) -> float | None:
    """Diagonal of the axis-aligned box, in the link frame, around the link's collision
    primitives (None: no collision, a mesh, or a number that is not one)."""
    if not collisions:
        return None
    lo, hi = [math.inf] * 3, [-math.inf] * 3
    for element in collisions:
        geometry = element.find("geometry")
        shape = None if geometry is None or len(geometry) == 0 else geometry[0]
        half = None if shape is None else primitive_half_extents(shape)
        origin = element.find("origin")
        xyz = _numbers("0 0 0" if origin is None else origin.get("xyz", "0 0 0"), 3)
        rpy = _numbers("0 0 0" if origin is None else origin.get("rpy", "0 0 0"), 3)
        if half is None or xyz is None or rpy is None:
            return None
        rotation = matrix_from_rpy(*rpy)
        for axis in range(3):
            reach = sum(abs(rotation[axis][k]) * half[k] for k in range(3))
            lo[axis] = min(lo[axis], xyz[axis] - reach)
            hi[axis] = max(hi[axis], xyz[axis] + reach)
    return math.dist(lo, hi)


def primitive_half_extents(shape: Any) -> tuple[float, float, float] | None:
    """Half the sides of the box a URDF primitive (``<box>``, ``<sphere>``, ``<cylinder>``,
    ``<capsule>``: the last two along z) fills in its own frame, in metres; None for a mesh or
    an unreadable size."""
    tag = shape.tag
    if tag == "box":
        size = _numbers(shape.get("size", ""), 3)
        return None if size is None else (abs(size[0]) / 2, abs(size[1]) / 2, abs(size[2]) / 2)
    radius = _numbers(shape.get("radius", ""), 1)
    if radius is None:
        return None
    r = abs(radius[0])
    if tag == "sphere":
        return (r, r, r)
    length = _numbers(shape.get("length", ""), 1)
    if length is None or tag not in ("cylinder", "capsule"):
        return None
    return (r, r, abs(length[0]) / 2 + (r if tag == "capsule" else 0.0))


def _numbers(text: str, n: int) -> list[float] | None:
    """The ``n`` finite numbers of an attribute, or None."""
    try:
        values = [float(v) for v in text.split()]
    except ValueError:
        return None
    if len(values) != n or not all(math.isfinite(v) for v in values):
        return None
    return values
