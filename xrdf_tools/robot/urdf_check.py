"""Check a parsed URDF (lxml tree) for everything yourdfpy would crash on or silently get
wrong, before yourdfpy sees it: names, joint types, links that joints refer to, one tree
without loops, and every number yourdfpy parses (origins, axes, limits, mimic, geometry,
inertia, dynamics, safety controller, calibration, material colours) finite and with the
right count. Every failure is a :class:`UrdfError` at the element's line.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from typing import Any

from ..diagnostics import Diagnostic, Severity
from ..util.errors import UrdfError, did_you_mean, shown_text
from ..util.numbers import MAX_NUMBER, bound_reason

__all__ = [
    "JOINT_TYPES",
    "RULE_PREFIX_UNDECLARED",
    "URDF_GEOMETRIES",
    "XACRO_NS",
    "check_urdf_tree",
]

JOINT_TYPES = ("revolute", "continuous", "prismatic", "fixed", "floating", "planar")
XACRO_NS = "http://www.ros.org/wiki/xacro"
#: The geometry elements the loader reads: yourdfpy's four, and ``<capsule>`` (not standard
#: URDF; handed to yourdfpy as a cylinder, see
#: :func:`xrdf_tools.robot.link_geometry.capsules_as_cylinders`).
URDF_GEOMETRIES = ("box", "cylinder", "sphere", "mesh", "capsule")
#: Numbers yourdfpy parses besides origins, axes, limits, mimic and geometry:
#: (element, child path, attributes, count).
_OTHER_NUMBERS: tuple[tuple[str, str, tuple[str, ...], int], ...] = (
    ("link", "inertial/origin", ("xyz", "rpy"), 3),
    ("link", "inertial/mass", ("value",), 1),
    ("link", "inertial/inertia", ("ixx", "ixy", "ixz", "iyy", "iyz", "izz"), 1),
    (
        "joint",
        "safety_controller",
        ("soft_lower_limit", "soft_upper_limit", "k_position", "k_velocity"),
        1,
    ),
    ("joint", "calibration", ("rising", "falling"), 1),
    ("joint", "dynamics", ("damping", "friction"), 1),
)

Fail = Callable[[str, Any], UrdfError]

RULE_COLOR_IGNORED = "urdf-color-ignored"
RULE_REVERSED_LIMIT = "urdf-limit-reversed"
RULE_UNBOUNDED_LIMIT = "urdf-limit-unbounded"
RULE_PREFIX_UNDECLARED = "urdf-prefix-undeclared"


class _ColorIgnored(UrdfError):
    """A material colour that is not four finite numbers (a warning, not a failure)."""


#: Robot formats a URDF is sometimes mistaken for, by their root element.
_OTHER_FORMATS = {
    "sdf": ": an SDF model (Gazebo, pybullet), not a URDF; give the robot's URDF",
    "mujoco": ": an MJCF model (MuJoCo), not a URDF; give the robot's URDF",
}


def check_urdf_tree(
    root: Any, path: str, warnings: list[Diagnostic] | None = None
) -> tuple[dict[str, int], dict[str, int]]:
    """Check what yourdfpy needs; return the line of every link and joint.

    With a ``warnings`` list, a material colour that is not four finite numbers (used only to
    draw the robot) is removed from the tree with a located ``urdf-color-ignored`` warning
    appended there, instead of failing: what no command plans with does not stop one. So is a
    revolute joint's limit of ±1e16 (how exporters write "no limit"): the joint is read as
    continuous, with a located ``urdf-limit-unbounded`` warning."""

    def fail(msg: str, el: Any) -> UrdfError:
        return UrdfError(msg, path=path, line=getattr(el, "sourceline", None))

    _check_root(root, fail)
    link_lines = _named_lines(root, "link", fail)
    if not link_lines:
        raise fail("<robot> has no <link>; a URDF needs at least one link", root)
    for el in root.findall("link"):
        _check_geometry(el, fail)
    _check_colors(root, path, fail, warnings)
    _check_other_numbers(root, fail)
    joint_lines = _named_lines(root, "joint", fail)
    edges = [_checked_joint(el, link_lines, fail, path, warnings) for el in root.findall("joint")]
    _check_is_tree(edges, joint_lines, fail)
    return link_lines, joint_lines


def _check_root(root: Any, fail: Fail) -> None:
    """The root is a named <robot> and no element is xacro's (a xacro file not expanded)."""
    from lxml import etree

    tag = etree.QName(root).localname if isinstance(root.tag, str) else str(root.tag)
    if tag != "robot":
        raise fail(
            f"the root element must be <robot>, not <{tag}>{_OTHER_FORMATS.get(tag, '')}", root
        )
    for el in root.iter():
        if isinstance(el.tag, str) and etree.QName(el).namespace == XACRO_NS:
            raise fail(
                f"<xacro:{etree.QName(el).localname}> found: this is a xacro file; expand it "
                "first (xrdf convert reads .xacro files)",
                el,
            )
    if not root.get("name"):
        raise fail("<robot> has no 'name' attribute", root)


