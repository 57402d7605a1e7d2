"""Is a link's collision geometry where its visual geometry is? A check made when fitting.

A vendor's collision meshes exported in another frame than the visual ones (Flexiv's Rizon 10:
every collision STL turned -90° about x) are fitted faithfully, and nothing else shows it: the
planner then avoids a robot that is not there. :func:`visual_disagreements` compares, per
link fitted from its ``<collision>`` elements that also has ``<visual>`` elements, the two
axis-aligned boxes in the link frame (the collision solid's, and the visual elements' read
cheaply by :func:`~xrdf_tools.robot.element_bounds.elements_bounds`). They disagree when

* a quarter turn of the collision box about the link's x, y or z axis makes it agree with the
  visual box (``TURNED_AGREES`` of the smaller box inside the other) while as it is it does not
  (under ``AS_IS_DISAGREES``): the message names the turn; or
* the boxes are apart by more than the larger of them is across (a collision ``<origin>``
  with a misplaced number: Alex's nub, its ``rpy`` written in its ``xyz``, 1.5 m away).

A placeholder (collision geometry less than ``PLACEHOLDER_SIZE``, 2 cm, across) is said to be
apart or shifted only from :data:`APART_FLOOR` on: two 2 mm boxes 49 mm apart, the youBot's
``base_footprint``, are no misplaced part.

Collision geometry that is a coarser or partial model of the link (a cylinder over a joint, a
box for a camera, a hip motor beside the hip's visual) is not flagged: over
example-robot-data the overlap of such boxes falls to 0, but no quarter turn makes them agree
(at most 0.73) and none is apart by more than 0.42 of its size. A link fitted from its
visual geometry (``--from visual``, or the ``auto`` fallback) is never compared with itself.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, Literal

import numpy as np

from ..diagnostics import Diagnostic, Severity
from ..robot.element_bounds import Box, Unbounded, elements_bounds
from ..util.arrays import FloatArray
from ..util.numbers import PLACEHOLDER_SIZE
from ..util.text import name_list

if TYPE_CHECKING:
    from ..robot.core import Robot
    from ..robot.packages import PackagePaths
    from .geometry import LinkGeometry

__all__ = [
    "RULE_MISMATCH",
    "RULE_UNCHECKED",
    "VISUAL_CHECKS",
    "VisualCheck",
    "box_agreement",
    "visual_disagreements",
]

#: ``fast``: visual STL, OBJ, COLLADA and GLB meshes and primitives are read without trimesh
#: (other formats, and a COLLADA or GLB file its reader gives up on, are counted in one note);
#: ``all``: those
#: too, through trimesh (about 25 ms a file, and half a second to start); ``off``: no check.
VisualCheck = Literal["fast", "all", "off"]
VISUAL_CHECKS: tuple[VisualCheck, ...] = ("fast", "all", "off")

RULE_MISMATCH = "spheres-collision-not-visual"
RULE_UNCHECKED = "spheres-visual-unchecked"
#: A placeholder's boxes apart or shifted by less than this (metres) are not said to be: a few
#: centimetres between millimetre boxes is no misplaced ``<origin>``.
APART_FLOOR = 0.1
#: Below this share of the smaller box inside the other, the boxes do not agree as they are.
AS_IS_DISAGREES = 0.5
#: At or above this share after a quarter turn, the turn is what they differ by.
TURNED_AGREES = 0.9
#: A collision box of the visual box's size that disagrees with it is said to be shifted from
#: this far (metres): below it, a few millimetres on a finger joint (TIAGo's thumb, whose
#: collision mesh is its visual one mirrored) are no misplaced <origin>.
SHIFT_SAID = 0.01
#: Each box is taken at least this share of the larger box's size thick (a flat plate has a
#: box of no volume, which no share could compare).
_THICKNESS_FLOOR = 0.1
_AXES = "xyz"


def box_agreement(a: Box, b: Box) -> float:
    """The share of the smaller of boxes ``a`` and ``b`` inside the other (1: one holds the
    other), each at least a tenth of the larger's size thick."""
    size = float(max(a.extents.max(), b.extents.max()))
    if size <= 0.0:
        return 1.0
    (alo, ahi), (blo, bhi) = (_thickened(box, _THICKNESS_FLOOR * size) for box in (a, b))
    inside = np.clip(np.minimum(ahi, bhi) - np.maximum(alo, blo), 0.0, None).prod()
    return float(inside / min((ahi - alo).prod(), (bhi - blo).prod()))


