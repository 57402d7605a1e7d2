"""Read a URDF, without meshes, with errors that name the file and line.

The XML is parsed strictly first (:mod:`xrdf_tools.util.safe_xml`: no entities, no network),
then checked for what yourdfpy would crash on or silently get wrong: missing names, unknown
joint types, duplicate links or joints, joints that refer to unknown links, numbers that do not
parse. The checked tree is the :class:`~xrdf_tools.robot.core.Robot`; yourdfpy gets it only
when geometry is read (:func:`xrdf_tools.robot.yourdfpy_build.build_yourdfpy`). Every failure
is a :class:`UrdfError` whose one-line message starts with ``path:line:`` when the line is
known (for an expanded xacro, the line of the element in the xacro file when it is written
there literally).

:class:`JointInfo`, :func:`joints_of` and :func:`links_of` give a plain, typed view of a loaded
URDF for the kinematics, the linter and the converter. yourdfpy is imported lazily so that
commands which never read a URDF start fast.
"""

from __future__ import annotations

import math
import os
import re
from collections.abc import Mapping
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal
from xml.sax.saxutils import escape

from ..util.errors import UrdfError, UrdfReadError
from ..util.safe_xml import XmlSyntaxError
from ..util.textpos import attribute_line, line_col
from .urdf_check import JOINT_TYPES, check_urdf_tree
from .urdf_joints import MOVABLE_TYPES, JointInfo, joint_info
from .urdfdom_refusals import urdfdom_refusals
from .xacro_places import template_offset
from .xml_prefixes import drop_prefixed_names, undeclared_prefix_warning

if TYPE_CHECKING:
    import yourdfpy

    from .core import Robot
    from .packages import PackagePaths


__all__ = [
    "JOINT_TYPES",
    "MOVABLE_TYPES",
    "JointInfo",
    "joint_info",
    "joints_of",
    "links_of",
    "load_urdf",
    "parse_robot",
    "parse_urdf_string",
    "read_robot",
    "relocate_expansion",
    "source_line",
    "urdf_path",
]


def links_of(urdf: Robot | yourdfpy.URDF) -> list[str]:
    """Link names in document order."""
    from .core import as_robot

    return list(as_robot(urdf).links)


def root_link(urdf: Robot | yourdfpy.URDF) -> str:
    """The one link that is no joint's child; :class:`UrdfError` when there is not exactly one."""
    from .core import as_robot

    return as_robot(urdf).root_link()


def joints_of(urdf: Robot | yourdfpy.URDF) -> dict[str, JointInfo]:
    """Every ``<joint>`` of the robot as :class:`JointInfo`, keyed by name, in document order."""
    from .core import as_robot

    return dict(as_robot(urdf).joints)


# --------------------------------------------------------------------------------------------
# Where a loaded URDF came from (fields of its :class:`~xrdf_tools.robot.core.Robot`)
# --------------------------------------------------------------------------------------------
def urdf_path(urdf: Robot | yourdfpy.URDF) -> str:
    """The path a URDF was loaded from by this module, or ``"<urdf>"``."""
    from .core import as_robot

    return as_robot(urdf).path


def urdf_text(urdf: Robot | yourdfpy.URDF) -> str | None:
    """The text a URDF was parsed from by this module (an expanded xacro: the expansion)."""
    from .core import as_robot

    return as_robot(urdf).text


def source_line(
    urdf: Robot | yourdfpy.URDF, kind: Literal["link", "joint"], name: str
) -> int | None:
    """Line of the ``<link>``/``<joint>`` element named ``name`` (None if unknown)."""
    from .core import as_robot

    return as_robot(urdf).source_line(kind, name)


