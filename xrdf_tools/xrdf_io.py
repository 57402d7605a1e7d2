"""Read an XRDF document into the model, and write the model back canonically.

Reading is strict about types (one :class:`SchemaError` with file:line:col for the first
problem) and lenient about what the linter judges (missing ``cspace``, a section spelled for the
other version, unknown keys). Writing is canonical: the section order of the spec, floats always
written as floats that both YAML 1.1 and 1.2 readers parse as floats, stable formatting.
"""

from __future__ import annotations

import json
import math
import os
import re
from collections.abc import Callable, Mapping, Sequence
from typing import Any, TypeVar

from .errors import SchemaError
from .frozen import FrozenMap
from .model import (
    SUPPORTED_VERSIONS,
    AddFrame,
    CollisionSection,
    CSpace,
    GeometryGroup,
    Modifier,
    Orientation,
    RemoveMimicAttributes,
    SelfCollisionSection,
    SetBaseFrame,
    SourceMap,
    Sphere,
    Vec3,
    Xrdf,
    resolve_group,
)
from .yaml_io import (
    YamlDocument,
    YMap,
    YNode,
    YScalar,
    YSeq,
    describe_node,
    load_yaml,
    node_positions,
    parse_yaml,
    raise_on_duplicates,
    to_python,
)

T = TypeVar("T")

TOP_LEVEL_ORDER = (
    "format",
    "format_version",
    "modifiers",
    "default_joint_positions",
    "cspace",
    "tool_frames",
    "collision",
    "world_collision",
    "self_collision",
    "geometry",
)


#: Largest length or coordinate accepted in an XRDF, in metres (sphere centres and radii,
#: buffer distances, added frame positions): far beyond any robot, far below overflow.
MAX_LENGTH = 1e6


class _Reader:
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
        if node is None or (isinstance(node, YScalar) and node.value is None):
            if nullable:
                return None
            raise self.fail(node, f"{what} must be a mapping, not null")
        if not isinstance(node, YMap):
            raise self.fail(node, f"{what} must be a mapping, not {describe(node)}")
        return node

    def sequence(self, node: YNode | None, what: str, *, nullable: bool = True) -> YSeq | None:
        if node is None or (isinstance(node, YScalar) and node.value is None):
            if nullable:
                return None
            raise self.fail(node, f"{what} must be a list, not null")
        if not isinstance(node, YSeq):
            raise self.fail(node, f"{what} must be a list, not {describe(node)}")
        return node

    def string(self, node: YNode | None, what: str) -> str:
        if isinstance(node, YScalar) and isinstance(node.value, str) and node.value != "":
            return node.value
        if (
            isinstance(node, YScalar)
            and isinstance(node.value, (int, float))
            and not isinstance(node.value, bool)
        ):
            # A frame called 1 is legal YAML-wise; keep its text form.
            return str(node.value)
        raise self.fail(node, f"{what} must be a non-empty string, not {describe(node)}")

    def number(self, node: YNode | None, what: str) -> float:
        """A finite number (NaN and infinities reach no consumer: they poison FK and JSON)."""
        if (
            isinstance(node, YScalar)
            and isinstance(node.value, (int, float))
            and not isinstance(node.value, bool)
        ):
            v = float(node.value)
            if not math.isfinite(v):
                raise self.fail(node, f"{what} must be a finite number, not {v}")
            return v
        raise self.fail(node, f"{what} must be a number, not {describe(node)}")

    def length(self, node: YNode | None, what: str) -> float:
        """A number that is a length or coordinate in metres: finite and within
        ±:data:`MAX_LENGTH` (beyond that, squared distances overflow)."""
        v = self.number(node, what)
        if abs(v) > MAX_LENGTH:
            raise self.fail(
                node,
                f"{what} is {v:g}; lengths must be finite and within ±{MAX_LENGTH:g} m",
            )
        return v

    def numbers(
        self, node: YNode | None, what: str, length: int | None = None
    ) -> tuple[float, ...]:
        seq = self.sequence(node, what, nullable=False)
        assert seq is not None
        if length is not None and len(seq) != length:
            raise self.fail(seq, f"{what} must have exactly {length} numbers, found {len(seq)}")
        return tuple(self.number(item, f"{what}[{i}]") for i, item in enumerate(seq))

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