def _checked_joint(
    el: Any,
    link_lines: Mapping[str, int],
    fail: Fail,
    path: str,
    warnings: list[Diagnostic] | None,
) -> tuple[str, str, str, Any]:
    """Check one <joint> (type, links, origin, axis, limit, mimic); its edge of the tree:
    joint, parent, child, element."""
    name = el.get("name")
    jtype = _joint_type(el, name, fail)
    parent, child = (_joint_link(el, name, role, link_lines, fail) for role in ("parent", "child"))
    _check_numbers(
        el.find("origin"), ("xyz", "rpy"), 3, f"joint '{name}' <origin>", fail, metres=("xyz",)
    )
    _check_numbers(el.find("axis"), ("xyz",), 3, f"joint '{name}' <axis>", fail)
    jtype = _unless_unbounded(el, name, jtype, path, warnings)
    _check_limit(el, name, jtype, fail, path, warnings)
    mimic = el.find("mimic")
    if mimic is not None:
        if not mimic.get("joint"):
            raise fail(f"joint '{name}' <mimic> has no 'joint' attribute", mimic)
        _check_numbers(mimic, ("multiplier", "offset"), 1, f"joint '{name}' <mimic>", fail)
    return name, parent, child, el


def _joint_type(el: Any, name: str, fail: Fail) -> str:
    """The joint's type, one of :data:`JOINT_TYPES`."""
    jtype = el.get("type")
    if jtype not in JOINT_TYPES:
        what = f"type '{jtype}'" if jtype else "no 'type'"
        raise fail(
            f"joint '{name}' has {what}; valid: {', '.join(JOINT_TYPES)}"
            + (did_you_mean(jtype, JOINT_TYPES) if jtype else ""),
            el,
        )
    return str(jtype)


def _joint_link(el: Any, name: str, role: str, link_lines: Mapping[str, int], fail: Fail) -> str:
    """The link the joint's <parent> or <child> (``role``) names, a link of the robot."""
    sub = el.find(role)
    link = sub.get("link") if sub is not None else None
    if not link:
        raise fail(f"joint '{name}' has no <{role} link='...'/>", el)
    if link not in link_lines:
        raise fail(
            f"joint '{name}' refers to unknown {role} link '{link}'"
            + did_you_mean(link, link_lines),
            sub,
        )
    return str(link)


def _check_colors(root: Any, path: str, fail: Fail, warnings: list[Diagnostic] | None) -> None:
    """Material colours (top-level and of visual elements) are four finite numbers; with
    ``warnings``, one that is not is removed and reported there, else ``fail`` raises."""

    def ignored(msg: str, el: Any) -> UrdfError:
        return _ColorIgnored(msg, path=path, line=getattr(el, "sourceline", None))

    if warnings is not None:
        fail = ignored
    colors = [
        (m.find("color"), f"material '{m.get('name')}' <color>") for m in root.findall("material")
    ]
    for link in root.findall("link"):
        for material in link.findall("visual/material"):
            colors.append(
                (material.find("color"), f"link '{link.get('name')}' <visual> <material> <color>")
            )
    for color, what in colors:
        if color is None or color.get("rgba") is None:
            continue
        try:
            _check_numbers(color, ("rgba",), 4, what, fail)
        except _ColorIgnored as e:
            color.getparent().remove(color)
            if warnings is not None:
                message = f"{e.message}; the colour is ignored (it only draws the robot)"
                warnings.append(
                    Diagnostic(
                        e.path or "", e.line, None, RULE_COLOR_IGNORED, Severity.WARNING, message
                    )
                )


