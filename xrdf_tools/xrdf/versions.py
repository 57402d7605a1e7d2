"""Conversions between XRDF 1.0 and 2.0, reporting what could not be carried over.

What each version can express and what is reported: docs/format.md ("Version conversion").
"""

from __future__ import annotations

from ..diagnostics import Diagnostic, Severity
from ..util.errors import ConversionError
from ..util.frozen import FrozenMap
from .model import GeometryGroup, RemoveMimicAttributes, Sphere, Xrdf, clone_order, resolve_group


def _diag(x: Xrdf, rule: str, severity: Severity, message: str, key_path: str) -> Diagnostic:
    line, col = x.source.position(key_path)
    return Diagnostic(x.source.path, line, col, rule, severity, message, key_path)


def needs_version_2(x: Xrdf) -> list[str]:
    """Why ``x`` cannot be written as XRDF 1.0 without changing the robot (empty: it can)."""
    why = []
    if (groups := different_collision_groups(x)) is not None:
        why.append(
            f"world and self collision use different geometry groups ('{groups[0]}', '{groups[1]}')"
        )
    why += [
        f"remove_mimic_attributes ('{m.joint_name}') has no 1.0 form"
        for m in x.modifiers
        if isinstance(m, RemoveMimicAttributes)
    ]
    return why


def to_version(x: Xrdf, version: str) -> tuple[Xrdf, list[Diagnostic]]:
    """Convert ``x`` to ``version`` ("1.0" or "2.0"); same version returns it unchanged."""
    if version == x.format_version:
        return x, []
    if version == "2.0":
        return to_2_0(x)
    if version == "1.0":
        return to_1_0(x)
    raise ConversionError(f"unsupported format_version '{version}'; supported: 1.0, 2.0")


def _not_in_2_0(s: Sphere, frame: str, i: int, buffers: list[float]) -> str:
    """Why sphere ``i`` of ``frame`` cannot be written in 2.0 ("" when it can)."""
    if s.radius <= -1:
        return (
            f"sphere {i} on '{frame}' (radius {s.radius:g}) is a cuRobo attached-object slot; "
            "XRDF 2.0 requires radius > 0 and cannot express it, so it was dropped (write 1.0 "
            "to keep it)"
        )
    if s.radius <= 0:
        return (
            f"sphere {i} on '{frame}' has radius {s.radius:g}; 1.0 readers turn it into a real "
            "sphere once buffered, but XRDF 2.0 requires radius > 0, so it was dropped (write "
            "1.0 to keep it)"
        )
    if any(s.radius + b <= 0 for b in buffers):
        return (
            f"sphere {i} on '{frame}' has radius {s.radius:g} but a buffered radius ≤ 0; 2.0 "
            "rejects it, so it was dropped"
        )
    return ""


def to_2_0(x: Xrdf) -> tuple[Xrdf, list[Diagnostic]]:
    """1.0 → 2.0: ``collision`` becomes ``world_collision``; spheres 2.0 cannot express
    (radius ≤ 0: cuRobo's attached-object slots and small negative radii; buffered radius
    ≤ 0) are dropped and reported."""
    diags: list[Diagnostic] = []
    geometry = x.geometry
    if geometry is not None:
        world_buf = x.world_collision.buffer_distance if x.world_collision else FrozenMap()
        self_buf = x.self_collision.buffer_distance if x.self_collision else FrozenMap()
        groups = {}
        for gname, group in geometry.items():
            frames: dict[str, tuple[Sphere, ...]] = {}
            for frame, spheres in group.spheres.items():
                kept = []
                for i, s in enumerate(spheres):
                    kp = f"geometry.{gname}.spheres.{frame}[{i}].radius"
                    buffers = [world_buf.get(frame, 0.0), self_buf.get(frame, 0.0)]
                    why = _not_in_2_0(s, frame, i, buffers)
                    if why:
                        diags.append(
                            _diag(x, "dropped-nonpositive-sphere", Severity.WARNING, why, kp)
                        )
                    else:
                        kept.append(s)
                if kept or not spheres:  # a frame whose every sphere was dropped goes too
                    frames[frame] = tuple(kept)
            groups[gname] = GeometryGroup(FrozenMap(frames), group.clone)
        geometry = FrozenMap(groups)
    return x.replace(format_version="2.0", geometry=geometry), diags