def describe(node: YNode | None) -> str:
    """Human name of a node's type: 'a mapping', 'a list', 'the number 0.1', 'null' …
    (strings escaped and shortened: see :func:`xrdf_tools.yaml_io.describe_node`)."""
    return describe_node(node)


def version_string(node: YNode | None) -> str | None:
    """Normalise ``format_version`` (``1.0``, ``1``, ``"2.0"``) to ``"1.0"``/``"2.0"``."""
    if not isinstance(node, YScalar) or isinstance(node.value, bool) or node.value is None:
        return None
    v = node.value
    try:
        f = float(v)
    except (TypeError, ValueError):
        return str(v)
    return f"{f:.1f}" if f.is_integer() else str(v)


def parse_xrdf(text: str, path: str = "<string>") -> Xrdf:
    """Parse XRDF text into the model (see :func:`xrdf_from_document`)."""
    doc = parse_yaml(text, path)
    raise_on_duplicates(doc)
    return xrdf_from_document(doc)


def load_xrdf(path: str | os.PathLike[str]) -> Xrdf:
    """Read an XRDF file. Raises :class:`XrdfToolsError` subclasses with file:line:col."""
    return xrdf_from_document(load_yaml(path))


def xrdf_from_document(doc: YamlDocument) -> Xrdf:
    r = _Reader(doc.path)
    root = doc.root
    if root is None:
        raise SchemaError(
            "the file is empty; an XRDF needs at least 'format' and 'format_version'",
            path=doc.path,
            line=1,
            col=1,
        )
    if not isinstance(root, YMap):
        raise r.fail(root, f"the top level of an XRDF must be a mapping, not {describe(root)}")

    fmt = root.get("format")
    if fmt is None:
        raise r.fail(root, "missing required key 'format' (expected 'format: xrdf')")
    if not (isinstance(fmt, YScalar) and fmt.value == "xrdf"):
        raise r.fail(fmt, f"'format' must be 'xrdf', not {describe(fmt)}")
    vnode = root.get("format_version")
    if vnode is None:
        raise r.fail(root, "missing required key 'format_version' (1.0 or 2.0)")
    version = version_string(vnode)
    if version not in SUPPORTED_VERSIONS:
        raise r.fail(
            vnode,
            f"unsupported format_version {describe(vnode)}; supported: "
            f"{', '.join(SUPPORTED_VERSIONS)}",
        )

    modifiers = _read_modifiers(r, root.get("modifiers"))
    defaults_node = root.get("default_joint_positions")
    defaults = (
        r.frame_map(defaults_node, "default_joint_positions", r.number)
        if "default_joint_positions" in root
        else None
    )
    if defaults is not None and r.mapping(defaults_node, "default_joint_positions") is None:
        defaults = FrozenMap()
    cspace = _read_cspace(r, root.get("cspace")) if "cspace" in root else None
    tool_frames = (
        r.strings(root.get("tool_frames"), "tool_frames") if "tool_frames" in root else None
    )
    geometry = _read_geometry(r, root.get("geometry")) if "geometry" in root else None

    if "collision" in root and "world_collision" in root:
        raise r.fail(
            root.key_node("world_collision"),
            "both 'collision' and 'world_collision' are present; use 'collision' in 1.0 and "
            "'world_collision' in 2.0",
        )
    wkey = "collision" if "collision" in root else "world_collision"
    world = _read_world(r, root.get(wkey), wkey, geometry) if wkey in root else None
    self_c = (
        _read_self(r, root.get("self_collision"), geometry) if "self_collision" in root else None
    )
    extra = FrozenMap((str(k), to_python(v)) for k, v in root.items() if k not in TOP_LEVEL_ORDER)
    return Xrdf(
        format_version=version,
        cspace=cspace,
        modifiers=modifiers,
        default_joint_positions=defaults,
        tool_frames=tool_frames,
        world_collision=world,
        self_collision=self_c,
        geometry=geometry,
        extra=extra,
        source=SourceMap(doc.path, FrozenMap(node_positions(root))),
    )


def _read_vec3(r: _Reader, node: YNode | None, what: str) -> Vec3:
    """A position in metres (see :meth:`_Reader.length`)."""
    seq = r.sequence(node, what, nullable=False)
    assert seq is not None
    if len(seq) != 3:
        raise r.fail(seq, f"{what} must have exactly 3 numbers, found {len(seq)}")
    x, y, z = (r.length(item, f"{what}[{i}]") for i, item in enumerate(seq))
    return (x, y, z)


