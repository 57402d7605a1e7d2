"""What cuRobo builds from a robot config or an XRDF, as a plain value, for comparing the two.

Written from the reader facts in docs/format.md ("Who reads an XRDF") and the config mapping in
docs/convert.md, rule by rule (no cuRobo code), and checked against cuRobo's own loader on real
robots by ``benchmarks/check_curobo_loader.py``: the tests convert a real cuRobo config with
``xrdf convert`` and check that cuRobo, reading our XRDF, would build the robot the config
describes. :func:`from_xrdf` raises :class:`CuroboRejects` where cuRobo's loader raises; it
reproduces what cuRobo silently does (defaults in URDF order, joints in kinematic-tree order).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
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


#: The radius cuRobo (main) gives an attached-object slot (``extra_collision_spheres``; 0.7.x
#: used -10). Any radius <= -1 is such a slot; the model writes every slot with this radius.
SLOT = -100.0

#: The ``joint_type`` names cuRobo's ``add_frame`` accepts (its JointType members).
JOINT_TYPES = frozenset(
    f"{a}_{k}{s}" for a in "XYZ" for k in ("PRISM", "ROT") for s in ("", "_NEG")
) | {"FIXED"}


@dataclass(frozen=True)
class _Urdf:
    controlled: tuple[str, ...]  # non-fixed, non-mimic joints in URDF order
    links: frozenset[str]
    root: str
    #: child link -> (parent link, the joint that moves it: a mimic's leader, None when fixed)
    up: Mapping[str, tuple[str, str | None]]
    #: moving joints whose axis is not along x, y or z (cuRobo raises on them in its tree)
    tilted: frozenset[str]
    #: joints whose URDF velocity or effort limit is <= 0 or whose lower limit is not below the
    #: upper:
    #: cuRobo raises when one of them is a joint it plans for
    stuck: frozenset[str]


def _urdf(path: Path) -> _Urdf:
    u = load_urdf(path)
    joints = joints_of(u)
    controlled = tuple(n for n, j in joints.items() if j.type != "fixed" and not j.is_mimic)
    up = {
        j.child: (j.parent, None if j.type == "fixed" else (j.mimic_joint or n))
        for n, j in joints.items()
    }
    tilted = frozenset(
        j.child for j in joints.values() if j.type != "fixed" and 1.0 not in map(abs, j.axis)
    )
    stuck = frozenset(
        n
        for n, j in joints.items()
        if (j.velocity is not None and j.velocity <= 0)
        or (j.effort is not None and j.effort <= 0)
        or (j.type != "continuous" and None not in (j.lower, j.upper) and j.lower >= j.upper)
    )
    return _Urdf(controlled, frozenset(links_of(u)), root_link(u), up, tilted, stuck)


def tree(
    urdf: _Urdf, base: str, targets: list[str], extra: Mapping[str, str]
) -> tuple[list[str], list[str]]:
    """The links and the moving joints cuRobo meets building its tree, in its order: the chain
    from ``base`` to ``targets[0]`` (the end effector), then the chains to the other targets
    (tool frames, then sphere frames, then added frames' parents). A mimic follower counts as
    its leader. ``extra`` maps an added frame to its parent. Raises when a target is not below
    ``base`` or a joint on the way moves about an axis cuRobo has no joint type for."""
    seen: list[str] = [base]
    joints: list[str] = []
    for target in targets:
        chain, link = [], target
        while link != base:
            chain.append(link)
            if link in extra:
                link = extra[link]
            elif link in urdf.up:
                link = urdf.up[link][0]
            else:
                raise CuroboRejects(f"Link {target} not found in parent map (below {base})")
        for link in reversed(chain):
            if link in seen:
                continue
            seen.append(link)
            if link in urdf.tilted:
                raise CuroboRejects(f"the joint moving {link} has an axis not along x, y or z")
            moved_by = None if link in extra else urdf.up[link][1]
            if moved_by is not None and moved_by not in joints:
                joints.append(moved_by)
    return seen, joints


def _ee(tools: list[str], links: list[str], tree_joints: list[str], locked: Iterable[str]) -> str:
    """cuRobo's first tool frame: with no joint of its tree locked it reorders the tool frames
    as it met them building the tree (an ancestor of ``tools[0]`` then comes first); locking a
    joint of the tree restores the order given."""
    if any(j in tree_joints for j in locked):
        return tools[0]
    return min(tools, key=links.index)


def _limits_ok(urdf: _Urdf, active: tuple[str, ...], *limits: Mapping[str, float] | None) -> None:
    """Raise where cuRobo's joint limits check does: a velocity, effort, position, acceleration
    or jerk range that is empty for a joint it plans for."""
    bad = [j for j in active if j in urdf.stuck]
    bad += [j for lim in limits if lim for j in active if lim.get(j, 1.0) <= 0]
    if bad:
        raise CuroboRejects(f"lower limits must be less than upper limits: {bad}")


def _active(tree: list[str], cspace: list[str], locked: Mapping[str, float]) -> tuple[str, ...]:
    """The joints cuRobo plans for, in its tree order; raises where its c-space check does."""
    if len(set(cspace)) != len(cspace):
        raise CuroboRejects("cspace contains duplicate joint names")
    outside = [j for j in cspace if j not in tree and j not in locked]
    if outside:
        raise CuroboRejects(
            f"cspace contains joints that are not active in the configured tree and are not "
            f"explicitly locked: {outside}"
        )
    missing = [j for j in tree if j not in cspace and j not in locked]
    if missing:
        raise CuroboRejects(f"cspace is missing active tree joints: {missing}")
    unknown = [j for j in locked if j not in tree and j not in cspace]
    if unknown:
        raise CuroboRejects(f"lock_joints contains joints not in the tree or cspace: {unknown}")
    return tuple(j for j in tree if j not in locked)


def _targets(tools: list[str], sphere_links: list[str], extra: Mapping[str, str]) -> list[str]:
    out = list(tools)
    out += [f for f in sphere_links if f not in out]
    out += [p for p in extra.values() if p not in out]
    return out


def _mask(ignore: set[frozenset[str]], spheres: Spheres, built: bool) -> frozenset[frozenset[str]]:
    """The ignored pairs cuRobo acts on: both frames carry spheres (either direction). When it
    builds its collision model (``built``: some frame is named for spheres) and no pair of
    spheres on two frames is left to check, its loader divides by zero."""
    mask = frozenset(p for p in ignore if len(p) == 2 and all(f in spheres for f in p))
    pairs = {frozenset((a, b)) for a in spheres for b in spheres if a != b}
    if built and not pairs - mask:
        raise CuroboRejects("no sphere pair left to check: ZeroDivisionError")
    return mask


def _per_joint(value: Any, names: list[str], active: list[str]) -> dict[str, float] | None:
    if value is None:
        return None
    if isinstance(value, (int, float)):
        return {n: float(value) for n in names if n in active}
    return {n: float(v) for n, v in zip(names, value, strict=True) if n in active}


def _nonzero(buffers: Mapping[str, Any]) -> dict[str, float]:
    return {k: float(v) for k, v in buffers.items() if float(v) != 0.0}


def _radius(r: Any) -> float:
    return SLOT if float(r) <= -1.0 else float(r)


def _sphere_tuple(items: list[Mapping[str, Any]]) -> tuple[tuple[tuple[float, ...], float], ...]:
    return tuple((tuple(float(c) for c in s["center"]), _radius(s["radius"])) for s in items)


def from_config(config: Path, urdf_path: Path) -> CuroboRobot:
    """The robot a cuRobo config (classic or 2.0 layout) describes."""
    urdf = _urdf(urdf_path)
    kin = yaml.safe_load(config.read_text())["robot_cfg"]["kinematics"]
    cs = kin["cspace"]
    names = list(cs["joint_names"])
    locks = kin.get("lock_joints") or {}
    retract = cs.get("default_joint_position", cs.get("retract_config"))
    by_name = dict(zip(names, (float(v) for v in retract), strict=True))
    extra = kin.get("extra_links") or {}
    parents = {e.get("link_name", n): e["parent_link_name"] for n, e in extra.items()}
    frames = urdf.links | set(parents)
    spheres_src = kin.get("collision_spheres") or {}
    if isinstance(spheres_src, str):
        spheres_src = yaml.safe_load((config.parent / spheres_src).read_text())["collision_spheres"]
    spheres_src = dict(spheres_src)
    for link, n in (kin.get("extra_collision_spheres") or {}).items():
        spheres_src[link] = [{"center": [0.0, 0.0, 0.0], "radius": SLOT}] * n  # replaces
    allowed = list(kin.get("collision_link_names") or [])  # none named: no spheres loaded
    spheres: Spheres = {
        link: _sphere_tuple(spheres_src[link]) for link in allowed if spheres_src.get(link)
    }
    buf = kin.get("collision_sphere_buffer") or 0.0
    world = dict.fromkeys(spheres, buf) if isinstance(buf, (int, float)) else buf
    ignore = {
        frozenset((a, b))
        for a, bs in (kin.get("self_collision_ignore") or {}).items()
        for b in bs or ()
        if a in frames and b in frames and a != b
    }
    tools = kin.get("tool_frames") or [kin["ee_link"], *(kin.get("link_names") or [])]
    base = kin.get("base_link") or urdf.root
    links, joints = tree(urdf, base, _targets(tools, allowed, parents), parents)
    active = _active(joints, names, locks)
    acc = _per_joint(cs.get("max_acceleration"), names, list(active))
    jerk = _per_joint(cs.get("max_jerk"), names, list(active))
    _limits_ok(urdf, active, acc, jerk)
    return CuroboRobot(
        active_joints=active,
        locked={j: float(locks.get(j, 0.0)) for j in urdf.controlled if j not in active},
        defaults={j: by_name[j] for j in active},
        acceleration=acc,
        jerk=jerk,
        base_link=base,
        ee_link=_ee(tools, links, joints, locks),
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
        ignore=_mask(ignore, spheres, bool(allowed) and kin.get("collision_spheres") is not None),
    )


def _require(data: Mapping[str, Any], key: str) -> Any:
    if key not in data:
        raise CuroboRejects(f"{key} key not found in xrdf")
    return data[key]


@dataclass
class _Collision:
    spheres: Spheres
    frames: list[str]  # every frame the geometry group names (cuRobo builds a chain to each)
    world: Mapping[str, Any]
    self_buffer: Mapping[str, Any]
    ignore: set[frozenset[str]]


def _collision(x: Mapping[str, Any]) -> _Collision:
    """The collision part of an XRDF as cuRobo reads it; raises where it raises."""
    if "collision" not in x:
        # its converter only warns, but its robot loader then looks up collision_spheres
        raise CuroboRejects("no collision section: KeyError 'collision_spheres'")
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
    mask = _require(sc, "ignore")
    self_buffer = sc.get("buffer_distance") or {}
    if raw:  # the checks of its collision-model builder
        if not isinstance(mask, Mapping) or any(v is None for v in mask.values()):
            raise CuroboRejects("self_collision.ignore must map each frame to a list")
        if not isinstance(self_buffer, Mapping):
            raise CuroboRejects("a scalar self_collision buffer_distance cannot be copied")
    ignore = {frozenset((a, b)) for a, bs in (mask or {}).items() for b in bs or ()}
    return _Collision(spheres, list(raw), world, self_buffer, ignore)


def _added_frames(x: Mapping[str, Any], base: str) -> tuple[str, dict[str, Any]]:
    """The base frame and the added frames (name -> (parent, joint, transform)) of ``x``."""
    extra: dict[str, Any] = {}
    for m in x.get("modifiers") or []:
        if "set_base_frame" in m:
            base = m["set_base_frame"]
        elif "add_frame" in m:
            f = m["add_frame"]
            if _require(f, "joint_type") not in JOINT_TYPES:
                raise CuroboRejects(f"joint_type {f['joint_type']!r}: KeyError")
            t = f["fixed_transform"]
            extra[f["frame_name"]] = (
                f["parent_frame_name"],
                f["joint_name"],
                tuple(
                    float(v)
                    for v in [*t["position"], t["orientation"]["w"], *t["orientation"]["xyz"]]
                ),
            )
    return base, extra


def from_xrdf(text: str, urdf_path: Path) -> CuroboRobot:
    """The robot cuRobo's XRDF loader (0.7.x and main) builds from ``text``."""
    urdf = _urdf(urdf_path)
    x = yaml.safe_load(text)
    if _require(x, "format") != "xrdf":
        raise CuroboRejects("format is not xrdf")
    if not isinstance(_require(x, "format_version"), (int, float)):
        raise CuroboRejects("format_version is compared with 1.0 as a number")
    col = _collision(x)
    tools = _require(x, "tool_frames")
    cs = _require(x, "cspace")
    names = list(_require(cs, "joint_names"))
    defaults = _require(x, "default_joint_positions")
    # cuRobo's bug: the retract values are collected in URDF order, paired in c-space order
    in_urdf_order = [float(defaults.get(j, 0.0)) for j in urdf.controlled if j in names]
    by_name = dict(zip(names, in_urdf_order, strict=False))
    base, extra = _added_frames(x, urdf.root)
    locked = {j: float(defaults.get(j, 0.0)) for j in urdf.controlled if j not in names}
    parents = {k: v[0] for k, v in extra.items()}
    links, joints = tree(urdf, base, _targets(tools, col.frames, parents), parents)
    active = _active(joints, [*names, *locked], locked)
    acc = dict(zip(names, map(float, _require(cs, "acceleration_limits")), strict=True))
    jerk = dict(zip(names, map(float, _require(cs, "jerk_limits")), strict=True))
    _limits_ok(urdf, active, acc, jerk)
    return CuroboRobot(
        active_joints=active,
        locked=locked,
        defaults={j: by_name[j] for j in active if j in by_name},
        acceleration={j: acc[j] for j in active},
        jerk={j: jerk[j] for j in active},
        base_link=base,
        ee_link=_ee(tools, links, joints, locked),
        link_names=frozenset(tools),
        extra_links=extra,
        spheres=col.spheres,
        world_buffer=_nonzero({k: v for k, v in col.world.items() if k in col.spheres}),
        self_buffer=_nonzero(col.self_buffer),
        ignore=_mask(col.ignore, col.spheres, bool(col.frames)),
    )


def loads_as_written(text: str, urdf_path: Path) -> bool:
    """True when cuRobo loads ``text`` without raising and builds the robot it says: no
    defaults scrambled by the URDF-order bug."""
    try:
        robot = from_xrdf(text, urdf_path)
    except (CuroboRejects, KeyError, TypeError, IndexError):
        return False
    x = yaml.safe_load(text)
    defaults = x.get("default_joint_positions") or {}
    return all(robot.defaults[j] == float(defaults.get(j, 0.0)) for j in robot.active_joints)