def to_1_0(x: Xrdf) -> tuple[Xrdf, list[Diagnostic]]:
    """2.0 → 1.0: clones flattened, ``world_collision`` becomes ``collision``.

    Raises :class:`ConversionError` for ``remove_mimic_attributes`` (1.0 cannot express it).
    Warns when world and self collision use different groups (cuRobo rejects that in 1.0) and
    when ``tool_frames``/``default_joint_positions``, or ``self_collision`` beside a world
    collision section, are absent (cuRobo requires them).
    """
    diags: list[Diagnostic] = _invalid_radii(x)
    _refuse_remove_mimic(x)
    geometry = _flatten_clones(x, diags)
    if (groups := different_collision_groups(x)) is not None:
        diags.append(
            _diag(
                x,
                "different-collision-groups",
                Severity.WARNING,
                f"world collision uses '{groups[0]}' and self collision '{groups[1]}'; XRDF 1.0 "
                "consumers (cuRobo, Isaac Sim) need one group for both",
                "self_collision.geometry",
            )
        )
    diags.extend(_missing_for_curobo(x))
    return x.replace(format_version="1.0", geometry=geometry), diags


def different_collision_groups(x: Xrdf) -> tuple[str, str] | None:
    """The world and the self collision groups when they differ (None: they do not, or a
    section is missing)."""
    if x.world_collision is None or x.self_collision is None:
        return None
    if x.world_collision.geometry == x.self_collision.geometry:
        return None
    return x.world_collision.geometry, x.self_collision.geometry


def _refuse_remove_mimic(x: Xrdf) -> None:
    """Raise :class:`ConversionError` at the first ``remove_mimic_attributes`` modifier: XRDF
    1.0 cannot express it."""
    for i, m in enumerate(x.modifiers):
        if isinstance(m, RemoveMimicAttributes):
            line, col = x.source.position(f"modifiers[{i}]")
            raise ConversionError(
                f"modifier remove_mimic_attributes (joint '{m.joint_name}') has no XRDF 1.0 "
                "equivalent; edit the URDF instead or keep format_version 2.0",
                path=x.source.path or None,
                line=line,
                col=col,
            )


def _flatten_clones(x: Xrdf, diags: list[Diagnostic]) -> FrozenMap[str, GeometryGroup] | None:
    """The geometry of ``x`` with every clone resolved into its group's own spheres, a note
    in ``diags`` per group that cloned (unchanged when no group clones)."""
    geometry = x.geometry
    if geometry is None or not any(g.clone for g in geometry.values()):
        return geometry
    flat = {}
    for gname, group in geometry.items():
        if group.clone:
            diags.append(
                _diag(
                    x,
                    "flattened-clone",
                    Severity.INFO,
                    f"geometry group '{gname}' clones {', '.join(group.clone)}: flattened "
                    f"(order: {', '.join(clone_order(geometry, gname))})",
                    f"geometry.{gname}.clone",
                )
            )
        flat[gname] = GeometryGroup(resolve_group(geometry, gname), ())
    return FrozenMap(flat)


def _missing_for_curobo(x: Xrdf) -> list[Diagnostic]:
    """A note for each section cuRobo's 1.0 loader requires that ``x`` lacks."""
    missing: list[tuple[bool, str, str]] = [
        (x.tool_frames is None, "no tool_frames: cuRobo's 1.0 loader requires them", ""),
        (
            x.default_joint_positions is None,
            "no default_joint_positions: cuRobo's 1.0 loader requires them",
            "",
        ),
        (
            x.world_collision is not None and x.self_collision is None,
            "world collision without self_collision: cuRobo's 1.0 loader requires "
            "self_collision (with ignore) once collision is there",
            "world_collision",
        ),
    ]
    return [
        _diag(x, "missing-for-curobo", Severity.INFO, message, key_path)
        for lacking, message, key_path in missing
        if lacking
    ]


def _invalid_radii(x: Xrdf) -> list[Diagnostic]:
    """A warning at each sphere of a 2.0 file whose radius is ≤ 0 (2.0 forbids it): written
    into 1.0 as it is, it means something there (an attached-object slot, or a sphere once
    buffered) that the 2.0 file never said."""
    out = []
    for gname, group in (x.geometry or {}).items():
        for frame, spheres in group.spheres.items():
            for i, s in enumerate(spheres):
                if s.radius > 0:
                    continue
                meaning = (
                    "a cuRobo attached-object slot"
                    if s.radius <= -1
                    else "a sphere of that radius plus its buffer"
                )
                message = (
                    f"sphere {i} on '{frame}' has radius {s.radius:g}, invalid in XRDF 2.0 "
                    f"(radius > 0); written as it is, 1.0 readers take it as {meaning}: fix the "
                    "radius"
                )
                kp = f"geometry.{gname}.spheres.{frame}[{i}].radius"
                out.append(_diag(x, "invalid-radius-written", Severity.WARNING, message, kp))
    return out
