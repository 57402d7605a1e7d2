"""Write the model back as canonical XRDF text (public names re-exported by
:mod:`xrdf_tools.xrdf.io`).

Canonical: the section order of the spec, floats always written as floats that both YAML 1.1 and
1.2 readers parse as floats, stable formatting, so equal models give byte-identical text. One
writer per section; :func:`dump_xrdf` joins their blocks with blank lines.
"""

from __future__ import annotations

import json
import math
import re
from collections.abc import Callable, Mapping, Sequence
from typing import Any

from .model import AddFrame, GeometryGroup, Modifier, Orientation, SetBaseFrame, Xrdf

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


def _modifier_lines(m: Modifier) -> list[str]:
    if isinstance(m, SetBaseFrame):
        return [f"  - set_base_frame: {format_str(m.frame)}"]
    if isinstance(m, AddFrame):
        return [
            "  - add_frame:",
            f"      frame_name: {format_str(m.frame_name)}",
            f"      parent_frame_name: {format_str(m.parent_frame_name)}",
            f"      joint_name: {format_str(m.joint_name)}",
            f"      joint_type: {format_str(m.joint_type)}",
            "      fixed_transform:",
            f"        position: {_flow(m.position)}",
            *_orientation_lines(m.orientation, "        "),
        ]
    lines = ["  - remove_mimic_attributes:", f"      joint_name: {format_str(m.joint_name)}"]
    if m.position_limits is not None:
        lines.append(f"      position_limits: {_flow(m.position_limits)}")
    if m.velocity_limits is not None:
        lines.append(f"      velocity_limits: {format_float(m.velocity_limits)}")
    return lines


def _modifiers(x: Xrdf) -> list[str] | None:
    if not x.modifiers:
        return None
    return ["modifiers:"] + [line for m in x.modifiers for line in _modifier_lines(m)]


def _defaults(x: Xrdf) -> list[str] | None:
    d = x.default_joint_positions
    if d is None:
        return None
    if not d:
        return ["default_joint_positions: {}"]
    return ["default_joint_positions:"] + [
        f"  {format_str(k)}: {format_float(v)}" for k, v in d.items()
    ]


def _cspace(x: Xrdf) -> list[str] | None:
    c = x.cspace
    if c is None:
        return None
    lines = ["cspace:"]
    if c.joint_names:
        lines.append("  joint_names:")
        lines += [f"    - {format_str(j)}" for j in c.joint_names]
    else:
        lines.append("  joint_names: []")
    lines.append(f"  acceleration_limits: {_flow(c.acceleration_limits)}")
    lines.append(f"  jerk_limits: {_flow(c.jerk_limits)}")
    return lines


def _tool_frames(x: Xrdf) -> list[str] | None:
    return None if x.tool_frames is None else [f"tool_frames: {_flow(x.tool_frames)}"]


def _world(x: Xrdf) -> list[str] | None:
    w = x.world_collision
    if w is None:
        return None
    lines = [f"{x.collision_key}:", f"  geometry: {format_str(w.geometry)}"]
    return lines + _buffer_lines(w.buffer_distance)


def _self(x: Xrdf) -> list[str] | None:
    s = x.self_collision
    if s is None:
        return None
    lines = ["self_collision:", f"  geometry: {format_str(s.geometry)}"]
    lines += _buffer_lines(s.buffer_distance)
    if s.ignore:
        lines.append("  ignore:")
        lines += [f"    {format_str(k)}: {_flow(v)}" for k, v in s.ignore.items()]
    else:
        lines.append("  ignore: {}")  # cuRobo's loader raises when the key is missing
    return lines


def _group_lines(name: str, g: GeometryGroup) -> list[str]:
    lines = [f"  {format_str(name)}:"]
    if g.clone:
        lines.append(f"    clone: {_flow(g.clone)}")
    if g.clone and not g.spheres:
        return lines
    lines.append("    spheres:" if g.spheres else "    spheres: {}")
    for frame, spheres in g.spheres.items():
        if not spheres:
            lines.append(f"      {format_str(frame)}: []")
            continue
        lines.append(f"      {format_str(frame)}:")
        for sp in spheres:
            lines.append(f"        - center: {_flow(sp.center)}")
            lines.append(f"          radius: {format_float(sp.radius)}")
    return lines


def _geometry(x: Xrdf) -> list[str] | None:
    if x.geometry is None:
        return None
    if not x.geometry:
        return ["geometry: {}"]
    return ["geometry:"] + [line for n, g in x.geometry.items() for line in _group_lines(n, g)]


#: The section writers in the canonical order (that of the spec); None: section absent.
_SECTIONS: tuple[Callable[[Xrdf], list[str] | None], ...] = (
    _modifiers,
    _defaults,
    _cspace,
    _tool_frames,
    _world,
    _self,
    _geometry,
)


def _extra_lines(key: str, value: Any) -> list[str]:
    """A top-level key the model does not know, kept as plain data."""
    if isinstance(value, (Mapping, list, tuple)) and value:
        return [f"{format_str(key)}:", *_plain_block(value, 1)]
    return [f"{format_str(key)}: {_inline(value)}"]


def dump_xrdf(x: Xrdf) -> str:
    """Canonical YAML text of a model. Equal models give byte-identical text."""
    out: list[str] = ["format: xrdf", f"format_version: {x.format_version}"]
    blocks = [write(x) for write in _SECTIONS]
    blocks += [_extra_lines(k, v) for k, v in x.extra.items()]
    for lines in blocks:
        if lines is not None:
            out.append("")
            out.extend(lines)
    return "\n".join(out) + "\n"


def _buffer_lines(buffers: Mapping[str, float]) -> list[str]:
    if not buffers:
        return []
    return ["  buffer_distance:"] + [
        f"    {format_str(k)}: {format_float(v)}" for k, v in buffers.items()
    ]
