"""cuRobo robot configuration YAML → Draft: classic layout, 2.0 layout, Lula/Isaac Sim YAML.

See docs/convert.md for the mapping. Every key without an XRDF equivalent is
reported (``convert-dropped-key``) except visualisation, USD and asset-location keys, which are
ignored silently.
Unknown link names (cuRobo ignores them silently; its own ``ur10e.yml`` has ``forarm_link``)
are reported with a suggestion and dropped. Spheres are kept as written, negative radii included
(cuRobo turns a small negative radius into a real sphere once buffered), and the
``extra_collision_spheres`` attached-object slots become radius −10 spheres at the link origin,
as cuMotion's own ``franka_curobo.xrdf`` carries them (docs/format.md, "Who reads an XRDF").
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from ...diagnostics import Severity
from ...util.errors import SourceError
from ...xrdf.model import SetBaseFrame
from ...yaml.io import to_python
from ...yaml.shape import check_shape
from . import Draft, Reporter, RobotTree, known_frame, not_a_joint
from .curobo_config import kinematics_of, load_config
from .curobo_extra_links import read_extra_links
from .curobo_keys import changes_nothing, key_text, unknown_to_curobo
from .curobo_kin import KinSection
from .curobo_lula import read_lula
from .curobo_shape import CUROBO_FILE
from .curobo_spheres import find_spheres_file, is_num, read_slots, read_sphere_map

__all__ = ["detect_layout", "read_curobo"]

SILENT_KEYS = {
    "mesh_link_names",
    "use_global_cumul",
    "isaac_usd_path",
    "use_usd_kinematics",
    "urdf_path",
    "asset_root_path",
    "external_asset_path",
    "external_robot_configs_path",
    "format_version",
    "load_link_names_with_mesh",
    "usd_path",
    "usd_robot_root",
    "usd_flip_joints",
    "usd_flip_joint_limits",
    "load_meshes",  # whether cuRobo loads the link meshes (visualisation)
    "use_external_assets",  # where cuRobo looks for the URDF, as external_asset_path
    "debug",
}
HANDLED_KEYS = {
    "base_link",
    "ee_link",
    "link_names",
    "tool_frames",
    "collision_link_names",
    "collision_spheres",
    "collision_sphere_buffer",
    "self_collision_ignore",
    "self_collision_buffer",
    "extra_links",
    "extra_collision_spheres",
    "lock_joints",
    "cspace",
}
CSPACE_KEYS = {
    "joint_names",
    "retract_config",
    "default_joint_position",
    "max_acceleration",
    "max_jerk",
}


def detect_layout(data: Any) -> str:
    """``"classic"``, ``"2.0"`` or ``"lula"`` for the plain data of a config file."""
    if isinstance(data, Mapping):
        kin = kinematics_of(data)
        if kin is not None:
            fv = kin.get("format_version")
            if (
                (isinstance(fv, (int, float)) and float(fv) >= 2.0)
                or "tool_frames" in kin
                or "default_joint_position" in (kin.get("cspace") or {})
            ):
                return "2.0"
            return "classic"
        if isinstance(data.get("cspace"), list):
            return "lula"
    raise SourceError(
        "not a cuRobo robot configuration: expected 'robot_cfg: {kinematics: ...}' (cuRobo) or "
        "a Lula robot description with a 'cspace' list"
    )


def read_curobo(path: str | os.PathLike[str], tree: RobotTree, draft: Draft | None = None) -> Draft:
    """Map a cuRobo (or Lula) robot YAML onto a :class:`Draft`."""
    d = draft or Draft()
    doc, rep = load_config(path)
    check_shape(doc.root, CUROBO_FILE, path=doc.path, error=SourceError)
    data = to_python(doc.root)
    try:
        layout = detect_layout(data)
    except SourceError as e:
        raise SourceError(e.message, path=doc.path, line=1) from None
    if layout == "lula":
        read_lula(data, tree, d, rep)
    else:
        if kinematics_of(data) is not data.get("kinematics"):
            prefix = "robot_cfg.kinematics"
            for k in data["robot_cfg"]:
                if k != "kinematics":
                    rep.report(
                        "convert-dropped-key",
                        f"robot_cfg.{key_text(k)} has no XRDF equivalent; dropped",
                        f"robot_cfg.{k}",
                    )
        else:
            prefix = "kinematics"
        for k in data:
            if k not in ("robot_cfg", "kinematics"):
                rep.report(
                    "convert-dropped-key", f"'{key_text(k)}' has no XRDF equivalent; dropped", k
                )
        kin = kinematics_of(data)
        assert kin is not None
        _readkinematics_of(kin, layout, tree, d, rep, prefix, Path(doc.path))
    d.diagnostics.extend(rep.diagnostics)
    return d


def _readkinematics_of(
    kin: Mapping[str, Any],
    layout: str,
    tree: RobotTree,
    d: Draft,
    rep: Reporter,
    prefix: str,
    config_path: Path,
) -> None:
    k = KinSection(kin, tree, d, rep, prefix, config_path, list(tree.links))
    for key in kin:
        if key not in SILENT_KEYS and key not in HANDLED_KEYS and not str(key).startswith("usd"):
            _report_dropped(rep, f"'{key_text(key)}'", key, kin[key], "kinematics", k.kp(key))
    read_extra_links(k)  # first: they add frames the rest may refer to
    _read_base_and_tools(k)
    _read_cspace(k)
    _read_sphere_source(k)
    read_slots(
        kin.get("extra_collision_spheres"), k.frames, d, rep, k.kp("extra_collision_spheres")
    )
    _read_buffers(k)
    _read_ignore(k)


def _report_dropped(
    rep: Reporter, named: str, key: str, value: Any, section: str, where: str
) -> None:
    """A key the XRDF does not carry: nothing said when its value is what cuRobo takes
    without it; a key no cuRobo version knows is said to stop cuRobo's own loader."""
    if key == "load_collision_spheres" and value is False:
        rep.report(
            "convert-dropped-key",
            "load_collision_spheres: false: cuRobo loads none of this config's spheres, so it "
            "checks no collision with it; an XRDF has no such switch and keeps the spheres, "
            "which cuRobo then checks",
            where,
        )
    elif unknown_to_curobo(key, section):
        rep.report(
            "convert-dropped-key",
            f"{named} is not a cuRobo {section} setting (cuRobo's loader stops on it: "
            "unexpected keyword argument); dropped",
            where,
        )
    elif not changes_nothing(key, value):
        rep.report("convert-dropped-key", f"{named} has no XRDF equivalent; dropped", where)