# --------------------------------------------------------------------------------------------
# Loading
# --------------------------------------------------------------------------------------------
def load_urdf(
    path: str | os.PathLike[str],
    *,
    package_paths: PackagePaths | None = None,
    build_scene_graph: bool = False,
) -> yourdfpy.URDF:
    """Load a URDF file without loading any mesh: the yourdfpy object of :func:`read_robot`
    (which carries its :class:`~xrdf_tools.robot.core.Robot`, see
    :func:`xrdf_tools.robot.core.as_robot`).
    """
    return read_robot(path, package_paths=package_paths, build_scene_graph=build_scene_graph).urdf


def read_robot(
    path: str | os.PathLike[str],
    *,
    package_paths: PackagePaths | None = None,
    build_scene_graph: bool = False,
    data: bytes | None = None,
) -> Robot:
    """Load a URDF file without loading any mesh, as a :class:`~xrdf_tools.robot.core.Robot`.

    ``package_paths`` (``{"pkg": "/dir"}``) resolves ``package://pkg/...`` mesh URIs for
    whoever loads meshes later (see :func:`xrdf_tools.robot.yourdfpy_build.make_filename_handler`);
    meshes are never read here.
    ``build_scene_graph`` builds yourdfpy's scene graph (needed only for yourdfpy's own
    ``get_transform``; :mod:`xrdf_tools.robot.kinematics` does not need it). ``data``: the file's
    bytes when the caller has already read them (:func:`read_urdf_bytes`): not read again.

    Raises :class:`UrdfError` (one line, with the path, and the line when known).
    """
    p = os.fspath(path)
    if data is None:
        data = read_urdf_bytes(p)
    return _parse_bytes(data, p, package_paths=package_paths, build_scene_graph=build_scene_graph)


def read_urdf_bytes(path: str | os.PathLike[str]) -> bytes:
    """The bytes of a URDF file, read through :func:`xrdf_tools.util.fileio.read_input_bytes`
    (regular files only, size limit); any failure is a one-line :class:`UrdfReadError` (the file
    cannot be used at all: a usage error, not a finding about the robot)."""
    from ..util.fileio import read_input_bytes

    return read_input_bytes(path, what="URDF file", error=UrdfReadError)


_ENCODING_DECL = re.compile(r"^(\s*<\?xml[^>]*?)\s+encoding\s*=\s*(['\"])[^'\"]*\2", re.I)


def parse_urdf_string(
    text: str,
    path: str = "<string>",
    *,
    package_paths: PackagePaths | None = None,
    build_scene_graph: bool = False,
) -> yourdfpy.URDF:
    """Parse URDF text (e.g. expanded xacro output); ``path`` is used in messages and to
    resolve relative mesh paths. See :func:`load_urdf`."""
    return parse_robot(
        text, path, package_paths=package_paths, build_scene_graph=build_scene_graph
    ).urdf


def parse_robot(
    text: str,
    path: str = "<string>",
    *,
    package_paths: PackagePaths | None = None,
    build_scene_graph: bool = False,
    expanded: bool = False,
    xacro_args: Mapping[str, str] | None = None,
) -> Robot:
    """:func:`parse_urdf_string` as a :class:`~xrdf_tools.robot.core.Robot` (``expanded``: the
    text is the expansion of the xacro file ``path`` with ``xacro_args``)."""
    text = _ENCODING_DECL.sub(r"\1", text, count=1)
    return _parse_bytes(
        text.encode("utf-8"),
        path,
        package_paths=package_paths,
        build_scene_graph=build_scene_graph,
        expanded=expanded,
        xacro_args=xacro_args,
    )


#: How a USD stage begins: ASCII (``.usda``), binary crate (``.usdc``, often ``.usd``), or a
#: zip package (``.usdz``, told by its suffix: a zip is no XML either).
_USD_STARTS = (b"#usda ", b"PXR-USDC")


def _usd_hint(data: bytes, path: str) -> str:
    """The message for a USD stage given where the URDF goes (Isaac Sim's robots), else ''."""
    if not (data.startswith(_USD_STARTS) or path.lower().endswith(".usdz")):
        return ""
    return (
        "a USD stage (Isaac Sim), not a URDF: give the robot's URDF (Isaac Sim's USD to URDF "
        "Exporter, extension isaacsim.asset.exporter.urdf, writes one)"
    )


