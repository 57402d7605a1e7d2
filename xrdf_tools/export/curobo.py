"""XRDF → other formats: a cuRobo robot YAML and MoveIt SRDF ``disable_collisions``.

The SRDF side lives in :mod:`xrdf_tools.export.srdf` (``to_srdf`` is re-exported here).

Pure: functions return text and diagnostics. ``to_curobo`` writes what cuRobo's loader accepts:
every number a float (``0.0``, never ``0``: cuRobo broadcasts Python floats only), ``FIXED``
joint types in upper case, lists in c-space order looked up *by joint name* (cuRobo's own XRDF
reader fills defaults in URDF order — a bug we do not copy), buffers per link. What cuRobo's
loader would still raise on is an error diagnostic (``export-no-pair`` here, the ``curobo-*``
lint findings the YAML carries in :mod:`xrdf_tools.export.curobo_loader`): the command then
writes nothing.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..diagnostics import Diagnostic, Severity
from ..robot.tree import RobotTree
from ..util.errors import ConversionError
from ..util.text import name_list
from ..xrdf.io import format_float, format_str
from ..xrdf.model import RemoveMimicAttributes, Xrdf
from ..xrdf.versions import different_collision_groups
from .curobo_assets import curobo_paths, expanded_urdf_path, mesh_root, unserved_note
from .srdf import to_srdf

if TYPE_CHECKING:
    from ..robot.core import Robot

__all__ = [
    "CUROBO_LAYOUTS",
    "curobo_paths",
    "expanded_urdf_path",
    "for_target",
    "to_curobo",
    "to_srdf",
]

CUROBO_LAYOUTS = ("2.0", "classic")


def _scalar(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return format_float(float(v))
    if v is None:
        return "null"
    return format_str(str(v))


def _emit(value: Any, indent: int) -> list[str]:
    pad = "  " * indent
    lines: list[str] = []
    if isinstance(value, Mapping):
        for k, v in value.items():
            nested = isinstance(v, list) and any(isinstance(i, (Mapping, list)) for i in v)
            if (isinstance(v, Mapping) and v) or nested:
                lines.append(f"{pad}{format_str(str(k))}:")
                lines += _emit(v, indent + 1)
            else:
                lines.append(f"{pad}{format_str(str(k))}: {_inline(v)}")
    elif isinstance(value, list):
        for item in value:
            sub = _emit(item, indent + 1) if isinstance(item, (Mapping, list)) else []
            if sub:
                lines.append(f"{pad}- {sub[0].lstrip()}")
                lines += sub[1:]
            else:
                lines.append(f"{pad}- {_inline(item)}")
    return lines


def _inline(v: Any) -> str:
    if isinstance(v, Mapping):
        return "{" + ", ".join(f"{format_str(str(k))}: {_inline(x)}" for k, x in v.items()) + "}"
    if isinstance(v, list):
        return "[" + ", ".join(_inline(x) for x in v) + "]"
    return _scalar(v)


def for_target(
    x: Xrdf, target: str | None, format_version: str | None = None
) -> tuple[Xrdf, list[Diagnostic]]:
    """``x`` rewritten in the XRDF version ``target`` loads (or ``format_version``), with a
    diagnostic for everything the version change could not carry over."""
    from ..xrdf.readers import choose_version, parse_target
    from ..xrdf.versions import to_version

    version, why = choose_version(x, format_version, parse_target(target))
    out, diags = to_version(x, version)
    if why:
        diags.append(Diagnostic(x.source.path, None, None, "export-version", Severity.WARNING, why))
    return out, diags


def _located(x: Xrdf, key_path: str, message: str) -> ConversionError:
    """A :class:`ConversionError` at ``key_path`` of ``x`` (the document's start when the key
    is absent), so that the one-line error names the XRDF file and its line."""
    return ConversionError(message, **x.source.locate(key_path))


def _check_exportable(x: Xrdf, tree: RobotTree, layout: str, robot: Robot | None) -> None:
    """Raise :class:`ConversionError` / :class:`SourceError` when ``x`` cannot become a cuRobo
    config for ``tree``: unknown layout, no c-space, 2.0-only modifiers, another robot; with the
    loaded ``robot``, also what every command that poses it refuses (a modifier that cannot be
    applied, a c-space joint that is mimic, fixed or pruned)."""
    from ..robot.binding import check_belongs, cspace_indices

    if layout not in CUROBO_LAYOUTS:
        raise ConversionError(
            f"unknown cuRobo layout '{layout}'; choose {', '.join(CUROBO_LAYOUTS)}"
        )
    if x.cspace is None:
        raise _located(x, "", "the XRDF has no cspace; cuRobo needs one")
    for i, m in enumerate(x.modifiers):
        if isinstance(m, RemoveMimicAttributes):
            raise _located(
                x,
                f"modifiers[{i}]",
                "remove_mimic_attributes has no cuRobo equivalent; edit the URDF instead",
            )
    base = x.base_frame()
    check_belongs(x, tree.with_root(base) if base in tree.links else tree)
    if robot is not None:
        from ..robot.kinematics import build_kinematic_model

        cspace_indices(build_kinematic_model(robot, x)[0], x)


def to_curobo(
    x: Xrdf,
    tree: RobotTree | Robot,
    *,
    layout: str = "2.0",
    urdf_path: str | os.PathLike[str] | None = None,
    relative_to: str | os.PathLike[str] | None = None,
    plain_file_names: bool = False,
) -> tuple[str, list[Diagnostic]]:
    """A cuRobo robot configuration (``robot_cfg: {kinematics: ...}``) for ``x`` and its URDF.

    ``layout`` is ``"2.0"`` (``tool_frames``, ``default_joint_position``) or ``"classic"``
    (``ee_link``, ``link_names``, ``retract_config``; cuRobo ≤ 0.7). The actuated URDF
    joints outside the c-space become ``lock_joints``, held at their default position (without
    one, at 0 clamped to their limits: what the XRDF means, where cuRobo's own XRDF reader would
    lock them at 0.0, outside limits that exclude 0). ``tree`` is the URDF's
    :class:`RobotTree` or the loaded :class:`~xrdf_tools.robot.core.Robot`. ``urdf_path`` (the
    file ``urdf_path`` names; default: the tree's) is written relative to the directory
    ``relative_to`` (the output's), or absolute when it is None (see :func:`curobo_paths`).
    ``plain_file_names``: ``urdf_path`` is written by
    :func:`~xrdf_tools.export.curobo_assets.with_plain_file_names` (its ``file://`` meshes
    are found). A diagnostic of severity error says that cuRobo's loader raises on the text.
    """
    robot = None if isinstance(tree, RobotTree) else tree
    assets = None if robot is None else mesh_root(robot, plain_file_names=plain_file_names)
    if robot is not None:
        tree = robot.tree
    assert isinstance(tree, RobotTree)
    _check_exportable(x, tree, layout, robot)
    diags: list[Diagnostic] = []

    def note(rule: str, msg: str, sev: Severity = Severity.WARNING) -> None:
        diags.append(Diagnostic(x.source.path, None, None, rule, sev, msg, ""))

    kin: dict[str, Any] = {"format_version": 2.0} if layout == "2.0" else {}
    upath = Path(urdf_path) if urdf_path is not None else Path(tree.path)
    kin["urdf_path"], kin["asset_root_path"] = curobo_paths(upath, relative_to, assets)
    if assets is not None and assets.unserved:
        note("export-mesh-paths", unserved_note(assets))
    kin["base_link"] = x.base_frame() or tree.root
    kin.update(_tool_keys(x, layout))
    kin.update(_collision_keys(x, note))
    diags.extend(_no_pair_left(x, kin))
    diags.extend(_no_spheres(x, kin))
    kin["extra_links"] = _extra_links(x)
    if x.extra:
        note("export-dropped-key", f"top-level keys {name_list(x.extra)} are not exported")
    kin.update(_joint_keys(x, tree, layout, note))
    return _document(kin, layout, x.source.path), diags


def _tool_keys(x: Xrdf, layout: str) -> dict[str, Any]:
    """The end effector keys of ``layout``: ``tool_frames``, or classic ``ee_link`` (the
    first tool frame) and ``link_names``. Raises when the XRDF has no tool frame."""
    tools = list(x.tool_frames or [])
    if not tools:
        raise _located(
            x, "tool_frames", "the XRDF has no tool_frames; cuRobo needs an end effector"
        )
    if layout == "2.0":
        return {"tool_frames": tools}
    return {"ee_link": tools[0], "link_names": tools}


def _no_spheres(x: Xrdf, kin: Mapping[str, Any]) -> list[Diagnostic]:
    """An ``export-no-spheres`` warning when ``kin`` (the config written) has no collision
    sphere, located at the XRDF's world collision group (its geometry without one)."""
    if kin["collision_spheres"]:
        return []
    where = "collision.geometry" if x.world_collision is not None else "geometry"
    line, col = x.source.position(where)
    message = (
        "no collision sphere to export: cuRobo checks no collision for this robot (fit "
        "them: xrdf convert --fit-spheres)"
    )
    return [
        Diagnostic(x.source.path, line, col, "export-no-spheres", Severity.WARNING, message, where)
    ]


def _extra_links(x: Xrdf) -> dict[str, Any] | None:
    """cuRobo's ``extra_links``: one fixed link per frame the XRDF adds (None without)."""
    extra: dict[str, Any] = {}
    for m in x.added_frames():
        w, qx, qy, qz = m.orientation.as_wxyz()
        extra[m.frame_name] = {
            "parent_link_name": m.parent_frame_name,
            "link_name": m.frame_name,
            "joint_name": m.joint_name,
            "joint_type": "FIXED",
            "fixed_transform": [*m.position, w, qx, qy, qz],
        }
    return extra or None


def _joint_keys(
    x: Xrdf, tree: RobotTree, layout: str, note: Callable[[str, str], None]
) -> dict[str, Any]:
    """``lock_joints`` and ``cspace``: the c-space joints, then every other actuated joint of
    ``tree`` locked at its default position (0 clamped to its limits without one), as cuRobo's
    XRDF reader holds them (its config loader raises on a joint that is in neither list); the
    locked joints' limits are the c-space's largest. Default positions cuRobo cannot take are
    ``note``d."""
    cs = x.cspace
    assert cs is not None
    given = dict(x.default_joint_positions or {})
    defaults = {j: tree.joints[j].unset_position for j in tree.actuated_joints()} | given
    outside = [j for j in tree.actuated_joints() if j not in cs.joint_names]
    locks = {j: defaults[j] for j in outside}
    for j in given:
        if j not in cs.joint_names and j not in locks:
            note("export-dropped-joint", f"default position of '{j}' is not an actuated joint")
    missing = [j for j in cs.joint_names if j not in given]
    if missing:
        note(
            "export-default-positions",
            f"no default position for {name_list(missing, 12)}: cuRobo needs one, the XRDF's "
            "(0 clamped to the joint's limits) written",
        )
    names = [*cs.joint_names, *locks]
    acc = list(cs.acceleration_limits)
    jerk = list(cs.jerk_limits)
    if len(acc) != len(cs.joint_names) or len(jerk) != len(cs.joint_names):
        raise _located(x, "cspace", "cspace limits do not match the number of c-space joints")
    fill_a = max(acc, default=10.0)
    fill_j = max(jerk, default=1000.0)
    cspace: dict[str, Any] = {"joint_names": names}
    key = "default_joint_position" if layout == "2.0" else "retract_config"
    cspace[key] = [defaults.get(j, 0.0) for j in names]  # 0.0: a c-space name not in the URDF
    cspace["max_acceleration"] = acc + [fill_a] * len(locks)
    cspace["max_jerk"] = jerk + [fill_j] * len(locks)
    return {"lock_joints": locks or None, "cspace": cspace}


def _document(kin: Mapping[str, Any], layout: str, path: str) -> str:
    """The YAML text of the config ``kin`` under ``robot_cfg.kinematics``, with a header
    naming the XRDF ``path`` and saying how relative paths are read."""
    lines = [
        "# cuRobo robot configuration written by xrdf-tools (xrdf export curobo)",
        f"# from {Path(path).name if path else 'an XRDF'}; layout: {layout}",
        *(_RELATIVE_NOTE if not Path(kin["urdf_path"]).is_absolute() else ()),
        "robot_cfg:",
        "  kinematics:",
        *_emit(kin, 2),
    ]
    return "\n".join(lines) + "\n"


def _collision_keys(x: Xrdf, note: Callable[[str, str, Severity], None]) -> dict[str, Any]:
    """The spheres, buffers and ignore pairs of a cuRobo config (one sphere set: the world
    group's; a different self group is reported through ``note``)."""
    world = dict(x.world_collision_spheres())
    if (groups := different_collision_groups(x)) is not None:
        note(
            "export-different-groups",
            f"world and self collision use different groups; cuRobo has one sphere set, the "
            f"world group '{groups[0]}' is written",
            Severity.WARNING,
        )
    if not world and x.self_collision is not None:
        world = dict(x.self_collision_spheres())
        if any(world.values()):
            note(
                "export-self-only",
                "the XRDF checks its spheres for self-collision only; cuRobo has one sphere set "
                "and checks it against the world too",
                Severity.WARNING,
            )
    spheres = {
        f: [{"center": list(s.center), "radius": s.radius} for s in ss]
        for f, ss in sorted(world.items())
        if ss
    }
    kin: dict[str, Any] = {"collision_link_names": list(spheres), "collision_spheres": spheres}
    wbuf = dict(x.world_collision.buffer_distance) if x.world_collision else {}
    kin["collision_sphere_buffer"] = (
        {f: wbuf.get(f, 0.0) for f in [*spheres, *(k for k in wbuf if k not in spheres)]}
        if any(wbuf.values())
        else 0.0
    )
    ignore: dict[str, list[str]] = {}
    if x.self_collision is not None:
        for a, bs in x.self_collision.ignore.items():
            for b in bs:
                if b not in ignore.get(a, []) and a not in ignore.get(b, []):
                    ignore.setdefault(a, []).append(b)
        sbuf = {f: v for f, v in sorted(x.self_collision.buffer_distance.items())}
    elif len(spheres) > 1:  # world collision only: cuRobo can only be told to skip every pair
        frames = list(spheres)
        ignore = {a: frames[i + 1 :] for i, a in enumerate(frames[:-1])}
        note(
            "export-no-self-collision",
            "the XRDF has no self_collision section (its spheres are never checked against "
            "each other); cuRobo checks every pair not in self_collision_ignore, so every pair "
            f"of the {len(frames)} sphere frames is written there",
            Severity.INFO,
        )
        sbuf = {}
    else:
        sbuf = {}
    kin["self_collision_ignore"] = {a: ignore[a] for a in sorted(ignore)}
    kin["self_collision_buffer"] = sbuf
    return kin


def _no_pair_left(x: Xrdf, kin: Mapping[str, Any]) -> list[Diagnostic]:
    """An ``export-no-pair`` error when cuRobo would have no pair of the sphere frames of
    ``kin`` (the config written) to check for self-collision: its loader divides by that
    number and raises. Located at the XRDF's mask (its collision section without one)."""
    frames: list[str] = kin["collision_link_names"]
    if not frames:
        return []
    ignore: Mapping[str, list[str]] = kin["self_collision_ignore"]
    masked = {frozenset((a, b)) for a, bs in ignore.items() for b in bs}
    if any(frozenset((a, b)) not in masked for i, a in enumerate(frames) for b in frames[i + 1 :]):
        return []
    if x.self_collision is None:
        fix = (
            "give the XRDF a self_collision section that leaves the pairs that can collide "
            "unmasked (xrdf report FILE --urdf URDF --write-mask OUT adds one)"
        )
    else:
        fix = "remove a pair that can collide from self_collision.ignore"
    where = "self_collision.ignore" if x.self_collision is not None else x.collision_key
    line, col = x.source.position(f"{where}#key")
    message = (
        f"no pair of the {len(frames)} sphere frame(s) is left for self-collision: cuRobo's "
        f"loader raises on this config (ZeroDivisionError); {fix} (and turn self-collision "
        "checking off in cuRobo's planner configuration if the robot should not check it)"
    )
    return [Diagnostic(x.source.path, line, col, "export-no-pair", Severity.ERROR, message, where)]


_RELATIVE_NOTE = (
    "# urdf_path and asset_root_path are relative to this file's directory. cuRobo joins a",
    "# relative path to its own asset directory: before loading, set",
    "# robot_cfg.kinematics.external_asset_path to this file's directory, or export again",
    "# with --absolute-paths.",
)


def pairs_of(x: Xrdf) -> Sequence[frozenset[str]]:
    return sorted(x.self_collision.ignore_pairs() if x.self_collision else (), key=sorted)