def _read_base_and_tools(k: KinSection) -> None:
    base = k.data.get("base_link")
    if base is not None and known_frame(str(base), k.frames, k.rep, k.kp("base_link"), "base_link"):
        k.d.modifiers.insert(0, SetBaseFrame(str(base)))  # also the root: cuRobo's XRDFs do
    tools: list[tuple[str, str]] = []
    if k.data.get("tool_frames") is not None:
        tf = k.data["tool_frames"]
        tf = tf if isinstance(tf, list) else [tf]
        tools += [(str(t), k.kp("tool_frames", f"[{i}]")) for i, t in enumerate(tf)]
    if k.data.get("ee_link"):
        tools.insert(0, (str(k.data["ee_link"]), k.kp("ee_link")))
    for i, t in enumerate(k.data.get("link_names") or []):
        tools.append((str(t), k.kp("link_names") + f"[{i}]"))
    for t, where in tools:
        if known_frame(t, k.frames, k.rep, where, "tool frame") and t not in k.d.tool_frames:
            k.d.tool_frames.append(t)


def _per_joint(k: KinSection, names: list[str], value: Any, key: str) -> dict[str, float]:
    """A scalar (broadcast) or one value per c-space joint, by joint name."""
    if value is None:
        return {}
    if is_num(value):
        return {n: float(value) for n in names}
    if isinstance(value, list) and all(is_num(v) for v in value):
        if len(value) != len(names):
            raise k.fail(
                f"cspace.{key} has {len(value)} values for {len(names)} joints", "cspace", key
            )
        return {n: float(v) for n, v in zip(names, value, strict=True)}
    raise k.fail(f"cspace.{key} must be a number or a list of numbers", "cspace", key)


