"""Joint axes cuRobo can take, written into the URDF that ``xrdf export curobo`` writes.

cuRobo's kinematics turns about and slides along ±x, ±y and ±z only; its loader raises on any
other axis of a joint on the chains it builds (``curobo-joint-axis``). The URDF the export
writes for cuRobo gives every moving joint such an axis and is the same robot:

* an axis a rounding error off a coordinate axis (the lint rule's notion,
  :func:`~xrdf_tools.robot.axes.coordinate_axis_near`) is written as that axis, exactly;
* a tilted axis ``a`` gets the rewrite that keeps every link frame where it is: with ``R`` the
  rotation that takes z onto ``a`` by the shortest way, the joint keeps its name, parent,
  type, limits and mimic and turns about (slides along) z of its origin rotated by ``R``, its
  child becomes a new frame-only link ``<child>__axis``, and the original child hangs from
  that by a new fixed joint ``<joint>__axis`` with origin ``R⁻¹``. Rotation (translation)
  about ``a`` is ``R · (about z) · R⁻¹``, so each link's pose at every configuration is the
  one it had: meshes, spheres, tool frames, the c-space joint names and the XRDF stay valid.

Names never collide: a name taken by a link (joint) of the robot, or by a frame or joint the
XRDF adds (``add_frame``, which cuRobo adds to the URDF's links as ``extra_links``), gets
``_2``, ``_3``, ...
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from ..robot.axes import Axis, coordinate_axis_near, degrees_off, is_coordinate_axis
from ..util.text import name_list

if TYPE_CHECKING:
    from ..robot.core import Robot
    from ..util.arrays import FloatArray

__all__ = ["AxisRewrite", "axes_note", "axes_to_rewrite", "straighten_axes"]

#: What the export adds to a name for the frame-only link and the fixed joint it writes.
SUFFIX = "__axis"


@dataclass(frozen=True)
class AxisRewrite:
    """One moving joint whose axis cuRobo cannot take as written."""

    joint: str
    #: The axis as the URDF writes it.
    axis: Axis
    #: The coordinate axis it is but for rounding, written instead; None: tilted.
    exact: Axis | None

    @property
    def degrees(self) -> float:
        """How far the axis is off the nearest coordinate axis."""
        return degrees_off(self.axis)


def axes_to_rewrite(robot: Robot) -> list[AxisRewrite]:
    """The moving joints of ``robot`` (mimic followers included), in URDF order, whose axis is
    not exactly ±x, ±y or ±z; one whose direction is such an axis but for rounding (or a scaled
    one, ``0 0 2``) is to be written as that axis. A zero or non-finite axis is left to the
    checks that refuse it."""
    out = []
    for j in robot.joints.values():
        if not j.is_movable or is_coordinate_axis(j.axis):
            continue
        length = math.sqrt(sum(a * a for a in j.axis))
        if not math.isfinite(length) or length == 0.0:
            continue
        direction = (j.axis[0] / length, j.axis[1] / length, j.axis[2] / length)
        out.append(AxisRewrite(j.name, j.axis, coordinate_axis_near(direction)))
    return out


def straighten_axes(
    text: str, path: str, rewrites: Sequence[AxisRewrite], reserved: Iterable[str] = ()
) -> str:
    """The URDF ``text`` (of the file ``path``, for messages) with ``rewrites`` applied, the
    rest of the document as it was; the new links and joints take none of the names
    ``reserved`` (the frames and joints an XRDF adds). Raises
    :class:`~xrdf_tools.util.errors.SourceError`."""
    from .srdf_xml import XmlDocument

    doc = XmlDocument.parse(text, path, "robot", "URDF", undeclared_prefixes=True)
    root = doc.root
    joints = {str(e.get("name")): e for e in root.iterchildren("joint")}
    links = {str(e.get("name")) for e in root.iterchildren("link")} | set(reserved)
    joint_names = set(joints) | set(reserved)
    for rw in rewrites:
        element = joints[rw.joint]
        if rw.exact is not None:
            _axis_element(element).set("xyz", _xyz(rw.exact))
        else:
            _rotate_joint(root, element, rw.axis, links, joint_names)
    return doc.serialize().decode("utf-8")


def _rotate_joint(
    root: Any, element: Any, axis: Axis, links: set[str], joint_names: set[str]
) -> None:
    """Turn the joint ``element`` about z of its origin rotated onto ``axis``, through a new
    frame-only link and fixed joint (names added to ``links`` and ``joint_names``)."""
    import numpy as np
    from lxml import etree

    from ..robot.urdf_joints import origin_matrix
    from ..util.rotations import rpy_from_matrix
    from .srdf_xml import insert_after

    rotation = _z_onto(axis)
    origin = element.find("origin")
    if origin is None:
        origin = etree.SubElement(element, "origin")
    turned = origin_matrix(origin)[:3, :3] @ rotation
    origin.set("rpy", _xyz(rpy_from_matrix(turned)))
    _axis_element(element).set("xyz", "0 0 1")
    child = element.find("child")
    frame = _free_name(f"{child.get('link')}{SUFFIX}", links)
    fixed_name = _free_name(f"{element.get('name')}{SUFFIX}", joint_names)
    link = etree.Element("link", name=frame)
    fixed = etree.Element("joint", name=fixed_name, type="fixed")
    etree.SubElement(fixed, "parent", link=frame)
    etree.SubElement(fixed, "child", link=str(child.get("link")))
    back = rpy_from_matrix(np.ascontiguousarray(rotation.T))
    etree.SubElement(fixed, "origin", xyz="0 0 0", rpy=_xyz(back))
    for i, part in enumerate(fixed):  # laid out as the joint it follows
        part.tail = element.text if i < len(fixed) - 1 else element[-1].tail
    fixed.text = element.text
    child.set("link", frame)
    insert_after(root, element, [link, fixed])


def _z_onto(axis: Axis) -> FloatArray:
    """The rotation that takes z onto the direction of ``axis`` by the shortest way (about
    ``z × axis``; a half turn about x for -z)."""
    import numpy as np

    from ..util.rotations import axis_angle_matrix

    a = np.asarray(axis, dtype=np.float64)
    a = a / np.linalg.norm(a)
    k = np.array([-a[1], a[0], 0.0])  # z × a
    s = float(np.linalg.norm(k))
    if s == 0.0:
        return np.eye(3) if a[2] > 0 else np.diag([1.0, -1.0, -1.0])
    return axis_angle_matrix(k / s, math.atan2(s, float(a[2])))


def _axis_element(joint: Any) -> Any:
    from lxml import etree

    axis = joint.find("axis")
    return axis if axis is not None else etree.SubElement(joint, "axis")


def _xyz(values: Iterable[float]) -> str:
    """Numbers as a URDF attribute, each read back as the same float: ``1``, never ``1.0``
    or ``-0``."""
    return " ".join(_number(float(v)) for v in values)


def _number(v: float) -> str:
    return str(int(v)) if v.is_integer() and abs(v) < 1e15 else repr(v)


def _free_name(name: str, taken: set[str]) -> str:
    """``name``, or ``name_2``, ``name_3``, ... when taken; added to ``taken``."""
    out, n = name, 1
    while out in taken:
        n += 1
        out = f"{name}_{n}"
    taken.add(out)
    return out


def axes_note(rewrites: Sequence[AxisRewrite], written: str) -> str:
    """One line on the joint axes rewritten in the URDF ``written``."""
    tilted = [f"{r.joint} ({r.degrees:.4g}° off)" for r in rewrites if r.exact is None]
    rounded = [
        f"{r.joint} ({'xyz'[next(i for i, a in enumerate(r.exact) if a)]})"
        for r in rewrites
        if r.exact is not None
    ]
    parts = []
    if tilted:
        parts.append(
            f"{len(tilted)} tilted axis(es) turned onto z of a rotated joint origin, each child "
            f"hanging from a new frame-only link <child>{SUFFIX}: {name_list(tilted, 12)}"
        )
    if rounded:
        parts.append(
            f"{len(rounded)} axis(es) a rounding error off a coordinate axis written exactly: "
            f"{name_list(rounded, 12)}"
        )
    return (
        f"cuRobo turns joints about x, y or z only: wrote the URDF with {'; '.join(parts)} to "
        f"{written}; urdf_path names it. Every link frame stays where it was (the same robot: "
        "joint names, meshes, spheres and the XRDF unchanged); --keep-axes writes none"
    )