def visual_disagreements(
    robot: Robot,
    geoms: Mapping[str, LinkGeometry],
    *,
    package_paths: PackagePaths | None = None,
    check: VisualCheck = "fast",
) -> list[Diagnostic]:
    """A warning per link of ``geoms`` fitted from collision geometry that disagrees with its
    visual geometry, and one note naming the links whose visual geometry was not read
    (``check``: see :data:`VisualCheck`)."""
    if check == "off":
        return []
    resolver = robot.mesh_resolver(package_paths)
    out: list[Diagnostic] = []
    unread: list[tuple[str, Unbounded]] = []
    for name, geom in geoms.items():
        if geom.source != "collision":
            continue
        visual = elements_bounds(robot, name, "visual", resolver, other_formats=check == "all")
        if isinstance(visual, Unbounded):
            unread.append((name, visual))
        elif visual is not None:
            lo, hi = (np.asarray(v, dtype=np.float64) for v in geom.solid.bounds)
            said = _disagreement(name, Box(lo, hi), visual, _single_origin(robot, name))
            if said is not None:
                out.append(_at_collision(robot, name, said))
    if unread:
        out.append(_unchecked(robot.path, unread))
    return out


def _disagreement(link: str, collision: Box, visual: Box, origin: FloatArray | None) -> str | None:
    """Why ``collision`` disagrees with ``visual`` (a sentence), or None when they agree."""
    as_is = box_agreement(collision, visual)
    boxes = (
        f"link '{link}': collision geometry not where its visual geometry is (link frame, m): "
        f"collision box {collision.describe()}, visual box {visual.describe()}"
    )
    kept = "spheres fitted to the collision geometry as it is"
    if as_is < AS_IS_DISAGREES:
        share, axis, sign = max(
            (box_agreement(_turned(collision, axis, sign), visual), axis, sign)
            for axis in range(3)
            for sign in (1, -1)
        )
        if share >= TURNED_AGREES:
            turn = f"{'+' if sign > 0 else '-'}90° about {_AXES[axis]}"
            return (
                f"{boxes}; turned {turn} the collision box matches the visual one ({share:.0%} "
                f"of the smaller inside the other, against {as_is:.0%}): collision meshes "
                f"exported in another frame?{_fix(axis, sign, origin)}; {kept}"
            )
    gap = float(np.linalg.norm(_gap(collision, visual)))
    across = float(max(np.linalg.norm(collision.extents), np.linalg.norm(visual.extents)))
    tiny = float(np.linalg.norm(collision.extents)) < PLACEHOLDER_SIZE
    if gap > (max(across, APART_FLOOR) if tiny else across):
        return (
            f"{boxes}; they are {gap:.3g} m apart, farther than either is across: check the "
            f"<origin> of its <collision>; {kept}"
        )
    shift = np.round(visual.centre - collision.centre, 5) + 0.0  # 0.01 mm; no -0
    moved = box_agreement(Box(collision.low + shift, collision.high + shift), visual)
    if (
        as_is < AS_IS_DISAGREES
        and moved >= TURNED_AGREES
        and _same_size(collision, visual)
        and float(np.linalg.norm(shift)) >= (APART_FLOOR if tiny else SHIFT_SAID)
    ):
        by = _numbers(shift).replace(" ", ", ")
        return (
            f"{boxes}; shifted by ({by}) m the collision box matches the visual one "
            f"({moved:.0%} of the smaller inside the other, against {as_is:.0%}): an <origin> "
            f"given to the <visual> and not to the <collision>?{_moved(shift, origin)}; {kept}"
        )
    return None


def _same_size(a: Box, b: Box) -> bool:
    """Boxes of one size along each axis, within a tenth of the larger's size: one mesh, or
    one shape, placed twice (a small collision box inside a large visual one is not)."""
    size = float(max(a.extents.max(), b.extents.max()))
    return bool(np.all(np.abs(a.extents - b.extents) <= 0.1 * size))


def _moved(shift: FloatArray, origin: FloatArray | None) -> str:
    """The collision ``<origin>`` that shifts the link's only collision element by ``shift``
    (link frame), when that element is not turned (else nothing)."""
    if origin is None or not np.allclose(origin[:3, :3], np.eye(3)):
        return ""
    xyz = origin[:3, 3] + shift
    return f' <origin xyz="{_numbers(xyz)}" rpy="0 0 0"/> in its <collision> moves it'