def _read_cspace(k: KinSection) -> None:
    cs = k.mapping("cspace")
    for key in cs:
        if key not in CSPACE_KEYS:
            named = f"cspace.{key_text(key)}"
            _report_dropped(k.rep, named, key, cs[key], "cspace", k.kp("cspace", key))
    names = [str(n) for n in (cs.get("joint_names") or [])]
    locks = k.mapping("lock_joints")
    default_key = "default_joint_position" if "default_joint_position" in cs else "retract_config"
    defaults = cs.get(default_key)
    if defaults is not None and not isinstance(defaults, list):
        raise k.fail(f"cspace.{default_key} must be a list", "cspace", default_key)
    acc_map = _per_joint(k, names, cs.get("max_acceleration"), "max_acceleration")
    jerk_map = _per_joint(k, names, cs.get("max_jerk"), "max_jerk")
    def_map = _per_joint(k, names, defaults, default_key)
    cspace = _cspace_joints(k, names, locks)
    k.d.cspace = cspace
    for n in cspace:
        for source, target in (
            (acc_map, k.d.acceleration),
            (jerk_map, k.d.jerk),
            (def_map, k.d.defaults),
        ):
            if n in source:
                target[n] = source[n]
        if n in def_map:
            where = k.kp("cspace", default_key) + f"[{names.index(n)}]"
            k.d.default_at[n] = (k.rep.path, k.rep.position(where)[0])
    _read_locks(k, locks, def_map, names, default_key)
    for n, v in def_map.items():
        if n in k.moving_joints and n not in locks:
            where = k.kp("cspace", default_key) + f"[{names.index(n)}]"
            _moving_value_unused(k, f"c-space joint '{n}'", n, f"{default_key} value", v, where)


def _cspace_joints(k: KinSection, names: list[str], locks: Mapping[str, Any]) -> list[str]:
    """The actuated, unlocked c-space joints; the others reported. Raises when none of the
    names is a URDF joint: the config and the URDF describe different robots."""
    if names and not any(n in k.tree.joints for n in names):
        raise k.fail(_no_cspace_joint(names, k.tree), "cspace", "joint_names")
    cspace: list[str] = []
    for i, n in enumerate(names):
        where = k.kp("cspace", "joint_names") + f"[{i}]"
        j = k.tree.joints.get(n)
        if j is None and n in k.moving_joints:
            continue  # said with its extra link
        if j is None:
            k.rep.report(
                "convert-unknown-joint",
                f"c-space joint '{n}' {not_a_joint(n, k.tree)}; dropped",
                where,
            )
        elif n in locks:
            continue
        elif not j.is_actuated:
            k.rep.report(
                "convert-dropped-joint",
                f"c-space joint '{n}' is {'a mimic' if j.is_mimic else j.type} joint; "
                "XRDF c-space holds only actuated joints; dropped",
                where,
            )
        else:
            cspace.append(n)
    return cspace


def _no_cspace_joint(names: list[str], tree: RobotTree) -> str:
    """Why none of ``names`` is a joint: link names where joints belong (an xArm6 config
    listing link1 … link6), else another robot's joints."""
    shown = f"{', '.join(names[:4])}{', ...' if len(names) > 4 else ''}"
    urdf = Path(tree.path).name
    movers = [tree.parent_joint.get(n) for n in names]
    if all(movers):
        joints = [str(j) for j in movers]
        return (
            f"cspace.joint_names lists links of {urdf} ({shown}), not joints: name the joints "
            f"that move them ({', '.join(joints[:4])}{', ...' if len(joints) > 4 else ''})"
        )
    return (
        f"none of the {len(names)} c-space joints ({shown}) is a joint of {urdf}: "
        "the config and the URDF describe different robots"
    )


def _read_locks(
    k: KinSection,
    locks: Mapping[str, Any],
    defaults: Mapping[str, float],
    names: list[str],
    key: str,
) -> None:
    """Lock values become defaults; a locked joint's other ``key`` value is said unused."""
    for n, v in locks.items():
        where = k.kp("lock_joints", n)
        j = k.tree.joints.get(str(n))
        if j is None and str(n) in k.moving_joints:
            _moving_value_unused(k, f"locked joint '{n}'", str(n), "lock value", v, where)
        elif j is None:
            k.rep.report(
                "convert-unknown-joint",
                f"locked joint '{n}' {not_a_joint(str(n), k.tree)}; dropped",
                where,
            )
        elif not is_num(v):
            raise k.fail(f"lock_joints.{n} must be a number", "lock_joints", n)
        elif j.is_actuated:
            k.d.defaults[str(n)] = float(v)
            k.d.default_at[str(n)] = (k.rep.path, k.rep.position(where)[0])
            if (other := defaults.get(str(n), float(v))) != float(v):
                k.rep.report(
                    "convert-dropped-joint-value",
                    f"'{n}' is also in lock_joints: it is held at its lock value {float(v)!r}, "
                    f"as cuRobo does; its cspace.{key} value {other!r} is not used",
                    k.kp("cspace", key) + f"[{names.index(str(n))}]",
                    severity=Severity.INFO,
                )
        else:
            k.rep.report(
                "convert-dropped-joint-value",
                f"locked joint '{n}' is not actuated; its value is not written",
                where,
                severity=Severity.INFO,
            )