def _yaml_robot_hint(data: bytes, path: str) -> str:
    """What a file that is no XML is, when it is one of the YAML files given beside a URDF
    (a cuRobo robot config, an XRDF): the message that says which file goes where; else ''."""
    import yaml

    try:
        doc = yaml.safe_load(data)
    except (yaml.YAMLError, ValueError, RecursionError):
        return ""
    if not isinstance(doc, dict):
        return ""
    cfg = doc.get("robot_cfg")
    if isinstance(cfg, dict):
        kin = cfg.get("kinematics")
        urdf = kin.get("urdf_path") if isinstance(kin, dict) else None
        where = (
            f" (its urdf_path '{urdf}' is relative to cuRobo's asset directory)"
            if isinstance(urdf, str)
            else ""
        )
        return (
            "a cuRobo robot config, not a URDF: give the robot's URDF here and read the "
            f"config with --curobo{where}, e.g. xrdf convert ROBOT.urdf --curobo "
            f"{os.path.basename(path)}"
        )
    if doc.get("format") == "xrdf":
        return "an XRDF file, not a URDF: give the robot's URDF (or xacro) here"
    return ""


def _parse_bytes(
    data: bytes,
    path: str,
    *,
    package_paths: PackagePaths | None,
    build_scene_graph: bool,
    expanded: bool = False,
    xacro_args: Mapping[str, str] | None = None,
) -> Robot:
    from lxml import etree

    from ..util.frozen import FrozenMap
    from ..util.safe_xml import parse_xml
    from .core import Robot
    from .link_geometry import capsules_as_cylinders

    undeclared: list[XmlSyntaxError] = []
    try:
        root = parse_xml(data, remove_blank_text=True, undeclared_prefixes=undeclared)
    except XmlSyntaxError as e:
        hint = _usd_hint(data, path) or _yaml_robot_hint(data, path)
        if hint:
            raise UrdfError(hint, path=path, line=1, col=1) from None
        raise UrdfError(f"malformed XML: {e.reason}", path=path, line=e.line, col=e.col) from None
    if root is None:
        raise UrdfError("the file is empty", path=path, line=1)

    etree.strip_tags(root, etree.Comment)
    source = _xacro_source(path) if expanded else ""
    if expanded:
        relocate_expansion(root, source)
    warnings = [undeclared_prefix_warning(e, path) for e in undeclared]
    if undeclared:
        drop_prefixed_names(root)
    text = data.decode("utf-8", errors="replace")
    try:
        link_lines, joint_lines = check_urdf_tree(root, path, warnings)
        warnings.extend(urdfdom_refusals(root, path))
    except UrdfError as e:
        if expanded and e.line is None:  # made by a macro: where the value it quotes is written
            e.line = _quoted_value_line(source, e.message)
        elif not expanded and e.line is not None:
            e.line = attribute_line(text.splitlines(), e.line, e.message)
        raise
    if expanded:  # 0: not written literally in the xacro file (see relocate_expansion)
        link_lines = {k: v for k, v in link_lines.items() if v}
        joint_lines = {k: v for k, v in joint_lines.items() if v}
    elif warnings:
        lines = text.splitlines()
        warnings = [
            replace(w, line=attribute_line(lines, w.line, w.message)) if w.line else w
            for w in warnings
        ]
    etree.cleanup_namespaces(root)
    capsules = capsules_as_cylinders(root)  # yourdfpy knows no <capsule>

    return Robot(
        document=root,
        path=path,
        text=text,
        expanded=expanded,
        link_lines=FrozenMap(link_lines),
        joint_lines=FrozenMap(joint_lines),
        package_paths=FrozenMap(package_paths or {}),
        xacro_args=FrozenMap(xacro_args or {}),
        capsules=capsules,
        build_scene_graph=build_scene_graph,
        warnings=tuple(warnings),
    )


