"""Readers for conversion inputs: xacro, MoveIt SRDF + joint limits, cuRobo robot YAML.

Each reader fills a :class:`Draft` — what its source says, nothing guessed — and reports every
dropped or unusable value as a :class:`~xrdf_tools.diagnostics.Diagnostic` with the source
position. :mod:`xrdf_tools.convert` completes the draft against the URDF (defaults, checks) and
builds the XRDF model. Names of links and joints are checked against a :class:`RobotTree`, a
plain view of the URDF.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from ..diagnostics import Diagnostic, Severity
from ..errors import UrdfError, did_you_mean
from ..model import Modifier, Sphere

if TYPE_CHECKING:
    import yourdfpy

    from ..robot import Robot
    from ..urdf_source import JointInfo

__all__ = ["Draft", "Reporter", "RobotTree"]


@dataclass(frozen=True)
class RobotTree:
    """The URDF as a tree of names: links, joints, parent/child relations, DFS joint order."""

    name: str
    path: str
    links: tuple[str, ...]
    joints: Mapping[str, JointInfo]
    root: str
    parent_joint: Mapping[str, str]  # child link -> joint
    child_joints: Mapping[str, tuple[str, ...]]  # link -> joints, sorted by joint name
    #: Every link without a parent joint (one for a proper URDF; cuRobo ships URDFs with
    #: disconnected parts, usable once a base frame is chosen). ``root`` is the first.
    roots: tuple[str, ...] = ()

    @classmethod
    def from_urdf(cls, urdf: Robot | yourdfpy.URDF) -> RobotTree:
        """The tree of a loaded robot (built once per :class:`~xrdf_tools.robot.Robot`)."""
        from ..robot import as_robot

        return as_robot(urdf).tree

    @classmethod
    def from_robot(cls, robot: Robot) -> RobotTree:
        from ..errors import UrdfError

        joints = dict(robot.joints)
        links = robot.links
        parent_joint = {j.child: j.name for j in joints.values()}
        path = robot.path
        roots = tuple(link for link in links if link not in parent_joint)
        if not roots:
            raise UrdfError("the joints form a cycle: every link has a parent joint", path=path)
        root = roots[0]
        children: dict[str, list[str]] = {}
        for j in joints.values():
            children.setdefault(j.parent, []).append(j.name)
        return cls(
            name=robot.name,
            path=path,
            links=links,
            joints=joints,
            root=root,
            parent_joint=parent_joint,
            child_joints={k: tuple(sorted(v)) for k, v in children.items()},
            roots=roots,
        )

    def with_root(self, base: str) -> RobotTree:
        """The same tree walked from ``base`` (a link chosen as the robot's base)."""
        return RobotTree(
            self.name,
            self.path,
            self.links,
            self.joints,
            base,
            self.parent_joint,
            self.child_joints,
            self.roots,
        )

    def dfs_joints(self) -> list[str]:
        """Every joint, depth-first from the root, siblings ordered by joint name (MoveIt).

        Each joint is visited once, so a tree built by hand with a cycle cannot hang it (a
        URDF with a cycle is refused when it is loaded)."""
        out: list[str] = []
        seen: set[str] = set()
        stack = list(reversed(self.child_joints.get(self.root, ())))
        while stack:
            jn = stack.pop()
            if jn in seen:
                continue
            seen.add(jn)
            out.append(jn)
            stack.extend(reversed(self.child_joints.get(self.joints[jn].child, ())))
        return out

    def joint_order(self) -> dict[str, int]:
        return {j: i for i, j in enumerate(self.dfs_joints())}

    def is_actuated(self, joint: str) -> bool:
        j = self.joints.get(joint)
        return j is not None and j.is_actuated

    def actuated_joints(self) -> list[str]:
        return [j for j in self.dfs_joints() if self.joints[j].is_actuated]

    def ancestors(self, link: str) -> list[str]:
        """Links from ``link``'s parent up to the root; :class:`UrdfError` on a cycle."""
        out: list[str] = []
        seen = {link}
        while link in self.parent_joint:
            link = self.joints[self.parent_joint[link]].parent
            if link in seen:
                raise UrdfError(
                    f"the joints form a cycle through link '{link}'; a URDF must be a tree",
                    path=self.path,
                )
            seen.add(link)
            out.append(link)
        return out

    def chain_joints(self, base: str, tip: str) -> list[str] | None:
        """Joints from ``tip`` up to ``base`` (tip's parent joint first), or None when
        ``base`` is not ``tip`` or one of its ancestors."""
        out: list[str] = []
        cur = tip
        for up in self.ancestors(tip):
            if cur == base:
                break
            out.append(self.parent_joint[cur])
            cur = up
        return out if cur == base else None

    def descendants(self, link: str) -> list[str]:
        """Links below ``link``, each once."""
        out: list[str] = []
        seen = {link}
        stack = [link]
        while stack:
            cur = stack.pop()
            for jn in self.child_joints.get(cur, ()):
                child = self.joints[jn].child
                if child not in seen:
                    seen.add(child)
                    out.append(child)
                    stack.append(child)
        return out


@dataclass
class Draft:
    """What one or more sources say about the XRDF to write. Empty/None = not said."""

    cspace: list[str] | None = None
    acceleration: dict[str, float] = field(default_factory=dict)
    jerk: dict[str, float] = field(default_factory=dict)
    defaults: dict[str, float] = field(default_factory=dict)
    tool_frames: list[str] = field(default_factory=list)
    spheres: dict[str, list[Sphere]] | None = None
    world_buffer: dict[str, float] = field(default_factory=dict)
    self_buffer: dict[str, float] = field(default_factory=dict)
    ignore: dict[str, list[str]] = field(default_factory=dict)
    modifiers: list[Modifier] = field(default_factory=list)
    geometry_name: str | None = None
    group: str | None = None
    passive_joints: set[str] = field(default_factory=set)
    diagnostics: list[Diagnostic] = field(default_factory=list)

    def add_ignore(self, a: str, b: str) -> None:
        """Add the pair once (in either direction), folded under ``a``."""
        if a == b or b in self.ignore.get(a, ()) or a in self.ignore.get(b, ()):
            return
        self.ignore.setdefault(a, []).append(b)


@dataclass
class Reporter:
    """Makes diagnostics for one source file; positions come from ``positions[key_path]``."""

    path: str
    positions: Mapping[str, tuple[int, int]] = field(default_factory=dict)
    diagnostics: list[Diagnostic] = field(default_factory=list)

    def position(self, key_path: str) -> tuple[int | None, int | None]:
        for kp in (key_path + "#key", key_path):
            if kp in self.positions:
                return self.positions[kp]
        kp = key_path
        while kp:
            cut = max(kp.rfind("."), kp.rfind("["))
            kp = kp[:cut] if cut > 0 else ""
            if kp in self.positions:
                return self.positions[kp]
        return (None, None)

    def report(
        self,
        rule: str,
        message: str,
        key_path: str = "",
        *,
        severity: Severity = Severity.WARNING,
        line: int | None = None,
    ) -> Diagnostic:
        if line is not None:
            pos: tuple[int | None, int | None] = (line, None)
        else:
            pos = self.position(key_path)
        d = Diagnostic(self.path, pos[0], pos[1], rule, severity, message, key_path)
        self.diagnostics.append(d)
        return d


def known_frame(
    name: str,
    frames: Iterable[str],
    rep: Reporter,
    key_path: str,
    what: str,
    *,
    line: int | None = None,
) -> bool:
    """True when ``name`` is a frame; otherwise report ``convert-unknown-link`` (did-you-mean)."""
    frames = list(frames)
    if name in frames:
        return True
    rep.report(
        "convert-unknown-link",
        f"'{name}' ({what}) is not a link of the URDF; dropped{did_you_mean(name, frames)}",
        key_path,
        line=line,
    )
    return False
