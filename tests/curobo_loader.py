"""What cuRobo builds from a robot config or an XRDF, as a plain value, for comparing the two.

Written from the reader facts in docs/format.md ("Who reads an XRDF") and the config mapping in
docs/convert.md, rule by rule (no cuRobo code): the tests convert a real cuRobo config with
``xrdf convert`` and check that cuRobo, reading our XRDF, would build the robot the config
describes. :func:`from_xrdf` raises :class:`CuroboRejects` where cuRobo's loader raises; it
reproduces what cuRobo silently does (2.0 → no collision, defaults in URDF order).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import yaml

from xrdf_tools.robot.urdf_source import joints_of, links_of, load_urdf, root_link

Spheres = dict[str, tuple[tuple[tuple[float, float, float], float], ...]]


class CuroboRejects(Exception):
    """cuRobo's loader raises on this input."""


@dataclass(frozen=True)
class CuroboRobot:
    active_joints: tuple[str, ...]
    locked: Mapping[str, float]  # controlled URDF joints outside the c-space -> held value
    defaults: Mapping[str, float]  # active joint -> retract value, as cuRobo pairs them
    #: None where the config gives no value (the converter then fills a reported default)
    acceleration: Mapping[str, float] | None
    jerk: Mapping[str, float] | None
    base_link: str
    ee_link: str
    link_names: frozenset[str]  # frames cuRobo computes poses for (ee included)
    extra_links: Mapping[str, tuple[str, str, tuple[float, ...]]]
    spheres: Spheres  # every sphere cuRobo loads (attached-object slots included)
    world_buffer: Mapping[str, float]  # sphere link -> buffer (0 left out)
    self_buffer: Mapping[str, float]
    ignore: frozenset[frozenset[str]]


@dataclass(frozen=True)
class _Urdf:
    controlled: tuple[str, ...]  # non-fixed, non-mimic joints in URDF order
    links: frozenset[str]
    root: str


def _urdf(path: Path) -> _Urdf:
    u = load_urdf(path)
    joints = joints_of(u)
    controlled = tuple(n for n, j in joints.items() if j.type != "fixed" and not j.is_mimic)
    return _Urdf(controlled, frozenset(links_of(u)), root_link(u))


def _per_joint(value: Any, names: list[str], active: list[str]) -> dict[str, float] | None:
    if value is None:
        return None
    if isinstance(value, (int, float)):
        return {n: float(value) for n in names if n in active}
    return {n: float(v) for n, v in zip(names, value, strict=True) if n in active}


def _nonzero(buffers: Mapping[str, Any]) -> dict[str, float]:
    return {k: float(v) for k, v in buffers.items() if float(v) != 0.0}


def _sphere_tuple(items: list[Mapping[str, Any]]) -> tuple[tuple[tuple[float, ...], float], ...]:
    return tuple((tuple(float(c) for c in s["center"]), float(s["radius"])) for s in items)


def from_config(config: Path, urdf_path: Path) -> CuroboRobot:
    """The robot a cuRobo config (classic or 2.0 layout) describes."""
    urdf = _urdf(urdf_path)
    kin = yaml.safe_load(config.read_text())["robot_cfg"]["kinematics"]
    cs = kin["cspace"]
    names = list(cs["joint_names"])
    locks = kin.get("lock_joints") or {}
    active = [n for n in names if n not in locks]
    retract = cs.get("default_joint_position", cs.get("retract_config"))
    by_name = dict(zip(names, (float(v) for v in retract), strict=True))
    extra = kin.get("extra_links") or {}
    frames = urdf.links | {e.get("link_name", n) for n, e in extra.items()}
    spheres_src = kin.get("collision_spheres") or {}
    if isinstance(spheres_src, str):
        spheres_src = yaml.safe_load((config.parent / spheres_src).read_text())["collision_spheres"]
    allowed = kin.get("collision_link_names")
    spheres: Spheres = {}
    for link, items in spheres_src.items():
        if link in frames and (allowed is None or link in allowed) and items:
            spheres[link] = spheres.get(link, ()) + _sphere_tuple(items)
    for link, n in (kin.get("extra_collision_spheres") or {}).items():
        if n:
            spheres[link] = spheres.get(link, ()) + (((0.0, 0.0, 0.0), -10.0),) * n
    buf = kin.get("collision_sphere_buffer") or 0.0
    world = dict.fromkeys(spheres, buf) if isinstance(buf, (int, float)) else buf
    ignore = {
        frozenset((a, b))
        for a, bs in (kin.get("self_collision_ignore") or {}).items()
        for b in bs or ()
        if a in frames and b in frames and a != b
    }
    tools = kin.get("tool_frames") or [kin["ee_link"], *(kin.get("link_names") or [])]
    return CuroboRobot(
        active_joints=tuple(active),
        locked={j: float(locks.get(j, 0.0)) for j in urdf.controlled if j not in active},
        defaults={j: by_name[j] for j in active},
        acceleration=_per_joint(cs.get("max_acceleration"), names, active),
        jerk=_per_joint(cs.get("max_jerk"), names, active),
        base_link=kin.get("base_link") or urdf.root,
        ee_link=tools[0],
        link_names=frozenset(tools),
        extra_links={
            e.get("link_name", n): (
                e["parent_link_name"],
                e["joint_name"],
                tuple(float(v) for v in e["fixed_transform"]),
            )
            for n, e in extra.items()
        },
        spheres=spheres,
        world_buffer=_nonzero({k: v for k, v in world.items() if k in spheres}),
        self_buffer=_nonzero(kin.get("self_collision_buffer") or {}),
        ignore=frozenset(ignore),
    )