def _xacro_source(path: str) -> str:
    """The text of the xacro file an expansion came from ("" when it cannot be read again)."""
    try:
        return Path(path).read_text(encoding="utf-8", errors="replace")
    except OSError:
        return ""


def _line_of(source: str, at: int) -> int | None:
    return line_col(source, at)[0] if at >= 0 else None


def _quoted_value_line(source: str, message: str) -> int | None:
    """The line of the xacro text that writes what ``message`` quotes: an attribute it names
    with its value (``upper=''``), else a value (``'name'``), the last quoted first (the value
    at fault: "joint 'j' refers to unknown link 'x'"), else a part of a quoted name (a
    macro-made ``upper_joint``: the call that writes ``name="upper"``). Values are looked for
    as the text writes them too (``&amp;`` for ``&``), and a missing attribute (``'name'``) as
    one left empty (``name=""``: xacro drops it)."""
    message = message.split("; did you mean ", 1)[0]  # a suggestion is not what is written
    if (twice := _DEFINED_TWICE.match(message)) is not None:  # only where it is defined
        tag, name = twice.groups()
        written = {name, escape(name, {'"': "&quot;", "'": "&apos;"})}
        found = [source.find(f"<{tag} name={q}{v}{q}") for v in sorted(written) for q in "\"'"]
        at = _line_of(source, min((i for i in found if i >= 0), default=-1))
        if at is None:  # made by macros: the second call that writes its name
            at = _second_call_line(source, name)
        # a number written another way: name="1e308" makes 1e+308 and 1e+308_joint
        return at if at is not None else _numeric_value_line(source, [name, *name.split("_")])
    wanted = [(f"{attr}=", value) for attr, value in _ATTRIBUTE.findall(message)]
    values = re.findall(r"'([^'\n]+)'", message)
    wanted += [("=", value) for value in reversed(values)]
    # an attribute the message misses may be one the text leaves empty (xacro drops it)
    wanted += [(f"{value}=", "") for value in reversed(values) if value.isidentifier()]
    for value in values:
        pieces = {p for p in re.split(r"[\W_]+", value) if len(p) > 1} - {value}
        wanted += [("=", p) for p in sorted(pieces, key=lambda p: (-len(p), p))]
    for prefix, value in wanted:
        written = {value, escape(value, {'"': "&quot;", "'": "&apos;"})}
        found = [source.find(f"{prefix}{q}{v}{q}") for v in sorted(written) for q in "\"'"]
        line = _line_of(source, min((i for i in found if i >= 0), default=-1))
        if line is not None:
            return line
    return _numeric_value_line(source, list(reversed(values)))


def template_line(source: str, message: str) -> int | None:
    """For "link/joint 'X' is defined twice" that no file writes as it is: the line of the
    element of ``source`` whose name template (``name="${1e308}_joint"``, ``"${nan}"``) can
    make ``X``. The last resort, after every file was searched for the name itself."""
    twice = _DEFINED_TWICE.match(message)
    if twice is None:
        return None
    offset = template_offset(source, twice.group(1), twice.group(2))
    return None if offset is None else _line_of(source, offset)


def _second_call_line(source: str, name: str) -> int | None:
    """Where ``source`` passes ``name`` (or, for a name a macro composes, such as
    ``lower_joint``, its longest part: ``name="lower"``) to a xacro macro call the second time,
    else the first: a link or joint that macros define twice comes from two calls that pass the
    same name, and the second is the one to look at (a pasted line)."""
    parts = {*name.split("_"), *re.split(r"[\W_]+", name)}
    pieces = sorted((p for p in parts if len(p) > 1 and p != name), key=lambda p: (-len(p), p))
    for value in (name, *pieces):
        written = {value, escape(value, {'"': "&quot;", "'": "&apos;"})}
        calls = (rf"<xacro:[^>]*?=\s*([\"'])({re.escape(v)})\1" for v in written)
        starts = sorted(m.start(2) for c in calls for m in re.finditer(c, source))
        if starts:
            return _line_of(source, starts[min(1, len(starts) - 1)])
    return None