def _read_orientation(r: _Reader, node: YNode | None, what: str) -> Orientation:
    m = r.mapping(node, what)
    if m is None:
        return Orientation.identity()
    if "quaternion" in m:
        return Orientation("quaternion", r.numbers(m.get("quaternion"), f"{what}.quaternion", 4))
    if "euler_rpy" in m:
        return Orientation("euler_rpy", r.numbers(m.get("euler_rpy"), f"{what}.euler_rpy", 3))
    if "w" not in m or "xyz" not in m:
        raise r.fail(
            m,
            f"{what} needs 'w' and 'xyz' ({{w: 1.0, xyz: [0.0, 0.0, 0.0]}}), or 'quaternion' "
            "[w, x, y, z], or 'euler_rpy' [r, p, y]",
        )
    w = r.number(m.get("w"), f"{what}.w")
    xyz = r.numbers(m.get("xyz"), f"{what}.xyz", 3)
    return Orientation("w_xyz", (w, *xyz))


def _required(r: _Reader, m: YMap, key: str, what: str) -> YNode:
    node = m.get(key)
    if node is None:
        raise r.fail(m, f"{what} is missing required key '{key}'")
    return node


def _read_modifiers(r: _Reader, node: YNode | None) -> tuple[Modifier, ...]:
    seq = r.sequence(node, "modifiers")
    if seq is None:
        return ()
    out: list[Modifier] = []
    for i, item in enumerate(seq):
        what = f"modifiers[{i}]"
        m = r.mapping(item, what, nullable=False)
        assert m is not None
        if len(m.pairs) != 1:
            raise r.fail(
                m,
                f"{what} must have exactly one key (add_frame, set_base_frame or "
                f"remove_mimic_attributes), found {len(m.pairs)}",
            )
        key, value = m.items()[0]
        if key == "set_base_frame":
            out.append(SetBaseFrame(r.string(value, f"{what}.set_base_frame")))
        elif key == "add_frame":
            a = r.mapping(value, f"{what}.add_frame", nullable=False)
            assert a is not None
            w = f"{what}.add_frame"
            ft = r.mapping(
                _required(r, a, "fixed_transform", w), f"{w}.fixed_transform", nullable=False
            )
            assert ft is not None
            jt = a.get("joint_type")
            out.append(
                AddFrame(
                    frame_name=r.string(_required(r, a, "frame_name", w), f"{w}.frame_name"),
                    parent_frame_name=r.string(
                        _required(r, a, "parent_frame_name", w), f"{w}.parent_frame_name"
                    ),
                    joint_name=r.string(_required(r, a, "joint_name", w), f"{w}.joint_name"),
                    joint_type=r.string(jt, f"{w}.joint_type") if jt is not None else "FIXED",
                    position=_read_vec3(
                        r,
                        _required(r, ft, "position", f"{w}.fixed_transform"),
                        f"{w}.fixed_transform.position",
                    ),
                    orientation=_read_orientation(
                        r, ft.get("orientation"), f"{w}.fixed_transform.orientation"
                    ),
                )
            )
        elif key == "remove_mimic_attributes":
            w = f"{what}.remove_mimic_attributes"
            a = r.mapping(value, w, nullable=False)
            assert a is not None
            pl = a.get("position_limits")
            limits = None
            if pl is not None and not (isinstance(pl, YScalar) and pl.value is None):
                lo, hi = r.numbers(pl, f"{w}.position_limits", 2)
                limits = (lo, hi)
            vl = a.get("velocity_limits") if "velocity_limits" in a else a.get("velocity_limit")
            velocity = None
            if vl is not None and not (isinstance(vl, YScalar) and vl.value is None):
                velocity = r.number(vl, f"{w}.velocity_limits")
            out.append(
                RemoveMimicAttributes(
                    r.string(_required(r, a, "joint_name", w), f"{w}.joint_name"), limits, velocity
                )
            )
        else:
            raise r.fail(
                m.pairs[0][0],
                f"unknown modifier '{key}'; valid: add_frame, set_base_frame, "
                "remove_mimic_attributes",
            )
    return tuple(out)


