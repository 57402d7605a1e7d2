"""Frozen, typed model of an XRDF document (versions 1.0 and 2.0).

The model is version-neutral: ``Xrdf.world_collision`` holds the section spelled ``collision``
in 1.0 and ``world_collision`` in 2.0; ``Xrdf.format_version`` decides how it is written.
Positions of the source file live in ``Xrdf.source`` (excluded from equality).
"""

from __future__ import annotations

from collections import deque
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field, replace
from typing import Literal, TypedDict

from ..util.errors import GeometryGroupError
from ..util.frozen import FrozenMap
from ..util.graph import show_path
from ..util.rotations import quat_from_rpy, unit_quat

Vec3 = tuple[float, float, float]


@dataclass(frozen=True)
class Sphere:
    """A collision sphere: centre in its frame (metres) and radius (metres)."""

    center: Vec3
    radius: float


OrientationForm = Literal["w_xyz", "quaternion", "euler_rpy"]


@dataclass(frozen=True)
class Orientation:
    """Rotation of an added frame, in the form it was written.

    ``w_xyz``: ``{w: w, xyz: [x, y, z]}`` (the 1.0 form). ``quaternion``: ``[w, x, y, z]``.
    ``euler_rpy``: ``[roll, pitch, yaw]`` in radians, URDF convention (R = Rz(y)·Ry(p)·Rx(r)).
    """

    form: OrientationForm
    values: tuple[float, ...]

    @classmethod
    def identity(cls) -> Orientation:
        return cls("w_xyz", (1.0, 0.0, 0.0, 0.0))

    @classmethod
    def from_wxyz(cls, w: float, x: float, y: float, z: float) -> Orientation:
        return cls("w_xyz", (float(w), float(x), float(y), float(z)))

    def as_wxyz(self) -> tuple[float, float, float, float]:
        """Unit quaternion ``(w, x, y, z)`` for any form."""
        if self.form in ("w_xyz", "quaternion"):
            w, x, y, z = self.values
            return unit_quat(w, x, y, z)
        r, p, yaw = self.values
        return unit_quat(*quat_from_rpy(r, p, yaw))


@dataclass(frozen=True)
class AddFrame:
    """``add_frame``: a new frame fixed to ``parent_frame_name`` by joint ``joint_name``."""

    frame_name: str
    parent_frame_name: str
    joint_name: str
    position: Vec3 = (0.0, 0.0, 0.0)
    orientation: Orientation = field(default_factory=Orientation.identity)
    joint_type: str = "FIXED"


@dataclass(frozen=True)
class SetBaseFrame:
    """``set_base_frame``: the named frame becomes the root; everything upstream is pruned."""

    frame: str


@dataclass(frozen=True)
class RemoveMimicAttributes:
    """``remove_mimic_attributes`` (2.0): make a URDF mimic follower an independent joint."""

    joint_name: str
    position_limits: tuple[float, float] | None = None
    velocity_limits: float | None = None


Modifier = AddFrame | SetBaseFrame | RemoveMimicAttributes


@dataclass(frozen=True)
class GeometryGroup:
    """A named group: its own spheres per frame plus the groups it ``clone``s (2.0)."""

    spheres: FrozenMap[str, tuple[Sphere, ...]] = field(default_factory=FrozenMap)
    clone: tuple[str, ...] = ()

    def sphere_count(self) -> int:
        return sum(len(s) for s in self.spheres.values())


@dataclass(frozen=True)
class CollisionSection:
    """``collision`` (1.0) / ``world_collision`` (2.0)."""

    geometry: str
    buffer_distance: FrozenMap[str, float] = field(default_factory=FrozenMap)


@dataclass(frozen=True)
class SelfCollisionSection:
    """``self_collision``: geometry group, per-frame buffers and the ignore mask."""

    geometry: str
    buffer_distance: FrozenMap[str, float] = field(default_factory=FrozenMap)
    ignore: FrozenMap[str, tuple[str, ...]] = field(default_factory=FrozenMap)

    def ignore_pairs(self) -> frozenset[frozenset[str]]:
        """The mask as a symmetric set of unordered frame pairs (self-pairs dropped)."""
        return frozenset(
            frozenset((a, b)) for a, others in self.ignore.items() for b in others if a != b
        )

    def is_ignored(self, a: str, b: str) -> bool:
        return b in self.ignore.get(a, ()) or a in self.ignore.get(b, ())


@dataclass(frozen=True)
class CSpace:
    """C-space joints (order matters) with acceleration and jerk limits in the same order."""

    joint_names: tuple[str, ...]
    acceleration_limits: tuple[float, ...]
    jerk_limits: tuple[float, ...]


@dataclass(frozen=True)
class SourceMap:
    """Where each part of a model came from: ``key_path → (line, col)`` (1-based).

    A model read from a file gets a :class:`~xrdf_tools.yaml.positions.NodePositions`: the
    positions are looked up in the YAML tree when asked for, not listed up front.
    """

    path: str = ""
    positions: Mapping[str, tuple[int, int]] = field(default_factory=FrozenMap)

    def position(self, key_path: str) -> tuple[int | None, int | None]:
        """Position of ``key_path`` or of its nearest recorded ancestor."""
        kp = key_path
        while kp:
            if kp in self.positions:
                return self.positions[kp]
            cut = max(kp.rfind("."), kp.rfind("["))
            kp = kp[:cut] if cut > 0 else ""
        return (None, None)

    def locate(self, key_path: str) -> Location:
        """``path``/``line``/``col`` keywords of an error at ``key_path`` (its nearest recorded
        ancestor; the document's first line when nothing is recorded)."""
        line, col = self.position(key_path) if key_path else (None, None)
        return {
            "path": self.path or None,
            "line": line or (1 if self.path else None),
            "col": col,
        }