def _named_lines(root: Any, tag: str, fail: Fail) -> dict[str, int]:
    """The line of every ``<tag>`` child of ``root`` by name; each has a unique name."""
    lines: dict[str, int] = {}
    for el in root.findall(tag):
        name = el.get("name")
        if name is None:
            raise fail(f"<{tag}> has no 'name' attribute", el)
        if not name.strip():
            raise fail(f"<{tag}> has an empty name (name='{name}')", el)
        if name in lines:
            first, again = lines[name], el.sourceline or 0
            if first and again:
                where = f" (first on line {first})"
            elif first or again:  # a xacro: one written in the file, one by a macro or include
                where = f" (on line {first or again}, and again by a xacro macro or include)"
            else:
                where = ""
            raise fail(f"{tag} '{name}' is defined twice{where}", el)
        lines[name] = el.sourceline or 0
    return lines


def _unless_unbounded(
    el: Any, name: str, jtype: str, path: str, warnings: list[Diagnostic] | None
) -> str:
    """The joint's type as read: with ``warnings``, a ``<limit>`` lower or upper that is
    finite but beyond ±MAX_NUMBER (``±1e16``: how exporters write "no limit") is dropped with
    a warning there. A revolute joint is then continuous: such a limit bounds nothing, and
    sampling or planning between ±1e16 rad is meaningless (a double there cannot tell angles
    2 rad apart). A fixed or continuous joint has no position limits to begin with."""
    limit = el.find("limit")
    if warnings is None or jtype in ("prismatic", "floating", "planar") or limit is None:
        return jtype
    huge = []
    for attr in ("lower", "upper"):
        raw = limit.get(attr)
        if raw is None:
            continue
        try:
            v = float(raw)
        except ValueError:
            return jtype  # not a number: _check_limit says so
        if math.isfinite(v) and bound_reason(v) is not None:
            huge.append(f"{attr}='{raw.strip()}'")
    if not huge:
        return jtype
    for attr in ("lower", "upper"):
        limit.attrib.pop(attr, None)
    if jtype == "revolute":
        el.set("type", "continuous")
        what = "so no limit at all; the joint is read as continuous (it turns freely)"
    else:
        what = f"ignored (a {jtype} joint has no position limits)"
    message = f"{jtype} joint '{name}' <limit> {' '.join(huge)}: beyond ±{MAX_NUMBER:g}, {what}"
    line = getattr(limit, "sourceline", None)
    warnings.append(Diagnostic(path, line, None, RULE_UNBOUNDED_LIMIT, Severity.WARNING, message))
    return "continuous" if jtype == "revolute" else jtype


def _check_limit(
    el: Any, name: str, jtype: str, fail: Fail, path: str, warnings: list[Diagnostic] | None
) -> None:
    """Limit numbers are finite; a revolute or prismatic joint has ``lower <= upper``. With
    ``warnings``, a lower above the upper is a warning there: the robot is read (ROS reads it;
    a joint no c-space uses never needs a position between them), and a c-space that holds
    the joint is an error where it names it (:meth:`KinematicModel.cspace_reason`)."""
    limit = el.find("limit")
    what = f"joint '{name}' <limit>"
    ends = ("lower", "upper") if jtype == "prismatic" else ()
    _check_numbers(limit, ("lower", "upper", "velocity", "effort"), 1, what, fail, metres=ends)
    if limit is None or jtype not in ("revolute", "prismatic"):
        return
    lower, upper = limit.get("lower"), limit.get("upper")
    if lower is None or upper is None or float(lower) <= float(upper):
        return
    message = f"{what} lower={lower.strip()} is above upper={upper.strip()}"
    if warnings is None:
        raise fail(message, limit)
    line = getattr(limit, "sourceline", None)
    message += ": no position fits; read as written, an error in a c-space"
    warnings.append(Diagnostic(path, line, None, RULE_REVERSED_LIMIT, Severity.WARNING, message))


def _check_is_tree(
    edges: list[tuple[str, str, str, Any]],
    joint_lines: Mapping[str, int],
    fail: Fail,
) -> None:
    """Each link is the child of at most one joint, and parent links never loop back."""
    from ..util.graph import find_cycle, show_path

    parent_of: dict[str, tuple[str, str]] = {}  # child link -> (joint, parent link)
    element: dict[str, Any] = {}
    for joint, parent, child, el in edges:
        element[joint] = el
        if parent == child:
            raise fail(f"joint '{joint}' has link '{child}' as both parent and child", el)
        if child in parent_of:
            first = parent_of[child][0]
            raise fail(
                f"link '{child}' is the child of two joints, '{first}' (line "
                f"{joint_lines.get(first)}) and '{joint}'; a URDF must be a tree",
                el,
            )
        parent_of[child] = (joint, parent)
    cycle = find_cycle(parent_of, lambda link: [parent_of[link][1]] if link in parent_of else [])
    if cycle is not None:
        joints = [parent_of[link][0] for link in cycle[:-1]]
        raise fail(
            f"the joints form a cycle ({show_path(list(reversed(cycle)))}, through joints "
            f"{show_path(list(reversed(joints)))}); a URDF must be a tree",
            element[joints[-1]],
        )


