"""MoveIt planning groups of an SRDF against the URDF tree: expansion, checks and choice.

Group expansion (MoveIt ``RobotModel``, see docs/convert.md, "Sources"): a ``chain`` walks up
from ``tip_link`` adding each parent joint and stops at ``base_link`` (whose own parent joint is
not included); a ``joint`` is itself; a ``link`` contributes its parent joint; a subgroup
contributes all of its joints. Joints are ordered depth-first in URDF tree order (siblings by
name). The c-space is the group's joints minus fixed, mimic and passive joints.
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Sequence

from ...robot.chains import is_leg, joint_roles
from ...robot.names import ARM, name_role, name_words
from ...robot.tool_frame import fixed_below, tool_named
from ...util.errors import SourceError, did_you_mean
from ...util.graph import nodes_on_cycles, postorder, reachable, show_path
from ...util.text import name_list
from . import RobotTree
from .srdf_parse import EndEffector, GroupState, Srdf, SrdfGroup

__all__ = [
    "PREFERRED_STATES",
    "carries_end_effector",
    "check_groups",
    "choose_group",
    "choose_state",
    "cspace_of",
    "effector_tool_note",
    "group_joints",
    "group_problems",
    "group_sizes",
    "home_state",
    "member_groups",
    "unused_cycles",
]

#: Names of a group's rest pose, in this order. ``neutral`` is Rethink's (Baxter's
#: ``left_neutral``/``right_neutral``, its SDK's "move to neutral").
PREFERRED_STATES = ("home", "ready", "default", "neutral")


def group_named(srdf: Srdf, name: str) -> SrdfGroup:
    if name not in srdf.groups:
        raise SourceError(
            f"no group '{name}' in the SRDF{did_you_mean(name, srdf.groups)} "
            f"(groups: {name_list(srdf.groups, 12) or 'none'})",
            path=srdf.path,
        )
    return srdf.groups[name]


def _virtual_joints(srdf: Srdf) -> set[str]:
    return {vj.name for vj in srdf.virtual_joints}


def _own_problems(srdf: Srdf, g: SrdfGroup, tree: RobotTree) -> list[str]:
    """What is wrong with the elements of group ``g`` itself (subgroups not followed)."""
    virtual = _virtual_joints(srdf)
    joints = [j for j in g.joints if j not in tree.joints and j not in virtual]
    links = [n for n in g.links if n not in tree.links]
    chain_links = [n for c in g.chains for n in c if n not in tree.links]
    subs = [s for s in g.subgroups if s not in srdf.groups]
    out = []
    for what, names, pool in (
        ("joint", joints, tree.joints),
        ("link", links, tree.links),
        ("chain link", chain_links, tree.links),
        ("subgroup", subs, srdf.groups),
    ):
        if names:
            out.append(_unknown(what, names, pool))
    for base, tip in g.chains:
        if base in tree.links and tip in tree.links and base not in (tip, *tree.ancestors(tip)):
            out.append(f"chain base '{base}' is not an ancestor of tip '{tip}'")
    return out


def _unknown(what: str, names: list[str], pool: Iterable[str]) -> str:
    shown = name_list((f"'{n}'" for n in names), 6)
    plural = "s" if len(names) > 1 else ""
    hint = did_you_mean(names[0], pool).removeprefix("; ").removesuffix("?")
    about = f" for '{names[0]}'" if len(names) > 1 else ""
    hint = f" ({hint}{about}?)" if hint else ""
    return f"unknown {what}{plural} {shown}{hint}"


def group_problems(srdf: Srdf, tree: RobotTree) -> list[tuple[SrdfGroup, list[str]]]:
    """Every group that names joints, links or subgroups that do not exist (virtual joints
    are known), or has a chain whose base is not above its tip, with what is wrong with it
    (its own elements; a group is not blamed for a broken subgroup)."""
    broken = [(g, _own_problems(srdf, g, tree)) for g in srdf.groups.values()]
    return [(g, p) for g, p in broken if p]


def member_groups(srdf: Srdf, names: Iterable[str]) -> list[str]:
    """``names`` and every group they include through subgroups (existing groups only)."""
    out: dict[str, None] = {}
    stack = list(names)[::-1]
    while stack:
        g = stack.pop()
        if g in out or g not in srdf.groups:
            continue
        out[g] = None
        stack.extend(reversed(srdf.groups[g].subgroups))
    return list(out)


def check_groups(
    srdf: Srdf, tree: RobotTree, used: Iterable[str] | None = None
) -> list[tuple[SrdfGroup, list[str]]]:
    """Raise :class:`SourceError` when a group of ``used`` (default: every group), or a
    subgroup it includes, does not match the URDF (see :func:`group_problems`): every such
    group is named with its unknown names. Returns the broken groups that are not used,
    for the caller to warn about: a defect in a part the conversion does not use does not
    stop it, and is never skipped without a word."""
    used = None if used is None else tuple(used)
    members = member_groups(srdf, srdf.groups if used is None else used)
    broken = group_problems(srdf, tree)
    fatal = [(g, p) for g, p in broken if g.name in members]
    if fatal:
        parts = [
            f"group '{g.name}'{_at(srdf, g)}{_included_by(srdf, g.name, members, used)}: "
            + "; ".join(p)
            for g, p in fatal
        ]
        path, line = srdf.at(fatal[0][0])
        raise SourceError(
            f"{len(fatal)} SRDF group(s) used for the conversion do not match the URDF: "
            + " | ".join(parts),
            path=path,
            line=line,
        )
    return [(g, p) for g, p in broken if g.name not in members]


def _included_by(srdf: Srdf, name: str, members: Iterable[str], used: Iterable[str] | None) -> str:
    """``, a subgroup of 'G'`` when group ``name`` is used only as a subgroup of a group
    ``G`` among ``members`` (HSR's 'base' inside 'whole_body'), nothing when it was asked for."""
    if used is None or name in used:
        return ""
    parent = next((m for m in members if name in srdf.groups[m].subgroups), None)
    return f", a subgroup of '{parent}'" if parent is not None else ""


def _at(srdf: Srdf, g: SrdfGroup) -> str:
    """`` (line N)`` after a group's name (`` (file.xacro:N)`` when an included file writes
    it), nothing when it has no line."""
    path, line = srdf.at(g)
    if not line:
        return ""
    return f" (line {line})" if path == srdf.path else f" ({os.path.basename(path)}:{line})"


def unused_cycles(srdf: Srdf, used: Iterable[str]) -> list[tuple[SrdfGroup, str]]:
    """The groups not among ``used`` (and their subgroups) that include themselves through
    their subgroups, each with its cycle (``a -> b -> a``), for the caller to warn about. A
    used group on a cycle is an error when it is expanded (:func:`group_joints`)."""
    groups = srdf.groups

    def subs(name: str) -> list[str]:
        return [s for s in groups[name].subgroups if s in groups]

    members = set(member_groups(srdf, used))
    cyclic = nodes_on_cycles(groups, subs)
    out = []
    for name, g in groups.items():
        if name in cyclic and name not in members:
            _, cycle = reachable(name, subs)
            out.append((g, show_path(cycle or [name, name])))
    return out


def _own_joints(srdf: Srdf, gname: str, tree: RobotTree) -> set[str]:
    """Joints that group ``gname`` names itself (joints, links, chains; not its subgroups)."""
    g = group_named(srdf, gname)
    found: set[str] = set()

    def fail(msg: str) -> SourceError:
        path, line = srdf.at(g)
        return SourceError(f"group '{g.name}': {msg}", path=path, line=line)

    virtual = _virtual_joints(srdf)
    for j in g.joints:
        if j in virtual:
            continue  # a virtual joint is not a URDF joint: it contributes nothing
        if j not in tree.joints:
            raise fail(f"unknown joint '{j}'{did_you_mean(j, tree.joints)}")
        found.add(j)
    for link in g.links:
        if link not in tree.links:
            raise fail(f"unknown link '{link}'{did_you_mean(link, tree.links)}")
        if link in tree.parent_joint:
            found.add(tree.parent_joint[link])
    for base, tip in g.chains:
        for link in (base, tip):
            if link not in tree.links:
                raise fail(
                    f"chain link '{link}' is not in the URDF{did_you_mean(link, tree.links)}"
                )
        chain = tree.chain_joints(base, tip)
        if chain is None:
            raise fail(f"chain base '{base}' is not an ancestor of tip '{tip}'")
        found.update(chain)
    return found


def group_joints(srdf: Srdf, name: str, tree: RobotTree) -> list[str]:
    """All joints of group ``name`` (fixed ones included) in MoveIt's order.

    Virtual joints (``<virtual_joint>``) are not URDF joints and contribute nothing. Raises
    :class:`SourceError` for names that are not in the URDF, a chain whose base is not an
    ancestor of its tip, or subgroups that include each other.
    """
    # subgroups: each visited once, without recursion (1,000s of nested groups are fine)
    members, cycle = reachable(name, lambda gname: group_named(srdf, gname).subgroups)
    if cycle is not None:
        path, line = srdf.at(srdf.groups[cycle[0]])
        raise SourceError(f"groups include each other: {show_path(cycle)}", path=path, line=line)
    found: set[str] = set()
    for gname in members:
        found |= _own_joints(srdf, gname, tree)
    return [j for j in tree.dfs_joints() if j in found]


def _cspace_sizes(srdf: Srdf, tree: RobotTree) -> dict[str, int]:
    """``len(cspace_of(g))`` of every group, 0 when it does not resolve."""
    return {g: n or 0 for g, n in group_sizes(srdf, tree).items()}


def group_sizes(srdf: Srdf, tree: RobotTree) -> dict[str, int | None]:
    """``len(cspace_of(g))`` of every group, None when it does not resolve (for messages
    listing the alternatives), in one pass over the groups (children first), so thousands of
    nested groups stay linear."""
    groups = srdf.groups

    def subs(g: str) -> list[str]:
        return list(groups[g].subgroups) if g in groups else []

    cyclic = nodes_on_cycles(groups, subs)
    joints: dict[str, frozenset[str] | None] = {}
    for g in postorder(groups, subs):
        if g not in groups or g in cyclic:
            joints[g] = None
            continue
        try:
            own = frozenset(_own_joints(srdf, g, tree))
        except SourceError:
            own = None
        parts = [joints.get(s) for s in groups[g].subgroups]
        known = [p for p in parts if p is not None]
        joints[g] = None if own is None or len(known) < len(parts) else own.union(*known)
    passive = set(srdf.passive_joints)
    return {
        g: None if js is None else sum(1 for j in js if tree.is_actuated(j) and j not in passive)
        for g, js in joints.items()
        if g in groups
    }


def cspace_of(srdf: Srdf, name: str, tree: RobotTree) -> list[str]:
    """C-space of group ``name``: its joints minus fixed, mimic and passive joints."""
    passive = set(srdf.passive_joints)
    return [j for j in group_joints(srdf, name, tree) if tree.is_actuated(j) and j not in passive]


def _path_joints(tree: RobotTree, link: str) -> set[str]:
    """Joints between the root and ``link``."""
    return {tree.parent_joint[n] for n in (link, *tree.ancestors(link)) if n in tree.parent_joint}


def _is_gripper(srdf: Srdf, ee: EndEffector, tree: RobotTree) -> bool:
    """``ee.group`` is the end effector itself (MoveIt's meaning): none of its joints moves
    the parent link. Many SRDFs instead name the arm there (Panda, Talos): not a gripper."""
    if ee.group is None or ee.group not in srdf.groups or ee.parent_link not in tree.links:
        return False
    try:
        joints = set(group_joints(srdf, ee.group, tree))
    except SourceError:  # a broken group: not a candidate, the caller warns about it
        return False
    return not joints & _path_joints(tree, ee.parent_link)


def carries_end_effector(srdf: Srdf, group: str, ee: EndEffector, tree: RobotTree) -> bool:
    """Group ``group`` carries end effector ``ee`` (see :func:`_carries`); a group that
    cannot be resolved carries none."""
    try:
        return _carries(srdf, group, ee, tree, _is_gripper(srdf, ee, tree))
    except SourceError:
        return False


def _carries(srdf: Srdf, g: str, ee: EndEffector, tree: RobotTree, gripper: bool) -> bool:
    """Group ``g`` carries end effector ``ee``: named as its parent group, or a subgroup of
    that group holding the last joint moving the parent link (TIAGo++: `arm_left` in
    `arm_left_torso`); named as its group (not a gripper); or, without a parent group, it
    holds the last joint moving the parent link and not the gripper's joints."""
    last = _nearest_actuated(tree, ee.parent_link)
    if ee.parent_group is not None:
        if ee.parent_group == g:
            return True
        within, _ = reachable(ee.parent_group, lambda n: group_named(srdf, n).subgroups)
        return g in within and last in group_joints(srdf, g, tree)
    if ee.group == g:
        return not gripper
    if last is None:
        return False
    joints = set(group_joints(srdf, g, tree))
    own = set(group_joints(srdf, ee.group, tree)) if gripper and ee.group else set()
    return last in joints and not joints & own


def _nearest_actuated(tree: RobotTree, link: str) -> str | None:
    """The first actuated joint above ``link`` (the one that moves it last)."""
    for n in (link, *tree.ancestors(link)):
        jn = tree.parent_joint.get(n)
        if jn is not None and tree.is_actuated(jn):
            return jn
    return None


def choose_group(srdf: Srdf, tree: RobotTree) -> tuple[str | None, str]:
    """The default planning group and why it was chosen (``None`` when the SRDF has none).

    Candidates are the groups without subgroups that are not an end effector's gripper (all
    groups when none of those has a movable joint); the one with the most actuated joints
    wins, not counting the joints of a gripper it holds (:func:`_gripper_joints`), ties going
    to the group with fewer of those, then the group carrying the earliest end effector, then
    SRDF order. Groups with a leg's joints
    (:func:`~xrdf_tools.robot.chains.is_leg`), alone or in a whole body's joint list, come
    after every other group: a legged manipulator's or a humanoid's arm is what a planner
    plans, however many joints its legs have; groups named
    like a hand, head or wheels (:func:`_named_like_a_part`) come after those.
    """
    order = list(srdf.groups)
    sizes = _cspace_sizes(srdf, tree)
    grippers = {ee.name: _is_gripper(srdf, ee, tree) for ee in srdf.end_effectors}
    excluded = {ee.group for ee in srdf.end_effectors if grippers[ee.name]}
    plain = [g for g in order if not srdf.groups[g].subgroups and g not in excluded]
    cands = [g for g in plain if sizes[g] > 0] or [g for g in order if sizes[g] > 0]
    if not cands:
        return None, "the SRDF has no group with movable joints"

    def ee_rank(g: str) -> tuple[int, str]:
        for i, ee in enumerate(srdf.end_effectors):
            if _carries(srdf, g, ee, tree, grippers[ee.name]):
                return i, ee.name
        return len(srdf.end_effectors), ""

    legs = {g: any(is_leg(tree, [j]) for j in cspace_of(srdf, g, tree)) for g in cands}
    parts = {g: _named_like_a_part(g) for g in cands}
    jaws = _gripper_joints(srdf, tree, cands)
    arm = {g: sizes[g] - len(jaws[g]) for g in cands}
    best = min(
        cands,
        key=lambda g: (parts[g], legs[g], -arm[g], len(jaws[g]), ee_rank(g)[0], order.index(g)),
    )
    kind = "group without subgroups" if best in plain else "group"
    why = f"the {kind} with the most actuated joints ({sizes[best]})"
    if any(legs[g] and sizes[g] > sizes[best] for g in cands):
        why += " among the groups that move no leg"
    held = [g for g in cands if jaws[g] and arm[g] == arm[best] and g != best]
    if held:
        shown = ", ".join(f"{g} (+{name_list(jaws[g], 3)})" for g in held[:3])
        why += f" (passed over, the same arm joints and a gripper's: {shown})"
    named = [g for g in cands if parts[g] and not parts[best] and sizes[g] > sizes[best]]
    if named:
        why += f" (passed over, named like a hand, head or wheels: {name_list(named, 3)})"
    ee_name = ee_rank(best)[1]
    if ee_name:
        why += f", carrying end effector '{ee_name}'"
    return best, why


def _gripper_joints(srdf: Srdf, tree: RobotTree, groups: list[str]) -> dict[str, list[str]]:
    """The c-space joints of each group that move a gripper's jaw or finger
    (:func:`~xrdf_tools.robot.chains.joint_roles`): a group that is an arm plus one jaw of its
    gripper (the AgileX Piper's ``piper``, a chain down to a finger) plans no more of the arm
    than the arm's own group, and a planner moves the jaws apart from the arm."""
    roles = joint_roles(tree)
    return {g: [j for j in cspace_of(srdf, g, tree) if roles.get(j) == "gripper"] for g in groups}


#: Words that make a group name more than a part: an arm, or a whole of several parts
#: (``manipulator_with_hand``, ``robot_with_gripper``, ``upper_body_and_head``).
_WHOLE = ARM | {"manipulator", "with", "and", "body", "robot", "whole", "upper", "torso", "all"}


def _named_like_a_part(group: str) -> bool:
    """Whether a group's name says it moves a hand, a head or wheels and nothing more
    (``right_hand``, ``neck``; not ``arm_hand`` or ``manipulator_with_hand``): what a planner
    does not plan for, however many joints it has (the Sandia hands of Atlas have twelve,
    named ``f0_j0`` …)."""
    return name_role(group) is not None and not set(name_words(group)) & _WHOLE


def choose_state(
    srdf: Srdf, group: str | None, cspace: list[str], requested: str | None
) -> tuple[GroupState | None, str]:
    """The group state giving default positions, and why it was chosen: the requested one;
    else one named home, ready, default or neutral of the group, then of a group covering the
    c-space; then one with such a word in its name (``home_position``), in that order; else
    the first state of the group, then of a covering group."""
    if requested is not None:
        for s in srdf.group_states:
            if s.name == requested and (group is None or s.group in (group, None)):
                return s, "requested"
        for s in srdf.group_states:
            if s.name == requested:
                return s, "requested"
        names = [s.name for s in srdf.group_states]
        listed = [f"{s.name} ({s.group})" if s.group else s.name for s in srdf.group_states]
        raise SourceError(
            f"no group_state '{requested}'{did_you_mean(requested, names)} "
            f"(states: {name_list(dict.fromkeys(listed), 12) or 'none'})",
            path=srdf.path,
        )
    own = [s for s in srdf.group_states if group is not None and s.group == group]
    # A group without c-space joints (a base holding only a planar virtual joint) is covered
    # by no state: every state would "cover" its empty c-space.
    covering = [
        s
        for s in srdf.group_states
        if cspace and s not in own and set(cspace) <= {n for n, _ in s.values}
    ]
    kinds = ((own, f"of group '{group}'"), (covering, "covering the c-space"))
    if (named := _named_home([own, covering])) is not None:
        s, k = named
        return s, f"the state named '{s.name}' {kinds[k][1]}"
    for cands, why in kinds:
        if cands:
            return cands[0], f"the first state {why}"
    return None, ""


def home_state(srdf: Srdf, group: str) -> GroupState | None:
    """The group's state named home, ready, default or neutral (in that order; ``Home`` too),
    else one with such a word in its name (``home_position``), else None: a pose the SRDF's author
    meant as the group's rest, not any pose it lists (an ``open`` hand, an ``aggressive``
    reach)."""
    named = _named_home([[s for s in srdf.group_states if s.group == group]])
    return None if named is None else named[0]


def _named_home(lists: Sequence[Sequence[GroupState]]) -> tuple[GroupState, int] | None:
    """The first state named home, ready, default or neutral, and the index of its list: named so
    exactly in any list first, then with such a word in its name; lists in order, then the
    names in that order."""
    for match in (_named_preferred, _named_like_preferred):
        for k, cands in enumerate(lists):
            for pref in PREFERRED_STATES:
                for s in cands:
                    if match(s.name, pref):
                        return s, k
    return None


def _named_preferred(name: str, pref: str) -> bool:
    """``Home`` is ``home``: Interbotix and Kinova write it capitalized."""
    return name.lower() == pref


def _named_like_preferred(name: str, pref: str) -> bool:
    """``home_position``, ``ReadyPose``: the preferred name is one of the state name's words.
    Such a state, even of a larger group that covers the c-space (the Husky's two-arm
    ``home_position``), is a better default than a group's first state named otherwise (its
    ``right_aggressive``, a pose that reaches across the other arm)."""
    return pref in name_words(name)


def chain_tip_note(tree: RobotTree, group: str, tip: str) -> str:
    """The note on a chain tip taken as a tool frame (no end effector on ``group``) when
    frames are fixed below it (a flange, a hand, a TCP), which ``--tool-frame`` could name
    instead; else ''."""
    attached = [n for n, _ in fixed_below(tree, tip) if n != tip] if tip in tree.links else []
    if not attached:
        return ""
    return (
        f"tool frame '{tip}', the tip of group '{group}''s chain (the SRDF puts no end effector "
        f"on it); also rigidly attached: {name_list(attached, 6)}; --tool-frame chooses another"
    )


def effector_tool_note(tree: RobotTree, effector: str, link: str) -> str:
    """The note on an end effector's ``parent_link`` taken as a tool frame when a frame named
    like a tool frame is fixed below it (PR2's ``r_gripper_tool_frame`` below
    ``r_wrist_roll_link``), which ``--tool-frame`` could name instead; else ''."""
    named = [n for n, _ in tool_named(fixed_below(tree, link)) if n != link]
    if not named:
        return ""
    return (
        f"tool frame '{link}', the parent link of end effector '{effector}' (where MoveIt "
        f"plans it); fixed below it and named like a tool frame: {name_list(named, 4)}; "
        f"--tool-frame {named[0]} plans for that point instead"
    )