def _read_cspace(r: _Reader, node: YNode | None) -> CSpace:
    m = r.mapping(node, "cspace", nullable=False)
    assert m is not None
    names = r.strings(
        _required(r, m, "joint_names", "cspace")
        if "joint_names" not in m
        else m.get("joint_names"),
        "cspace.joint_names",
    )
    _no_repeats(r, m.get("joint_names"), names)

    def limits(key: str) -> tuple[float, ...]:
        n = m.get(key)
        if key not in m:
            raise r.fail(m, f"cspace is missing required key '{key}'")
        if isinstance(n, YScalar) and n.value is None:
            return ()
        return r.numbers(n, f"cspace.{key}")

    return CSpace(names, limits("acceleration_limits"), limits("jerk_limits"))


def _no_repeats(r: _Reader, node: YNode | None, names: tuple[str, ...]) -> None:
    """A c-space names each joint once (a repeat makes the configuration vector ambiguous)."""
    seen: set[str] = set()
    for i, n in enumerate(names):
        if n in seen:
            item = node.items[i] if isinstance(node, YSeq) else node
            raise r.fail(item, f"cspace.joint_names[{i}]: joint '{n}' is listed twice")
        seen.add(n)


def _read_spheres(r: _Reader, node: YNode, what: str) -> tuple[Sphere, ...]:
    seq = r.sequence(node, what)
    if seq is None:
        return ()
    out = []
    for i, item in enumerate(seq):
        w = f"{what}[{i}]"
        m = r.mapping(item, w, nullable=False)
        assert m is not None
        center = _read_vec3(r, _required(r, m, "center", f"sphere {w}"), f"{w}.center")
        radius = r.length(_required(r, m, "radius", f"sphere {w}"), f"{w}.radius")
        out.append(Sphere(center, radius))
    return tuple(out)


def _read_geometry(r: _Reader, node: YNode | None) -> FrozenMap[str, GeometryGroup]:
    def group(n: YNode, what: str) -> GeometryGroup:
        m = r.mapping(n, what)
        if m is None:
            return GeometryGroup()
        spheres = r.frame_map(
            m.get("spheres"), f"{what}.spheres", lambda v, w: _read_spheres(r, v, w)
        )
        clone_node = m.get("clone")
        if isinstance(clone_node, YScalar) and clone_node.value is not None:
            raise r.fail(
                clone_node,
                f"{what}.clone must be a list of group names, not {describe(clone_node)}",
            )
        clone = r.strings(clone_node, f"{what}.clone")
        return GeometryGroup(spheres, clone)

    return r.frame_map(node, "geometry", group)


def _group_name(r: _Reader, m: YMap, what: str) -> str:
    g = _required(r, m, "geometry", what)
    if isinstance(g, YSeq) and len(g) == 1:
        return r.string(g.items[0], f"{what}.geometry[0]")
    return r.string(g, f"{what}.geometry")


def _read_buffers(
    r: _Reader,
    node: YNode | None,
    what: str,
    geometry: Mapping[str, GeometryGroup] | None,
    group: str,
) -> FrozenMap[str, float]:
    if isinstance(node, YScalar) and node.value is not None:
        # cuRobo accepts a single number for every frame: expand it over the group's frames.
        value = r.length(node, what)
        frames: Sequence[str] = ()
        if geometry and group in geometry:
            try:
                frames = list(resolve_group(geometry, group))
            except SchemaError:
                frames = []
        return FrozenMap((f, value) for f in frames)
    return r.frame_map(node, what, r.length)


def _read_world(
    r: _Reader, node: YNode | None, key: str, geometry: Mapping[str, GeometryGroup] | None
) -> CollisionSection:
    m = r.mapping(node, key, nullable=False)
    assert m is not None
    group = _group_name(r, m, key)
    return CollisionSection(
        group, _read_buffers(r, m.get("buffer_distance"), f"{key}.buffer_distance", geometry, group)
    )