def _require(data: Mapping[str, Any], key: str) -> Any:
    if key not in data:
        raise CuroboRejects(f"{key} key not found in xrdf")
    return data[key]


def from_xrdf(text: str, urdf_path: Path) -> CuroboRobot:
    """The robot cuRobo's XRDF loader (0.7.x and main) builds from ``text``."""
    urdf = _urdf(urdf_path)
    x = yaml.safe_load(text)
    if _require(x, "format") != "xrdf":
        raise CuroboRejects("format is not xrdf")
    if not isinstance(_require(x, "format_version"), (int, float)):
        raise CuroboRejects("format_version is compared with 1.0 as a number")
    spheres: Spheres = {}
    world: Mapping[str, Any] = {}
    self_buffer: Mapping[str, Any] = {}
    ignore: set[frozenset[str]] = set()
    if "collision" in x:  # a 2.0 file has world_collision: no collision at all
        group = _require(x["collision"], "geometry")
        raw = _require(x["geometry"][group], "spheres")
        spheres = {f: _sphere_tuple(items) for f, items in raw.items() if items}
        buf = x["collision"].get("buffer_distance", 0.0)
        if isinstance(buf, int) and not isinstance(buf, bool):
            raise CuroboRejects("a scalar buffer must be a float to be broadcast")
        world = dict.fromkeys(spheres, buf) if isinstance(buf, float) else buf
        sc = _require(x, "self_collision")
        if sc["geometry"] != group:
            raise CuroboRejects("self_collision geometry does not match collision geometry")
        ignore = {frozenset((a, b)) for a, bs in _require(sc, "ignore").items() for b in bs}
        self_buffer = sc.get("buffer_distance") or {}
    tools = _require(x, "tool_frames")
    cs = _require(x, "cspace")
    active = list(_require(cs, "joint_names"))
    defaults = _require(x, "default_joint_positions")
    # cuRobo's bug: the retract values are collected in URDF order, paired in c-space order
    in_urdf_order = [float(defaults.get(j, 0.0)) for j in urdf.controlled if j in active]
    base, extra = urdf.root, {}
    for m in x.get("modifiers") or []:
        if "set_base_frame" in m:
            base = m["set_base_frame"]
        elif "add_frame" in m:
            f = m["add_frame"]
            t = f["fixed_transform"]
            extra[f["frame_name"]] = (
                f["parent_frame_name"],
                f["joint_name"],
                tuple(
                    float(v)
                    for v in [*t["position"], t["orientation"]["w"], *t["orientation"]["xyz"]]
                ),
            )
            _require(f, "joint_type")
    return CuroboRobot(
        active_joints=tuple(active),
        locked={j: float(defaults.get(j, 0.0)) for j in urdf.controlled if j not in active},
        defaults=dict(zip(active, in_urdf_order, strict=False)),
        acceleration=dict(
            zip(active, map(float, _require(cs, "acceleration_limits")), strict=True)
        ),
        jerk=dict(zip(active, map(float, _require(cs, "jerk_limits")), strict=True)),
        base_link=base,
        ee_link=tools[0],
        link_names=frozenset(tools),
        extra_links=extra,
        spheres=spheres,
        world_buffer=_nonzero({k: v for k, v in world.items() if k in spheres}),
        self_buffer=_nonzero(self_buffer),
        ignore=frozenset(p for p in ignore if len(p) == 2),
    )


def loads_as_written(text: str, urdf_path: Path) -> bool:
    """True when cuRobo loads ``text`` without raising and builds the robot it says: no
    collision lost to the version, no defaults scrambled by the URDF-order bug."""
    try:
        robot = from_xrdf(text, urdf_path)
    except (CuroboRejects, KeyError, TypeError, IndexError):
        return False
    x = yaml.safe_load(text)
    if "world_collision" in x and "collision" not in x:
        return False  # collision silently disabled
    defaults = x.get("default_joint_positions") or {}
    return all(robot.defaults[j] == float(defaults.get(j, 0.0)) for j in robot.active_joints)