#: Numbers each geometry needs: element -> ((attribute, count, required), ...).
_GEOMETRY: dict[str, tuple[tuple[str, tuple[int, ...], bool], ...]] = {
    "box": (("size", (3,), True),),
    "cylinder": (("radius", (1,), True), ("length", (1,), True)),
    "capsule": (("radius", (1,), True), ("length", (1,), True)),
    "sphere": (("radius", (1,), True),),
    "mesh": (("scale", (3, 1), False),),
}


def _check_geometry(link: Any, fail: Fail) -> None:
    """Visual and collision shapes have the numbers their type needs (finite, not negative)."""
    name = link.get("name")
    for kind in ("visual", "collision"):
        for item in link.findall(kind):
            _check_numbers(
                item.find("origin"),
                ("xyz", "rpy"),
                3,
                f"link '{name}' <{kind}>",
                fail,
                metres=("xyz",),
            )
            geometry = item.find("geometry")
            if geometry is None:
                raise fail(f"link '{name}' <{kind}> has no <geometry>", item)
            shapes = [g for g in geometry if isinstance(g.tag, str)]
            if not shapes or shapes[0].tag not in URDF_GEOMETRIES:
                held = f"<{shapes[0].tag}>" if shapes else "nothing"
                raise fail(
                    f"link '{name}' <{kind}> <geometry> holds {held}; a URDF geometry is one of "
                    f"{', '.join(f'<{g}>' for g in URDF_GEOMETRIES)}",
                    shapes[0] if shapes else geometry,
                )
            for shape in shapes:
                for attr, counts, required in _GEOMETRY.get(shape.tag, ()):
                    what = f"link '{name}' <{kind}> <{shape.tag}>"
                    raw = shape.get(attr)
                    if raw is None:
                        if required:
                            raise fail(f"{what} has no '{attr}' attribute", shape)
                        continue
                    lengths = (attr,) if shape.tag != "mesh" else ()
                    _check_numbers(shape, (attr,), counts, what, fail, metres=lengths)
                    if shape.tag != "mesh" and any(float(x) < 0 for x in raw.split()):
                        raise fail(f"{what} {attr}='{raw}' must not be negative", shape)


def _check_other_numbers(root: Any, fail: Fail) -> None:
    """The numbers of :data:`_OTHER_NUMBERS` (inertia, colours, dynamics, ...)."""
    for tag, child, attrs, count in _OTHER_NUMBERS:
        for el in root.findall(tag):
            for sub in el.findall(child):
                what = f"{tag} '{el.get('name')}' <{child.replace('/', '> <')}>"
                _check_numbers(sub, attrs, count, what, fail, metres=("xyz",))


def _check_numbers(
    el: Any,
    attrs: tuple[str, ...],
    count: int | tuple[int, ...],
    what: str,
    fail: Fail,
    *,
    metres: tuple[str, ...] = (),
) -> None:
    """Each attribute present holds ``count`` usable numbers (one of the counts of a tuple):
    finite and within the bounds of :mod:`xrdf_tools.util.numbers` (the attributes in
    ``metres`` are lengths or coordinates)."""
    if el is None:
        return
    counts = (count,) if isinstance(count, int) else count
    for attr in attrs:
        raw = el.get(attr)
        if raw is None:
            continue
        parts = raw.split()
        shown = shown_text(raw)
        try:
            values = [float(x) for x in parts]
        except ValueError:
            kind = "a number" if counts == (1,) else "a list of numbers"
            raise fail(f"{what} {attr}='{shown}' is not {kind}", el) from None
        if len(parts) not in counts:
            n = " or ".join("a number" if c == 1 else f"{c} numbers" for c in counts)
            raise fail(f"{what} {attr}='{shown}' must be {n}", el)
        for v in values:
            reason = bound_reason(v, metres=attr in metres)
            if reason is not None:
                raise fail(f"{what} {attr}='{shown}': {reason}", el)