def _read_self(
    r: _Reader, node: YNode | None, geometry: Mapping[str, GeometryGroup] | None
) -> SelfCollisionSection:
    m = r.mapping(node, "self_collision", nullable=False)
    assert m is not None
    group = _group_name(r, m, "self_collision")
    ignore_node = m.get("ignore")
    if isinstance(ignore_node, YSeq) and len(ignore_node) == 0:
        ignore_node = None  # `ignore: []` as cuRobo's writer emits it means "nothing masked"

    def frames(v: YNode, w: str) -> tuple[str, ...]:
        if isinstance(v, YScalar) and v.value is not None:
            raise r.fail(v, f"{w} must be a list of frame names, not {describe(v)}")
        return r.strings(v, w)

    return SelfCollisionSection(
        group,
        _read_buffers(
            r, m.get("buffer_distance"), "self_collision.buffer_distance", geometry, group
        ),
        r.frame_map(ignore_node, "self_collision.ignore", frames),
    )


# --- writing -----------------------------------------------------------------------------------

_PLAIN_RE = re.compile(r"^[A-Za-z_][A-Za-z0-9_./\-]*$")
_YAML11_SPECIAL = re.compile(
    r"^(?:y|Y|yes|Yes|YES|n|N|no|No|NO|true|True|TRUE|false|False|FALSE|on|On|ON|off|Off|OFF"
    r"|null|Null|NULL|~|\.inf|\.Inf|\.INF|\.nan|\.NaN|\.NAN)$"
)


def format_float(value: float) -> str:
    """A float that YAML 1.1 (PyYAML, cuRobo) and 1.2 both read back as the same float.

    ``0`` → ``0.0``; ``1e-05`` → ``1.0e-05``; infinities and NaN in YAML spelling.
    """
    v = float(value)
    if math.isnan(v):
        return ".nan"
    if math.isinf(v):
        return ".inf" if v > 0 else "-.inf"
    if v == 0.0:
        v = 0.0  # no negative zero in output
    text = repr(v)
    if "e" in text:
        mant, exp = text.split("e")
        if "." not in mant:
            mant += ".0"
        sign = exp[0] if exp[0] in "+-" else "+"
        digits = exp.lstrip("+-")
        text = f"{mant}e{sign}{digits}"
    elif "." not in text:
        text += ".0"
    return text


def format_str(value: str) -> str:
    """A string scalar: plain when safe for YAML 1.1 and 1.2 readers, double-quoted otherwise."""
    if _PLAIN_RE.match(value) and not _YAML11_SPECIAL.match(value):
        return value
    return json.dumps(value, ensure_ascii=False)


def _scalar(value: Any) -> str:
    if value is None:
        return "null"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return format_float(value)
    return format_str(str(value))


def _flow(values: Sequence[Any]) -> str:
    return "[" + ", ".join(_scalar(v) for v in values) + "]"


def _plain_block(value: Any, indent: int) -> list[str]:
    """Block YAML for plain data kept in ``Xrdf.extra``."""
    pad = "  " * indent
    if isinstance(value, Mapping):
        if not value:
            return [pad + "{}"]
        lines: list[str] = []
        for k, v in value.items():
            if isinstance(v, (Mapping, list, tuple)) and v:
                lines.append(f"{pad}{_scalar(k)}:")
                lines.extend(_plain_block(v, indent + 1))
            else:
                lines.append(f"{pad}{_scalar(k)}: {_inline(v)}")
        return lines
    if isinstance(value, (list, tuple)):
        if not value:
            return [pad + "[]"]
        lines = []
        for v in value:
            if isinstance(v, (Mapping, list, tuple)) and v:
                sub = _plain_block(v, indent + 1)
                lines.append(f"{pad}- {sub[0].strip()}")
                lines.extend(sub[1:])
            else:
                lines.append(f"{pad}- {_inline(v)}")
        return lines
    return [pad + _scalar(value)]


def _inline(value: Any) -> str:
    if isinstance(value, Mapping):
        return "{" + ", ".join(f"{_scalar(k)}: {_inline(v)}" for k, v in value.items()) + "}"
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_inline(v) for v in value) + "]"
    return _scalar(value)


def _orientation_lines(o: Orientation, pad: str) -> list[str]:
    if o.form == "w_xyz":
        w, x, y, z = o.values
        return [f"{pad}orientation: {{w: {format_float(w)}, xyz: {_flow((x, y, z))}}}"]
    key = "quaternion" if o.form == "quaternion" else "euler_rpy"
    return [f"{pad}orientation:", f"{pad}  {key}: {_flow(o.values)}"]