def _numeric_value_line(source: str, values: list[str]) -> int | None:
    """The line of the first attribute value in ``source`` that a number of ``values`` is,
    written another way (xacro evaluates ``parent="1e308"`` or ``name="${1e308}"`` and
    writes ``1e+308``)."""
    numbers = [v for v in (_as_number(value) for value in values) if v is not None]
    for number in numbers:
        for m in _QUOTED_VALUE.finditer(source):
            if _as_number(m.group(2)) == number:
                return _line_of(source, m.start())
    return None


def _as_number(text: str) -> float | None:
    """``text`` as a finite number, also when it is a xacro expression of one (``${1e308}``)."""
    text = text.strip()
    if text.startswith("${") and text.endswith("}"):
        text = text[2:-1]
    try:
        value = float(text)
    except ValueError:
        return None
    return value if math.isfinite(value) else None


#: A link or joint defined twice (by macros: the name is quoted where it is used, too).
_DEFINED_TWICE = re.compile(r"^(link|joint) '([^'\n]+)' is defined twice")
#: ``="value"`` or ``='value'`` in a xacro's text.
_QUOTED_VALUE = re.compile(r"=([\"'])([^\"'\n<]*)\1")


#: ``upper=''`` in a message: an attribute and the value it holds.
_ATTRIBUTE = re.compile(r"\b(\w+)='([^'\n]*)'")


def _start_tag(
    source: str, tag: str, key: str, value: str | None = None, taken: set[int] | None = None
) -> int:
    """Where ``source`` first writes ``<tag key="value"`` (any value when None), the attribute
    first, on the tag's line or the next (CAD exporters write one attribute a line), at an offset
    not in ``taken`` (a tag written once defines one element); -1."""
    written = "" if value is None else rf"\s*([\"']){re.escape(value)}\1"
    for found in re.finditer(rf"<{re.escape(tag)}\s+{re.escape(key)}\s*={written}", source):
        if taken is None or found.start() not in taken:
            return found.start()
    return -1


def relocate_expansion(root: Any, source: str) -> None:
    """Give the elements of an expanded xacro the lines of its xacro file's text ``source``.

    The expansion's own lines are not the file's. A top-level element (a URDF's ``<link>``/
    ``<joint>``, an SRDF's ``<group>``/``<group_state>``/``<disable_collisions>``) written
    literally in the file (``<joint name="j1"``, or its first attribute when it has no name)
    takes that line, and so does everything inside it; one that a macro or a ``$(arg)`` made
    has no line (lxml reads 0 as no line), also when the file writes the same tag literally
    for another element (a link the file defines and a macro defines again). The ``<robot>``
    (or the element a wrong file has in its place) takes the line of its tag.
    """
    taken: set[int] = set()
    for el in root:
        line = 0
        first = next(iter(el.attrib.items()), None) if isinstance(el.tag, str) else None
        if first is not None:  # its name, or what it has in place of one
            key, value = ("name", el.get("name")) if el.get("name") else first
            found = _start_tag(source, el.tag, key, value, taken)
            if key != "name" and found < 0:  # a macro wrote the value
                found = _start_tag(source, el.tag, key, None, taken)
            if found >= 0:
                taken.add(found)
            line = _line_of(source, found) or 0
        for node in el.iter():
            node.sourceline = line
    from lxml import etree

    # the <robot> tag, or the one a wrong file has in its place (a lone <link>)
    name = etree.QName(root).localname if isinstance(root.tag, str) else "robot"
    tag = re.search(rf"<(?:\w+:)?{re.escape(name)}[\s/>]", source)
    root.sourceline = (_line_of(source, tag.start()) or 0) if tag else 0
