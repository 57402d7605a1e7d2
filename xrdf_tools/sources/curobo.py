"""cuRobo robot configuration YAML → Draft: classic layout, 2.0 layout, Lula/Isaac Sim YAML.

See ``shared/spec/sources.md`` §1 for the mapping. Every key without an XRDF equivalent is
reported (``convert-dropped-key``) except visualisation/USD keys, which are ignored silently.
Unknown link names (cuRobo ignores them silently; its own ``ur10e.yml`` has ``forarm_link``)
are reported with a suggestion and dropped. Placeholder spheres (radius ≤ 0, and the
``extra_collision_spheres`` attached-object slots) are reported and not emitted.
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any, TypeGuard

from ..diagnostics import Severity
from ..errors import SourceError, did_you_mean
from ..model import AddFrame, Orientation, SetBaseFrame, Sphere
from ..shape import check_shape
from ..yaml_io import YamlDocument, node_positions, parse_yaml, read_text, to_python
from . import Draft, Reporter, RobotTree, known_frame
from .curobo_shape import CUROBO_FILE

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
        kin = _kinematics(data)
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


def _kinematics(data: Mapping[str, Any]) -> Mapping[str, Any] | None:
    rc = data.get("robot_cfg")
    if isinstance(rc, Mapping) and isinstance(rc.get("kinematics"), Mapping):
        return rc["kinematics"]  # type: ignore[no-any-return]
    if isinstance(data.get("kinematics"), Mapping):
        return data["kinematics"]  # type: ignore[no-any-return]
    return None


def _load(path: str | os.PathLike[str]) -> tuple[YamlDocument, Reporter]:
    """Parse a cuRobo YAML file. A repeated key is a warning, not an error: cuRobo loads its
    configs with PyYAML, which keeps the last value (its own ``franka.yml`` repeats
    ``usd_flip_joints``), so the last value is used here too."""
    doc = parse_yaml(read_text(path), str(path))
    rep = Reporter(doc.path, node_positions(doc.root))
    for dup in doc.duplicates:
        rep.report(
            "convert-duplicate-key",
            f"key '{dup.key_path}' appears more than once (first on line {dup.first_line}); "
            "cuRobo's YAML loader keeps the last value, and so does this conversion",
            dup.key_path,
            line=dup.line,
        )
    return doc, rep


def _is_num(v: Any) -> TypeGuard[float]:
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)


def read_curobo(path: str | os.PathLike[str], tree: RobotTree, draft: Draft | None = None) -> Draft:
    """Map a cuRobo (or Lula) robot YAML onto a :class:`Draft`."""
    d = draft or Draft()
    doc, rep = _load(path)
    check_shape(doc.root, CUROBO_FILE, path=doc.path, error=SourceError)
    data = to_python(doc.root)
    try:
        layout = detect_layout(data)
    except SourceError as e:
        raise SourceError(e.message, path=doc.path, line=1) from None
    if layout == "lula":
        _read_lula(data, tree, d, rep)
    else:
        if "robot_cfg" in data:
            prefix = "robot_cfg.kinematics"
            for k in data["robot_cfg"]:
                if k != "kinematics":
                    rep.report(
                        "convert-dropped-key",
                        f"robot_cfg.{k} has no XRDF equivalent; dropped",
                        f"robot_cfg.{k}",
                    )
        else:
            prefix = "kinematics"
        for k in data:
            if k not in ("robot_cfg", "kinematics"):
                rep.report("convert-dropped-key", f"'{k}' has no XRDF equivalent; dropped", k)
        kin = _kinematics(data)
        assert kin is not None
        _read_kinematics(kin, layout, tree, d, rep, prefix, Path(doc.path))
    d.diagnostics.extend(rep.diagnostics)
    return d


def _read_kinematics(
    kin: Mapping[str, Any],
    layout: str,
    tree: RobotTree,
    d: Draft,
    rep: Reporter,
    prefix: str,
    config_path: Path,
) -> None:
    def kp(*parts: object) -> str:
        return ".".join([prefix, *(str(p) for p in parts)])

    for key in kin:
        if key not in SILENT_KEYS and key not in HANDLED_KEYS and not str(key).startswith("usd"):
            rep.report(
                "convert-dropped-key",
                f"'{key}' has no XRDF equivalent; dropped",
                kp(key),
            )

    # extra links first: they add frames that the rest may refer to
    frames = list(tree.links)
    extra = kin.get("extra_links") or {}
    if not isinstance(extra, Mapping):
        raise SourceError(
            "extra_links must be a mapping", path=rep.path, line=rep.position(kp("extra_links"))[0]
        )
    for name, spec in extra.items():
        w = kp("extra_links", name)
        if not isinstance(spec, Mapping):
            raise SourceError(
                f"extra_links.{name} must be a mapping", path=rep.path, line=rep.position(w)[0]
            )
        parent = str(spec.get("parent_link_name", ""))
        link = str(spec.get("link_name") or name)
        if not known_frame(parent, frames, rep, f"{w}.parent_link_name", "extra link parent"):
            continue
        ft = spec.get("fixed_transform") or [0, 0, 0, 1, 0, 0, 0]
        if not (isinstance(ft, list) and len(ft) == 7 and all(_is_num(v) for v in ft)):
            raise SourceError(
                f"extra_links.{name}.fixed_transform must be [x, y, z, qw, qx, qy, qz]",
                path=rep.path,
                line=rep.position(f"{w}.fixed_transform")[0],
            )
        jt = str(spec.get("joint_type", "FIXED"))
        if jt.upper() != "FIXED":
            rep.report(
                "convert-dropped-key",
                f"extra link '{name}' has joint_type '{jt}'; XRDF add_frame is always FIXED",
                f"{w}.joint_type",
            )
        if link in frames:
            rep.report(
                "convert-duplicate-frame",
                f"extra link '{link}' already exists in the URDF; not added",
                w,
            )
            continue
        x, y, z, qw, qx, qy, qz = (float(v) for v in ft)
        d.modifiers.append(
            AddFrame(
                frame_name=link,
                parent_frame_name=parent,
                joint_name=str(spec.get("joint_name") or f"{link}_joint"),
                position=(x, y, z),
                orientation=Orientation.from_wxyz(qw, qx, qy, qz),
                joint_type="FIXED",
            )
        )
        frames.append(link)

    base = kin.get("base_link")
    base_ok = base is not None and known_frame(str(base), frames, rep, kp("base_link"), "base_link")
    if base_ok:  # written even when it is the URDF root, as cuRobo's own XRDFs do
        d.modifiers.insert(0, SetBaseFrame(str(base)))

    # tool frames
    tools: list[tuple[str, str]] = []
    if "tool_frames" in kin and kin["tool_frames"] is not None:
        tf = kin["tool_frames"]
        tf = tf if isinstance(tf, list) else [tf]
        tools += [(str(t), kp("tool_frames", f"[{i}]")) for i, t in enumerate(tf)]
    if kin.get("ee_link"):
        tools.insert(0, (str(kin["ee_link"]), kp("ee_link")))
    for i, t in enumerate(kin.get("link_names") or []):
        tools.append((str(t), kp("link_names") + f"[{i}]"))
    for t, where in tools:
        if known_frame(t, frames, rep, where, "tool frame") and t not in d.tool_frames:
            d.tool_frames.append(t)

    # c-space
    cs = kin.get("cspace") or {}
    if not isinstance(cs, Mapping):
        raise SourceError(
            "cspace must be a mapping", path=rep.path, line=rep.position(kp("cspace"))[0]
        )
    for key in cs:
        if key not in CSPACE_KEYS:
            rep.report(
                "convert-dropped-key",
                f"cspace.{key} has no XRDF equivalent; dropped",
                kp("cspace", key),
            )
    names = [str(n) for n in (cs.get("joint_names") or [])]
    locks = kin.get("lock_joints") or {}
    if not isinstance(locks, Mapping):
        raise SourceError(
            "lock_joints must be a mapping", path=rep.path, line=rep.position(kp("lock_joints"))[0]
        )
    default_key = "default_joint_position" if "default_joint_position" in cs else "retract_config"
    defaults = cs.get(default_key)
    accel = cs.get("max_acceleration")
    jerk = cs.get("max_jerk")

    def per_joint(value: Any, key: str) -> dict[str, float]:
        if value is None:
            return {}
        if _is_num(value):
            return {n: float(value) for n in names}
        if isinstance(value, list) and all(_is_num(v) for v in value):
            if len(value) != len(names):
                raise SourceError(
                    f"cspace.{key} has {len(value)} values for {len(names)} joints",
                    path=rep.path,
                    line=rep.position(kp("cspace", key))[0],
                )
            return {n: float(v) for n, v in zip(names, value, strict=True)}
        raise SourceError(
            f"cspace.{key} must be a number or a list of numbers",
            path=rep.path,
            line=rep.position(kp("cspace", key))[0],
        )

    acc_map = per_joint(accel, "max_acceleration")
    jerk_map = per_joint(jerk, "max_jerk")
    def_map = per_joint(defaults, default_key) if isinstance(defaults, list) else {}
    if defaults is not None and not isinstance(defaults, list):
        raise SourceError(
            f"cspace.{default_key} must be a list",
            path=rep.path,
            line=rep.position(kp("cspace", default_key))[0],
        )

    cspace: list[str] = []
    for i, n in enumerate(names):
        where = kp("cspace", "joint_names") + f"[{i}]"
        j = tree.joints.get(n)
        if j is None:
            rep.report(
                "convert-unknown-joint",
                f"c-space joint '{n}' is not in the URDF{did_you_mean(n, tree.joints)}; dropped",
                where,
            )
            continue
        if n in locks:
            continue
        if not j.is_actuated:
            rep.report(
                "convert-dropped-joint",
                f"c-space joint '{n}' is {'a mimic' if j.is_mimic else j.type} joint; "
                "XRDF c-space holds only actuated joints; dropped",
                where,
            )
            continue
        cspace.append(n)
    d.cspace = cspace
    for n in cspace:
        if n in acc_map:
            d.acceleration[n] = acc_map[n]
        if n in jerk_map:
            d.jerk[n] = jerk_map[n]
        if n in def_map:
            d.defaults[n] = def_map[n]
    for n, v in locks.items():
        where = kp("lock_joints", n)
        j = tree.joints.get(str(n))
        if j is None:
            rep.report(
                "convert-unknown-joint",
                f"locked joint '{n}' is not in the URDF{did_you_mean(str(n), tree.joints)}; "
                "dropped",
                where,
            )
        elif not _is_num(v):
            raise SourceError(
                f"lock_joints.{n} must be a number", path=rep.path, line=rep.position(where)[0]
            )
        elif j.is_actuated:
            d.defaults[str(n)] = float(v)
        else:
            rep.report(
                "convert-dropped-joint-value",
                f"locked joint '{n}' is not actuated; its value is not written",
                where,
                severity=Severity.INFO,
            )

    # spheres
    spheres_value = kin.get("collision_spheres")
    raw_spheres: Mapping[str, Any] | None = None
    srep = rep
    sprefix = kp("collision_spheres")
    if isinstance(spheres_value, str):
        sphere_file = _find_spheres_file(spheres_value, config_path, rep, kp("collision_spheres"))
        sdoc, srep = _load(sphere_file)
        sdata = to_python(sdoc.root)
        if not isinstance(sdata, Mapping) or not isinstance(
            sdata.get("collision_spheres"), Mapping
        ):
            raise SourceError(
                "a cuRobo spheres file needs a top-level 'collision_spheres' mapping",
                path=sdoc.path,
                line=1,
            )
        raw_spheres = sdata["collision_spheres"]
        sprefix = "collision_spheres"
    elif isinstance(spheres_value, Mapping):
        raw_spheres = spheres_value
    elif spheres_value is not None:
        raise SourceError(
            "collision_spheres must be a file path or a mapping of link → spheres",
            path=rep.path,
            line=rep.position(kp("collision_spheres"))[0],
        )
    coll_links = kin.get("collision_link_names")
    allowed = None if coll_links is None else {str(c) for c in coll_links}
    if raw_spheres is not None:
        d.spheres = _read_sphere_map(raw_spheres, frames, srep, sprefix, allowed)
        if srep is not rep:
            d.diagnostics.extend(srep.diagnostics)
        for i, c in enumerate(coll_links or []):
            if str(c) not in frames:
                known_frame(
                    str(c), frames, rep, kp("collision_link_names") + f"[{i}]", "collision link"
                )
    extra_spheres = kin.get("extra_collision_spheres") or {}
    if isinstance(extra_spheres, Mapping):
        for link, n in extra_spheres.items():
            rep.report(
                "convert-placeholder-spheres",
                f"extra_collision_spheres reserves {n} placeholder sphere(s) on '{link}' for "
                "attached objects (cuRobo gives them a negative radius); XRDF has no "
                "equivalent, so they are not emitted",
                kp("extra_collision_spheres", link),
            )

    # buffers
    sphere_frames = list((d.spheres or {}).keys())
    buf = kin.get("collision_sphere_buffer")
    if _is_num(buf):
        if float(buf) != 0.0:
            d.world_buffer.update({f: float(buf) for f in sphere_frames})
    elif isinstance(buf, Mapping):
        for f, v in buf.items():
            w = kp("collision_sphere_buffer", f)
            ok = known_frame(str(f), frames, rep, w, "collision_sphere_buffer")
            if ok and _is_num(v) and float(v) != 0.0:
                d.world_buffer[str(f)] = float(v)
    elif buf is not None:
        raise SourceError(
            "collision_sphere_buffer must be a number or a mapping",
            path=rep.path,
            line=rep.position(kp("collision_sphere_buffer"))[0],
        )
    sbuf = kin.get("self_collision_buffer") or {}
    if isinstance(sbuf, Mapping):
        for f, v in sbuf.items():
            w = kp("self_collision_buffer", f)
            ok = known_frame(str(f), frames, rep, w, "self_collision_buffer")
            if ok and _is_num(v) and float(v) != 0.0:
                d.self_buffer[str(f)] = float(v)
    elif _is_num(sbuf) and float(sbuf) != 0.0:
        d.self_buffer.update({f: float(sbuf) for f in sphere_frames})

    ign = kin.get("self_collision_ignore") or {}
    if not isinstance(ign, Mapping):
        raise SourceError(
            "self_collision_ignore must be a mapping of link → [links]",
            path=rep.path,
            line=rep.position(kp("self_collision_ignore"))[0],
        )
    for a, others in ign.items():
        w = kp("self_collision_ignore", a)
        if not known_frame(str(a), frames, rep, w, "self_collision_ignore key"):
            continue
        for i, b in enumerate(others or []):
            if known_frame(str(b), frames, rep, f"{w}[{i}]", f"ignored with '{a}'"):
                d.add_ignore(str(a), str(b))


def _find_spheres_file(value: str, config_path: Path, rep: Reporter, where: str) -> Path:
    base = config_path.parent
    candidates = [base / value, base.parent / value, base / "spheres" / Path(value).name]
    for c in candidates:
        if c.is_file():
            return c
    raise SourceError(
        f"collision_spheres file '{value}' not found (looked in "
        f"{', '.join(str(c.parent) for c in candidates)})",
        path=rep.path,
        line=rep.position(where)[0],
    )


def _read_sphere_map(
    raw: Mapping[str, Any],
    frames: list[str],
    rep: Reporter,
    prefix: str,
    allowed: set[str] | None,
) -> dict[str, list[Sphere]]:
    out: dict[str, list[Sphere]] = {}
    # cuRobo looks spheres up only for collision_link_names, so a sphere file shared between
    # robots (cuRobo's iiwa.yml uses spheres/iiwa_allegro.yml) may name links of another robot:
    # those are neither unknown-link mistakes nor lost spheres; one info note covers them.
    foreign: list[str] = []
    for link, items in raw.items():
        link = str(link)
        w = f"{prefix}.{link}"
        if allowed is not None and link not in allowed and link not in frames:
            foreign.append(link)
            continue
        if not known_frame(link, frames, rep, w, "collision spheres"):
            continue
        if allowed is not None and link not in allowed:
            rep.report(
                "convert-unused-spheres",
                f"spheres on '{link}' are not used by cuRobo ('{link}' is not in "
                "collision_link_names); dropped",
                w,
            )
            continue
        spheres = _spheres(items, rep, w)
        if spheres:
            out.setdefault(link, []).extend(spheres)
    if foreign:
        shown = ", ".join(foreign[:5]) + (
            f" and {len(foreign) - 5} more" if len(foreign) > 5 else ""
        )
        rep.report(
            "convert-unused-spheres",
            f"spheres on {len(foreign)} link(s) that are neither in the URDF nor in "
            f"collision_link_names ({shown}) are ignored: cuRobo never reads them (a sphere "
            "file shared with another robot?)",
            f"{prefix}.{foreign[0]}",
            severity=Severity.INFO,
        )
    return out


def _spheres(items: Any, rep: Reporter, where: str) -> list[Sphere]:
    if items is None:
        return []
    if not isinstance(items, list):
        raise SourceError(
            "spheres of a link must be a list", path=rep.path, line=rep.position(where)[0]
        )
    out = []
    for i, s in enumerate(items):
        w = f"{where}[{i}]"
        c = s.get("center") if isinstance(s, Mapping) else None
        r = s.get("radius") if isinstance(s, Mapping) else None
        if not (isinstance(c, list) and len(c) == 3 and all(_is_num(v) for v in c) and _is_num(r)):
            raise SourceError(
                "a sphere needs center: [x, y, z] and a numeric radius",
                path=rep.path,
                line=rep.position(w)[0],
            )
        if r <= 0:
            rep.report(
                "convert-placeholder-spheres",
                f"sphere {i} on '{where.rsplit('.', 1)[-1]}' has radius {r} (a cuRobo "
                "placeholder); not emitted",
                f"{w}.radius",
            )
            continue
        out.append(Sphere((float(c[0]), float(c[1]), float(c[2])), float(r)))
    return out


LULA_HANDLED = {
    "cspace",
    "default_q",
    "acceleration_limits",
    "jerk_limits",
    "collision_spheres",
    "root_link",
    "cspace_to_urdf_rules",
    "api_version",
}


def _read_lula(data: Mapping[str, Any], tree: RobotTree, d: Draft, rep: Reporter) -> None:
    for key in data:
        if key not in LULA_HANDLED:
            rep.report("convert-dropped-key", f"'{key}' has no XRDF equivalent; dropped", key)
    frames = list(tree.links)
    root = data.get("root_link")
    root_ok = bool(root) and known_frame(str(root), frames, rep, "root_link", "root_link")
    if root_ok and str(root) != tree.root:
        d.modifiers.append(SetBaseFrame(str(root)))
    names = [str(n) for n in data.get("cspace") or []]
    cspace = []
    for i, n in enumerate(names):
        if n not in tree.joints:
            rep.report(
                "convert-unknown-joint",
                f"c-space joint '{n}' is not in the URDF{did_you_mean(n, tree.joints)}; dropped",
                f"cspace[{i}]",
            )
        else:
            cspace.append(n)
    d.cspace = cspace
    for key, target in (
        ("default_q", d.defaults),
        ("acceleration_limits", d.acceleration),
        ("jerk_limits", d.jerk),
    ):
        vals = data.get(key)
        if vals is None:
            continue
        if not (isinstance(vals, list) and len(vals) == len(names) and all(map(_is_num, vals))):
            raise SourceError(
                f"{key} must be a list of {len(names)} numbers (one per cspace joint)",
                path=rep.path,
                line=rep.position(key)[0],
            )
        for n, v in zip(names, vals, strict=True):
            if n in cspace:
                target[n] = float(v)
    for i, rule in enumerate(data.get("cspace_to_urdf_rules") or []):
        if isinstance(rule, Mapping) and rule.get("rule") == "fixed" and _is_num(rule.get("value")):
            n = str(rule.get("name"))
            if tree.is_actuated(n):
                d.defaults[n] = float(rule["value"])
            else:
                rep.report(
                    "convert-unknown-joint",
                    f"cspace_to_urdf_rules fixes '{n}', which is not an actuated URDF joint"
                    f"{did_you_mean(n, tree.joints)}; dropped",
                    f"cspace_to_urdf_rules[{i}]",
                )
    spheres = data.get("collision_spheres")
    if isinstance(spheres, list):
        out: dict[str, list[Sphere]] = {}
        for i, entry in enumerate(spheres):
            if not isinstance(entry, Mapping):
                continue
            for link, items in entry.items():
                w = f"collision_spheres[{i}].{link}"
                if known_frame(str(link), frames, rep, w, "collision spheres"):
                    out.setdefault(str(link), []).extend(_spheres(items, rep, w))
        d.spheres = {k: v for k, v in out.items() if v}