def dump_xrdf(x: Xrdf) -> str:
    """Canonical YAML text of a model. Equal models give byte-identical text."""
    out: list[str] = ["format: xrdf", f"format_version: {x.format_version}"]

    def section(lines: list[str]) -> None:
        out.append("")
        out.extend(lines)

    if x.modifiers:
        lines = ["modifiers:"]
        for m in x.modifiers:
            if isinstance(m, SetBaseFrame):
                lines.append(f"  - set_base_frame: {format_str(m.frame)}")
            elif isinstance(m, AddFrame):
                lines += [
                    "  - add_frame:",
                    f"      frame_name: {format_str(m.frame_name)}",
                    f"      parent_frame_name: {format_str(m.parent_frame_name)}",
                    f"      joint_name: {format_str(m.joint_name)}",
                    f"      joint_type: {format_str(m.joint_type)}",
                    "      fixed_transform:",
                    f"        position: {_flow(m.position)}",
                    *_orientation_lines(m.orientation, "        "),
                ]
            else:
                lines += [
                    "  - remove_mimic_attributes:",
                    f"      joint_name: {format_str(m.joint_name)}",
                ]
                if m.position_limits is not None:
                    lines.append(f"      position_limits: {_flow(m.position_limits)}")
                if m.velocity_limits is not None:
                    lines.append(f"      velocity_limits: {format_float(m.velocity_limits)}")
        section(lines)

    if x.default_joint_positions is not None:
        if x.default_joint_positions:
            section(
                ["default_joint_positions:"]
                + [
                    f"  {format_str(k)}: {format_float(v)}"
                    for k, v in x.default_joint_positions.items()
                ]
            )
        else:
            section(["default_joint_positions: {}"])

    if x.cspace is not None:
        c = x.cspace
        lines = ["cspace:"]
        if c.joint_names:
            lines.append("  joint_names:")
            lines += [f"    - {format_str(j)}" for j in c.joint_names]
        else:
            lines.append("  joint_names: []")
        lines.append(f"  acceleration_limits: {_flow(c.acceleration_limits)}")
        lines.append(f"  jerk_limits: {_flow(c.jerk_limits)}")
        section(lines)

    if x.tool_frames is not None:
        section([f"tool_frames: {_flow(x.tool_frames)}"])

    if x.world_collision is not None:
        w = x.world_collision
        lines = [f"{x.collision_key}:", f"  geometry: {format_str(w.geometry)}"]
        lines += _buffer_lines(w.buffer_distance)
        section(lines)

    if x.self_collision is not None:
        s = x.self_collision
        lines = ["self_collision:", f"  geometry: {format_str(s.geometry)}"]
        lines += _buffer_lines(s.buffer_distance)
        if s.ignore:
            lines.append("  ignore:")
            lines += [f"    {format_str(k)}: {_flow(v)}" for k, v in s.ignore.items()]
        else:
            lines.append("  ignore: {}")  # cuRobo's loader raises when the key is missing
        section(lines)

    if x.geometry is not None:
        if not x.geometry:
            section(["geometry: {}"])
        else:
            lines = ["geometry:"]
            for name, g in x.geometry.items():
                lines.append(f"  {format_str(name)}:")
                if g.clone:
                    lines.append(f"    clone: {_flow(g.clone)}")
                if g.spheres or not g.clone:
                    if not g.spheres:
                        lines.append("    spheres: {}")
                    else:
                        lines.append("    spheres:")
                    for frame, spheres in g.spheres.items():
                        if not spheres:
                            lines.append(f"      {format_str(frame)}: []")
                            continue
                        lines.append(f"      {format_str(frame)}:")
                        for sp in spheres:
                            lines.append(f"        - center: {_flow(sp.center)}")
                            lines.append(f"          radius: {format_float(sp.radius)}")
            section(lines)

    for k, v in x.extra.items():
        if isinstance(v, (Mapping, list, tuple)) and v:
            section([f"{format_str(k)}:", *_plain_block(v, 1)])
        else:
            section([f"{format_str(k)}: {_inline(v)}"])
    return "\n".join(out) + "\n"


def _buffer_lines(buffers: Mapping[str, float]) -> list[str]:
    if not buffers:
        return []
    return ["  buffer_distance:"] + [
        f"    {format_str(k)}: {format_float(v)}" for k, v in buffers.items()
    ]