def _moving_value_unused(
    k: KinSection, who: str, joint: str, what: str, value: Any, where: str
) -> None:
    """A value given for a moving extra link's joint (its default, its lock): the XRDF holds
    that link at its zero pose, so a value other than 0 is said not applied."""
    if is_num(value) and float(value) == 0.0:
        return
    k.rep.report(
        "convert-dropped-joint-value",
        f"{who} moves extra link '{k.moving_joints[joint]}', which the XRDF holds at its zero "
        f"pose; its {what} {value!r} is not applied",
        where,
    )


def _read_sphere_source(k: KinSection) -> None:
    """``collision_spheres``: inline, or a file beside the config; restricted to
    ``collision_link_names`` as cuRobo does."""
    value = k.data.get("collision_spheres")
    raw: Mapping[str, Any] | None = None
    srep, sprefix = k.rep, k.kp("collision_spheres")
    if isinstance(value, str):
        sphere_file = find_spheres_file(value, k.config_path, k.rep, sprefix)
        sdoc, srep = load_config(sphere_file)
        sdata = to_python(sdoc.root)
        if not isinstance(sdata, Mapping) or not isinstance(
            sdata.get("collision_spheres"), Mapping
        ):
            raise SourceError(
                "a cuRobo spheres file needs a top-level 'collision_spheres' mapping",
                path=sdoc.path,
                line=1,
            )
        raw, sprefix = sdata["collision_spheres"], "collision_spheres"
    elif isinstance(value, Mapping):
        raw = value
    elif value is not None:
        raise k.fail(
            "collision_spheres must be a file path or a mapping of link → spheres",
            "collision_spheres",
        )
    coll_links = k.data.get("collision_link_names")
    allowed = None if coll_links is None else {str(c) for c in coll_links}
    if raw is None:
        return
    k.d.spheres = read_sphere_map(raw, k.frames, srep, sprefix, allowed)
    if allowed is None and any(k.d.spheres.values()):
        k.rep.report(
            "convert-unused-spheres",
            "no collision_link_names: cuRobo loads none of these spheres from this config "
            "(it checks no collision for it); the XRDF keeps them, so its readers check them",
            k.kp("collision_spheres"),
        )
    if srep is not k.rep:
        k.d.diagnostics.extend(srep.diagnostics)
    for i, c in enumerate(coll_links or []):
        if str(c) not in k.frames:
            where = k.kp("collision_link_names") + f"[{i}]"
            known_frame(str(c), k.frames, k.rep, where, "collision link")


def _read_buffers(k: KinSection) -> None:
    """``collision_sphere_buffer`` (scalar: every sphere frame) and ``self_collision_buffer``;
    zero buffers are not written."""
    sphere_frames = list((k.d.spheres or {}).keys())
    for key, target in (
        ("collision_sphere_buffer", k.d.world_buffer),
        ("self_collision_buffer", k.d.self_buffer),
    ):
        buf = k.data.get(key)
        if is_num(buf):
            if float(buf) != 0.0:
                target.update({f: float(buf) for f in sphere_frames})
        elif isinstance(buf, Mapping):
            for f, v in buf.items():
                ok = known_frame(str(f), k.frames, k.rep, k.kp(key, f), key)
                if ok and is_num(v) and float(v) != 0.0:
                    target[str(f)] = float(v)
        elif buf is not None:
            raise k.fail(f"{key} must be a number or a mapping", key)


def _read_ignore(k: KinSection) -> None:
    for a, others in k.mapping("self_collision_ignore").items():
        w = k.kp("self_collision_ignore", a)
        if not known_frame(str(a), k.frames, k.rep, w, "self_collision_ignore key"):
            continue
        for i, b in enumerate(others or []):
            if known_frame(str(b), k.frames, k.rep, f"{w}[{i}]", f"ignored with '{a}'"):
                k.d.add_ignore(str(a), str(b))