def _thickened(box: Box, floor: float) -> tuple[FloatArray, FloatArray]:
    half = np.maximum(box.extents / 2.0, floor / 2.0)
    return box.centre - half, box.centre + half


def _turn_matrix(axis: int, sign: int) -> FloatArray:
    """A quarter turn about ``axis`` (0, 1, 2: x, y, z), anticlockwise for ``sign`` > 0."""
    i, j = (axis + 1) % 3, (axis + 2) % 3
    rotation = np.eye(3)
    rotation[i, i] = rotation[j, j] = 0.0
    rotation[j, i], rotation[i, j] = float(sign), float(-sign)
    return rotation


def _turned(box: Box, axis: int, sign: int) -> Box:
    """``box`` turned a quarter about the link frame's ``axis`` (exact: a quarter turn maps
    an axis-aligned box to one)."""
    corners = np.array(
        [[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], dtype=np.float64
    )
    points = (box.low + corners * box.extents) @ _turn_matrix(axis, sign).T
    return Box(points.min(axis=0), points.max(axis=0))


def _gap(a: Box, b: Box) -> FloatArray:
    """Per axis, how far apart the boxes are (0 where they overlap)."""
    return np.asarray(np.maximum(0.0, np.maximum(a.low - b.high, b.low - a.high)), np.float64)


def _single_origin(robot: Robot, link: str) -> FloatArray | None:
    """The ``<origin>`` (4x4) of ``link``'s only collision element, when it has one."""
    elements = list(robot.urdf.link_map[link].collisions or ())
    if len(elements) != 1:
        return None
    origin = elements[0].origin
    return np.eye(4) if origin is None else np.asarray(origin, dtype=np.float64)


def _fix(axis: int, sign: int, origin: FloatArray | None) -> str:
    """The collision ``<origin>`` that turns the link's only collision element, when that
    element is not turned already (else the turn is only named)."""
    if origin is None or not np.allclose(origin[:3, :3], np.eye(3)):
        return ""
    xyz = _turn_matrix(axis, sign) @ origin[:3, 3]
    rpy = [0.0, 0.0, 0.0]
    rpy[axis] = sign * 1.5708
    return f' <origin xyz="{_numbers(xyz)}" rpy="{_numbers(rpy)}"/> in its <collision> turns it'


def _numbers(values: object) -> str:
    out = []
    for v in np.asarray(values, dtype=np.float64):
        text = f"{v:.6g}"
        out.append("0" if text == "-0" else text)
    return " ".join(out)


def _at_collision(robot: Robot, link: str, message: str) -> Diagnostic:
    """A warning at ``link``'s first ``<collision>`` element (its ``<link>`` when that line
    is not known: a xacro macro wrote it)."""
    line = None
    if robot.document is not None:
        written = (e for e in robot.document.findall("link") if e.get("name") == link)
        element = next(written, None)
        collision = None if element is None else element.find("collision")
        line = getattr(collision, "sourceline", None) or None
    if line is None:
        line = robot.link_lines.get(link)
    return Diagnostic(robot.path, line, None, RULE_MISMATCH, Severity.WARNING, message)


def _unchecked(path: str, unread: list[tuple[str, Unbounded]]) -> Diagnostic:
    """One note: the links whose visual geometry was not read, so not compared: those in a
    format the fast check skips, and those that could not be read (the first reason)."""
    skipped = [(n, u.format) for n, u in unread if u.format is not None]
    failed = [(n, u.reason) for n, u in unread if u.format is None]
    parts = []
    if skipped:
        formats = "/".join(sorted({str(f) for _, f in skipped}))
        parts.append(
            f"{len(skipped)} with {formats} visual meshes ({name_list([n for n, _ in skipped])}; "
            "--visual-check all reads them through trimesh, slower)"
        )
    if failed:
        parts.append(
            f"{len(failed)} whose visual geometry cannot be read "
            f"({name_list([n for n, _ in failed])}; first: {failed[0][1]})"
        )
    message = (
        "collision geometry not compared with the visual geometry of "
        f"{len(unread)} link(s): {'; '.join(parts)}"
    )
    return Diagnostic(path, None, None, RULE_UNCHECKED, Severity.INFO, message)
