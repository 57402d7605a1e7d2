"""The URDF as a tree of names: links, joints, parent/child relations, depth-first order.

Built once per :class:`~xrdf_tools.robot.core.Robot` (:attr:`~xrdf_tools.robot.core.Robot.tree`);
the converter and the source readers check names and walk chains with it. Imports nothing above
the plain joint view.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from ..util.errors import UrdfError
from .urdf_joints import JointInfo

__all__ = ["RobotTree"]


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
    def from_parts(
        cls, name: str, path: str, links: tuple[str, ...], joints: Mapping[str, JointInfo]
    ) -> RobotTree:
        """The tree of a robot's links and joints (:attr:`xrdf_tools.robot.core.Robot.tree` builds
        it once per robot); :class:`UrdfError` when every link has a parent joint."""
        parent_joint = {j.child: j.name for j in joints.values()}
        roots = tuple(link for link in links if link not in parent_joint)
        if not links:
            raise UrdfError("the robot has no links; a URDF needs at least one <link>", path=path)
        if not roots:
            raise UrdfError("the joints form a cycle: every link has a parent joint", path=path)
        children: dict[str, list[str]] = {}
        for j in joints.values():
            children.setdefault(j.parent, []).append(j.name)
        return cls(
            name=name,
            path=path,
            links=links,
            joints=dict(joints),
            root=roots[0],
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

    def is_held(self, joint: str) -> bool:
        """Whether ``joint`` is fixed or held still by its limits (:attr:`JointInfo.is_held`)."""
        j = self.joints[joint]
        return j.type == "fixed" or j.is_held

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