class Location(TypedDict):
    """Where an error points: the keywords of :class:`~xrdf_tools.util.errors.XrdfToolsError`."""

    path: str | None
    line: int | None
    col: int | None


@dataclass(frozen=True)
class Xrdf:
    """A whole XRDF document.

    ``None`` means the optional section is absent. ``extra`` keeps unknown top-level keys
    (plain YAML data) so nothing is lost on a round trip.
    """

    format_version: str = "2.0"
    cspace: CSpace | None = None
    modifiers: tuple[Modifier, ...] = ()
    default_joint_positions: FrozenMap[str, float] | None = None
    tool_frames: tuple[str, ...] | None = None
    world_collision: CollisionSection | None = None
    self_collision: SelfCollisionSection | None = None
    geometry: FrozenMap[str, GeometryGroup] | None = None
    extra: FrozenMap[str, object] = field(default_factory=FrozenMap)
    source: SourceMap = field(default_factory=SourceMap, compare=False, repr=False)

    # --- convenience -------------------------------------------------------------------------
    @property
    def collision_key(self) -> str:
        """The spelling of the world-collision section in this version."""
        return "collision" if self.format_version == "1.0" else "world_collision"

    def replace(self, **changes: object) -> Xrdf:
        return replace(self, **changes)  # type: ignore[arg-type]

    def base_frame(self) -> str | None:
        """The last ``set_base_frame`` modifier, if any."""
        base = None
        for m in self.modifiers:
            if isinstance(m, SetBaseFrame):
                base = m.frame
        return base

    def added_frames(self) -> tuple[AddFrame, ...]:
        return tuple(m for m in self.modifiers if isinstance(m, AddFrame))

    def resolved_spheres(self, group: str) -> FrozenMap[str, tuple[Sphere, ...]]:
        """Spheres of ``group`` with clones resolved (see :func:`resolve_group`)."""
        return resolve_group(self.geometry or FrozenMap(), group)

    def self_collision_spheres(self) -> FrozenMap[str, tuple[Sphere, ...]]:
        if self.self_collision is None:
            return FrozenMap()
        return self.resolved_spheres(self.self_collision.geometry)

    def world_collision_spheres(self) -> FrozenMap[str, tuple[Sphere, ...]]:
        if self.world_collision is None:
            return FrozenMap()
        return self.resolved_spheres(self.world_collision.geometry)


def clone_order(geometry: Mapping[str, GeometryGroup], group: str) -> list[str]:
    """Groups whose spheres make up ``group``: itself first, then clones breadth-first.

    Clones are walked in list order and a group reached twice counts once (the Isaac Sim
    loader's order). Raises :class:`GeometryGroupError` for a missing group or a cycle.
    """
    if group not in geometry:
        raise GeometryGroupError(
            f"geometry group '{group}' is not defined (defined: {', '.join(geometry) or 'none'})"
        )
    _check_acyclic(geometry, group)
    order: list[str] = []
    seen = {group}
    queue = deque([group])
    while queue:
        name = queue.popleft()
        order.append(name)
        for child in geometry[name].clone:
            if child not in geometry:
                raise GeometryGroupError(
                    f"geometry group '{name}' clones '{child}', which is not defined "
                    f"(defined: {', '.join(geometry)})"
                )
            if child not in seen:
                seen.add(child)
                queue.append(child)
    return order


def _check_acyclic(geometry: Mapping[str, GeometryGroup], start: str) -> None:
    state: dict[str, int] = {}  # 1 = on stack, 2 = done
    stack: list[tuple[str, Iterator[str]]] = [(start, iter(geometry[start].clone))]
    path = [start]
    state[start] = 1
    while stack:
        name, children = stack[-1]
        child = next(children, None)
        if child is None:
            state[name] = 2
            stack.pop()
            path.pop()
            continue
        if child not in geometry:
            continue  # reported by clone_order with a better message
        if state.get(child) == 1:
            cycle = [*path[path.index(child) :], child]
            raise GeometryGroupError(f"geometry groups clone each other: {show_path(cycle)}")
        if child not in state:
            state[child] = 1
            path.append(child)
            stack.append((child, iter(geometry[child].clone)))


def resolve_group(
    geometry: Mapping[str, GeometryGroup], group: str
) -> FrozenMap[str, tuple[Sphere, ...]]:
    """Spheres per frame of ``group`` with every transitive clone merged in.

    A frame present in several groups keeps all of its spheres, concatenated in
    :func:`clone_order`. Frames keep the order in which they first appear.
    """
    merged: dict[str, list[Sphere]] = {}
    for name in clone_order(geometry, group):
        for frame, spheres in geometry[name].spheres.items():
            merged.setdefault(frame, []).extend(spheres)
    return FrozenMap((f, tuple(s)) for f, s in merged.items())
