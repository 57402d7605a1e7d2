"""What a robot description holds, as one value: links, joints, chains, SRDF groups, and the
c-space and tool frame ``xrdf convert`` would pick by default.

:func:`inspect_robot` reads only the URDF XML (and the SRDF): no mesh is loaded. The default
choice comes from :func:`xrdf_tools.convert.core.convert` itself, so ``xrdf inspect`` shows
exactly what ``xrdf convert`` without ``--group``/``--chain``/``--joints`` would write.
:meth:`Inspection.to_dict` is the stable JSON form (keys documented in ``docs/inspect.md``);
:func:`xrdf_tools.convert.inspect_text.render_inspection` the text form.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any

from ..robot.chains import (
    BELOW_LEFT_OUT,
    Chain,
    chain_flag,
    default_cspace,
    joint_roles,
    leaf_chains,
)
from ..robot.drake import DrakeFrame, drake_extensions

if TYPE_CHECKING:
    from ..robot.core import Robot
    from .core import ConvertOptions

__all__ = [
    "DefaultChoice",
    "GroupView",
    "Inspection",
    "JointView",
    "LinkView",
    "inspect_robot",
]

#: Version of the JSON form (:meth:`Inspection.to_dict`); raised when a key changes meaning.
JSON_VERSION = 1

#: Diagnostics of ``convert`` that explain the default choice.
_CHOICE_RULES = (
    "convert-chosen-group",
    "convert-chosen-tool-frame",
    "convert-chosen-state",
    "convert-unplannable-joint",
)


@dataclass(frozen=True)
class LinkView:
    """One link: its parent joint (None for the root) and its geometry element counts."""

    name: str
    parent_joint: str | None
    collision: int
    visual: int


@dataclass(frozen=True)
class JointView:
    """One joint as written in the URDF, whether it is a c-space coordinate (``actuated``)
    and why a default c-space leaves it out (``role``: wheel, gripper, head)."""

    name: str
    type: str
    parent: str
    child: str
    lower: float | None
    upper: float | None
    velocity: float | None
    mimic_joint: str | None
    mimic_multiplier: float
    mimic_offset: float
    actuated: bool
    role: str | None


@dataclass(frozen=True)
class GroupView:
    """One SRDF group resolved against the URDF (``problem``: why it does not resolve)."""

    name: str
    joints: tuple[str, ...]
    cspace: tuple[str, ...]
    subgroups: tuple[str, ...]
    line: int | None
    problem: str | None = None
    #: Planar and floating joints the group names (no c-space can hold them).
    unplannable: tuple[str, ...] = ()
    #: The file that writes the group: the SRDF, or the included xacro file whose macro
    #: writes it (``line`` is a line of that file).
    file: str | None = None


@dataclass(frozen=True)
class DefaultChoice:
    """What ``xrdf convert`` picks (without ``--group``/``--chain``/``--joints``, or with the
    choice flags given), and why."""

    cspace: tuple[str, ...]
    tool_frames: tuple[str, ...]
    #: ``srdf`` (an SRDF group), ``chain`` (the longest arm chain) or ``error``.
    source: str
    notes: tuple[str, ...]
    #: The ``--chain`` that gives the same c-space without an SRDF (None with an SRDF).
    chain_flag: str | None = None
    error: str | None = None
    #: The choice flags given (``--group l_arm``): what convert picks with them.
    flags: tuple[str, ...] = ()


@dataclass(frozen=True)
class Inspection:
    """Everything ``xrdf inspect`` shows."""

    name: str
    path: str
    root: str
    links: tuple[LinkView, ...]
    joints: tuple[JointView, ...]
    chains: tuple[Chain, ...]
    groups: tuple[GroupView, ...]
    default: DefaultChoice
    srdf: str | None = None
    #: Movable joints a default c-space leaves out, by reason.
    left_out: tuple[tuple[str, tuple[str, ...]], ...] = ()
    #: Every link without a parent joint (``root`` first; more than one: disconnected parts).
    roots: tuple[str, ...] = ()
    #: Drake ``<frame>`` elements: named poses on links, which no XRDF reader sees.
    frames: tuple[DrakeFrame, ...] = ()

    def to_dict(self) -> dict[str, Any]:
        """The JSON form: plain dicts and lists, keys in a fixed order."""
        return {
            "version": JSON_VERSION,
            "robot": self.name,
            "path": self.path,
            "srdf": self.srdf,
            "root": self.root,
            "roots": list(self.roots or (self.root,)),
            "links": [
                {
                    "name": lk.name,
                    "parent_joint": lk.parent_joint,
                    "collision": lk.collision,
                    "visual": lk.visual,
                }
                for lk in self.links
            ],
            "joints": [_joint_dict(j) for j in self.joints],
            "chains": [
                {
                    "leaf": c.leaf,
                    "joints": list(c.joints),
                    "actuated": [j for j in c.joints if j in self._actuated],
                    "default_cspace": list(c.cspace),
                }
                for c in self.chains
            ],
            "groups": [
                {
                    "name": g.name,
                    "file": g.file,
                    "line": g.line,
                    "joints": list(g.joints),
                    "cspace": list(g.cspace),
                    "subgroups": list(g.subgroups),
                    "unplannable": list(g.unplannable),
                    "problem": g.problem,
                }
                for g in self.groups
            ],
            "left_out": {role: list(js) for role, js in self.left_out},
            "frames": [
                {"name": f.name, "link": f.link, "xyz": f.xyz, "rpy": f.rpy, "line": f.at[1]}
                for f in self.frames
            ],
            "default": {
                "source": self.default.source,
                "cspace": list(self.default.cspace),
                "tool_frames": list(self.default.tool_frames),
                "chain_flag": self.default.chain_flag,
                "flags": list(self.default.flags),
                "notes": list(self.default.notes),
                "error": self.default.error,
            },
        }

    @property
    def _actuated(self) -> set[str]:
        return {j.name for j in self.joints if j.actuated}


def _joint_dict(j: JointView) -> dict[str, Any]:
    mimic = None
    if j.mimic_joint is not None:
        mimic = {"joint": j.mimic_joint, "multiplier": j.mimic_multiplier, "offset": j.mimic_offset}
    return {
        "name": j.name,
        "type": j.type,
        "parent": j.parent,
        "child": j.child,
        "lower": j.lower,
        "upper": j.upper,
        "velocity": j.velocity,
        "mimic": mimic,
        "actuated": j.actuated,
        "role": j.role,
    }


def inspect_robot(
    robot: Robot,
    srdf: str | os.PathLike[str] | None = None,
    choice: ConvertOptions | None = None,
) -> Inspection:
    """Inspect ``robot`` (and the SRDF at ``srdf``); ``choice``: the c-space, state and tool
    frame flags of ``xrdf convert`` (groups, state, tool frames, joints, chains), whose pick is
    shown instead of the default.

    Raises :class:`~xrdf_tools.util.errors.XrdfToolsError` when the SRDF cannot be read, or
    when convert fails with the ``choice`` given (a group the SRDF lacks); a group that does
    not resolve, or a default choice that fails, is reported in the value.
    """
    tree = robot.tree
    roles = joint_roles(tree)
    chosen = default_cspace(tree, collision_links=frozenset(robot.collision_counts))
    below = dict.fromkeys(chosen.left_out.get(BELOW_LEFT_OUT, ()), "below a left-out joint")
    visuals = _visual_counts(robot)
    links = tuple(
        LinkView(
            name,
            tree.parent_joint.get(name),
            robot.collision_counts.get(name, 0),
            visuals.get(name, 0),
        )
        for name in robot.links
    )
    joints = tuple(
        JointView(
            j.name,
            j.type,
            j.parent,
            j.child,
            j.lower,
            j.upper,
            j.velocity,
            j.mimic_joint,
            j.mimic_multiplier,
            j.mimic_offset,
            j.is_actuated,
            roles.get(j.name, below.get(j.name)),
        )
        for j in robot.joints.values()
    )
    srdf_path = None if srdf is None else os.fspath(srdf)
    groups = _groups(srdf_path, robot) if srdf_path is not None else ()
    return Inspection(
        name=robot.name,
        path=robot.path,
        root=tree.root,
        links=links,
        joints=joints,
        chains=tuple(leaf_chains(tree, roles)),
        groups=groups,
        default=_default_choice(robot, srdf_path, choice),
        srdf=srdf_path,
        left_out=tuple(chosen.left_out.items()),
        roots=tree.roots or (tree.root,),
        frames=drake_extensions(robot).frames,
    )


def _visual_counts(robot: Robot) -> dict[str, int]:
    """``<visual>`` elements per link, from the checked XML (no yourdfpy, no meshes) when the
    loader kept it, else from the yourdfpy object the robot was made from."""
    if robot.document is not None:
        return {
            str(e.get("name")): len(e.findall("visual")) for e in robot.document.findall("link")
        }
    return {str(lk.name): len(lk.visuals) for lk in robot.urdf.robot.links}


def _groups(path: str, robot: Robot) -> tuple[GroupView, ...]:
    from ..util.errors import XrdfToolsError
    from .sources.cspace import unplannable_joints
    from .sources.srdf import cspace_of, group_joints, load_srdf
    from .sources.srdf_groups import group_problems

    srdf = load_srdf(path, xacro_args=robot.xacro_args, package_paths=robot.package_paths)
    # every unknown name of a group, as convert names them (the walk stops at the first)
    own = {g.name: "; ".join(p) for g, p in group_problems(srdf, robot.tree)}
    out: list[GroupView] = []
    for g in srdf.groups.values():
        try:
            joints = tuple(group_joints(srdf, g.name, robot.tree))
            cspace = tuple(cspace_of(srdf, g.name, robot.tree))
            problem = None
        except XrdfToolsError as e:
            joints, cspace = (), ()
            problem = f"group '{g.name}': {own[g.name]}" if g.name in own else _plain(e)
        odd = tuple(j for _, j, _ in unplannable_joints(srdf, [g.name], robot.tree))
        file, line = srdf.at(g)
        out.append(GroupView(g.name, joints, cspace, tuple(g.subgroups), line, problem, odd, file))
    return tuple(out)


def _plain(e: Exception) -> str:
    return str(getattr(e, "message", None) or e)


def _default_choice(
    robot: Robot, srdf: str | None, choice: ConvertOptions | None = None
) -> DefaultChoice:
    """Run ``convert`` as ``xrdf convert ROBOT [--srdf S] [choice flags]`` would and keep what
    it chose. Without choice flags, an error when the command would fail (the robot's
    kinematics included: a mimic loop, a zero axis) is the value; with them, it is raised."""
    from ..robot.kinematics import build_kinematic_model
    from ..util.errors import XrdfToolsError
    from .core import ConvertOptions, convert

    flags = choice_flags(choice)
    options = ConvertOptions(srdf=srdf) if choice is None else replace(choice, srdf=srdf)
    try:
        x, diags = convert(robot, options)
        build_kinematic_model(robot, x)
    except XrdfToolsError as e:
        if flags:
            raise
        return DefaultChoice((), (), "error", (), error=_plain(e))
    cspace = tuple(x.cspace.joint_names) if x.cspace is not None else ()
    notes = tuple(d.message for d in diags if d.rule in _CHOICE_RULES)
    by_group = srdf is not None and any(
        d.rule == "convert-chosen-group" and d.path == srdf for d in diags
    )
    tools = tuple(x.tool_frames or ())
    if flags:
        return DefaultChoice(cspace, tools, "flags", notes, flags=flags)
    flag = None
    if not by_group and cspace and tools:
        flag = chain_flag(robot.tree.root, tools[0])
    return DefaultChoice(cspace, tools, "srdf" if by_group else "chain", notes, chain_flag=flag)


def choice_flags(choice: ConvertOptions | None) -> tuple[str, ...]:
    """The command-line flags of the c-space, state and tool-frame choice in ``choice``."""
    if choice is None:
        return ()
    out = [f"--group {g}" for g in choice.planning_groups()]
    if choice.joints:
        out.append(f"--joints {','.join(choice.joints)}")
    out += [f"--chain {base}:{tip}" for base, tip in choice.chains]
    if choice.state is not None:
        out.append(f"--state {choice.state}")
    out += [f"--tool-frame {t}" for t in choice.tool_frames]
    return tuple(out)


def chain_summary(
    chains: Sequence[Chain], actuated: set[str]
) -> list[tuple[tuple[str, ...], list[str]]]:
    """Chains grouped by their actuated joints: ``(joints, leaves)``, longest first, then in
    depth-first order; chains without an actuated joint are left out."""
    groups: dict[tuple[str, ...], list[str]] = {}
    for c in chains:
        key = tuple(j for j in c.joints if j in actuated)
        if key:
            groups.setdefault(key, []).append(c.leaf)
    firsts = list(groups)
    return sorted(groups.items(), key=lambda kv: (-len(kv[0]), firsts.index(kv[0])))
