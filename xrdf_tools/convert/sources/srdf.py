"""MoveIt SRDF onto a Draft: planning group(s) → c-space, a group state → default positions,
end effectors and chain tips → tool frames, collision masks → self-collision ignore, sphere
approximations → spheres (mapping: docs/convert.md, "Sources").

The parser is :mod:`.srdf_parse`, group expansion and choice :mod:`.srdf_groups`; their public
names are re-exported here.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import replace

from ...diagnostics import Severity
from ...util.errors import SourceError, did_you_mean
from ...util.text import name_list, pair_text
from ...xrdf.model import Sphere
from . import Draft, Reporter, RobotTree, known_frame
from .srdf_groups import (
    PREFERRED_STATES,
    carries_end_effector,
    chain_tip_note,
    check_groups,
    choose_group,
    choose_state,
    cspace_of,
    effector_tool_note,
    group_joints,
    group_named,
    group_sizes,
    home_state,
    unused_cycles,
)
from .srdf_parse import EndEffector, GroupState, Srdf, SrdfGroup, load_srdf, parse_srdf

RULE_UNUSED_GROUP = "convert-srdf-unused-group"

__all__ = [
    "PREFERRED_STATES",
    "EndEffector",
    "GroupState",
    "Srdf",
    "SrdfGroup",
    "check_groups",
    "choose_group",
    "choose_state",
    "cspace_of",
    "group_joints",
    "group_sizes",
    "load_srdf",
    "parse_srdf",
    "read_srdf",
]


def read_srdf(
    srdf: Srdf,
    tree: RobotTree,
    *,
    group: str | Sequence[str] | None = None,
    state: str | None = None,
    draft: Draft | None = None,
    choose: bool = True,
) -> Draft:
    """Map an SRDF onto a :class:`Draft` (mapping: docs/convert.md, "Sources").

    ``group`` is one group or several (their union, in the given order: a dual-arm c-space);
    none chooses one (see :func:`choose_group`) unless ``choose`` is false (the c-space is
    given otherwise). The groups used (and their subgroups) must match the URDF
    (:func:`check_groups` raises); any other group that does not is a located warning
    (``convert-srdf-unused-group``), as are other SRDF elements naming what the URDF lacks.
    """
    d = draft or Draft()
    rep = Reporter(srdf.path)
    srdf = _known_end_effectors(srdf, rep)
    groups = [group] if isinstance(group, str) else list(dict.fromkeys(group or ()))
    for g in groups:
        group_named(srdf, g)
    if not groups and choose:
        groups = _choose(srdf, tree, rep)
    for broken, problems in check_groups(srdf, tree, groups):
        rep.report(
            RULE_UNUSED_GROUP,
            f"group '{broken.name}' does not match the URDF ({'; '.join(problems)}); it is not "
            "used for this conversion, so it is ignored",
            at=srdf.at(broken),
        )
    for looped, cycle in unused_cycles(srdf, groups):
        rep.report(
            RULE_UNUSED_GROUP,
            f"group '{looped.name}' includes itself through its subgroups ({cycle}); it is not "
            "used for this conversion, so it is ignored",
            at=srdf.at(looped),
        )
    d.group = "+".join(groups) or None
    d.passive_joints |= _passive_joints(srdf, tree, rep)
    if groups:
        cspace = [j for g in groups for j in cspace_of(srdf, g, tree)]
        d.cspace = list(dict.fromkeys(cspace))
    _defaults(srdf, tree, groups, state, d, rep)
    if groups:
        d.tool_frames = _tool_frames(srdf, tree, groups, rep)

    _mask(srdf, tree, d, rep)
    _virtual(srdf, tree, rep)
    _spheres(srdf, tree, d, rep)
    d.diagnostics.extend(srdf.warnings)
    d.diagnostics.extend(rep.diagnostics)
    return d


def _known_end_effectors(srdf: Srdf, rep: Reporter) -> Srdf:
    """``srdf`` without the end effectors MoveIt drops: one without a ``group``, or naming a
    ``group`` or ``parent_group`` the SRDF does not define (srdfdom logs an error and skips
    it). Each is a located warning; kept, it would pick tool frames and rank groups (the
    dual-arm Panda's ``left_hand``/``right_hand`` end effectors name groups it lacks)."""
    kept = []
    for ee in srdf.end_effectors:
        problems = [] if ee.group else ["has no group"]
        for attr, name in (("group", ee.group), ("parent_group", ee.parent_group)):
            if name and name not in srdf.groups:
                # not the arm it hangs from: the end effector's own group is what is missing
                others = [g for g in srdf.groups if g != ee.parent_group]
                problems.append(
                    f"names {attr} '{name}', which the SRDF does not define"
                    f"{did_you_mean(name, others)}"
                )
        if not problems:
            kept.append(ee)
            continue
        rep.report(
            "convert-srdf-end-effector",
            f"end_effector '{ee.name}' {' and '.join(problems)}: MoveIt skips it, and so does "
            "this conversion (no tool frame or group choice from it)",
            at=srdf.at(ee),
        )
    if len(kept) == len(srdf.end_effectors):
        return srdf
    return replace(srdf, end_effectors=tuple(kept))


#: Unknown links of disable_collisions entries named one by one; the rest are counted.
_UNKNOWN_NAMED = 10


def _mask(srdf: Srdf, tree: RobotTree, d: Draft, rep: Reporter) -> None:
    """The self-collision mask: disabled pairs of known links, minus re-enabled pairs.

    A link the URDF lacks is reported once, at its first entry, with the number of entries
    that name it (an SRDF written for another base names its links in dozens of pairs); past
    ten such links, the others are counted in one more warning."""
    unknown: dict[str, list[tuple[str, tuple[str, int | None]]]] = {}
    for l1, l2, _reason, line in srdf.disable_collisions:
        at = srdf.where(("disable_collisions", l1, l2), line)
        for link, key in ((l1, "link1"), (l2, "link2")):
            if link not in tree.links:
                unknown.setdefault(link, []).append((key, at))
        if l1 == l2 and l1 in tree.links:
            rep.report(
                "convert-dropped-key",
                f"disable_collisions names '{l1}' twice: a link is never checked against "
                "itself, so there is no pair to carry",
                severity=Severity.INFO,
                at=at,
            )
        elif l1 in tree.links and l2 in tree.links:
            d.add_ignore(l1, l2)
    named = list(unknown.items())
    for link, uses in named[:_UNKNOWN_NAMED]:
        key, at = uses[0]
        what = f"disable_collisions {key}"
        if len(uses) > 1:
            what = f"in {len(uses)} disable_collisions entries, first as {key}"
        known_frame(link, tree.links, rep, "", what, at=at)
    rest = named[_UNKNOWN_NAMED:]
    if rest:
        rep.report(
            "convert-unknown-link",
            f"{len(rest):,} more links of disable_collisions entries are not links of the "
            f"URDF ({name_list((n for n, _ in rest), 4)}); dropped: was the SRDF written for "
            "another robot?",
            at=rest[0][1][0][1],
        )
    for link, line in srdf.disable_default:
        at = srdf.where(("disable_default_collisions", link), line)
        if known_frame(link, tree.links, rep, "", "disable_default_collisions", at=at):
            for other in tree.links:
                d.add_ignore(link, other)
    for l1, l2, line in srdf.enable_collisions:
        rep.report(
            "convert-dropped-key",
            f"enable_collisions {pair_text(l1, l2)} re-enables a pair; XRDF has no override, so "
            "the pair is checked unless disabled above",
            severity=Severity.INFO,
            at=srdf.where(("enable_collisions", l1, l2), line),
        )
        if l2 in d.ignore.get(l1, []):
            d.ignore[l1].remove(l2)
        if l1 in d.ignore.get(l2, []):
            d.ignore[l2].remove(l1)


def _virtual(srdf: Srdf, tree: RobotTree, rep: Reporter) -> None:
    """Each virtual joint is reported as not represented; one whose ``child_link`` is no
    link of the URDF (srdfdom skips it) says so: the SRDF was written for another URDF of the
    robot (Neuromeka's MoveIt config loads ``indy7_fixed.xacro``, which adds ``world``)."""
    for vj in srdf.virtual_joints:
        if vj.child and vj.child not in tree.links:
            rep.report(
                "convert-unknown-link",
                f"virtual_joint '{vj.name}' attaches '{vj.child}', which is not a link of the "
                f"URDF (MoveIt skips it){did_you_mean(vj.child, tree.links)}: is this the SRDF "
                "of another URDF of the robot?",
                at=srdf.at(vj),
            )
            continue
        rep.report(
            "convert-virtual-joint",
            f"virtual_joint '{vj.name}' ({vj.type}) is not represented: XRDF is relative to "
            "the URDF root",
            severity=Severity.INFO,
            at=srdf.at(vj),
        )


def _spheres(srdf: Srdf, tree: RobotTree, d: Draft, rep: Reporter) -> None:
    """Sphere approximations of known links (radii <= 0 dropped)."""
    if srdf.spheres:
        spheres: dict[str, list[Sphere]] = {}
        for link, ss, line in srdf.spheres:
            at = srdf.where(("link_sphere_approximation", link), line)
            if not known_frame(link, tree.links, rep, "", "link_sphere_approximation", at=at):
                continue
            kept = [s for s in ss if s.radius > 0]
            if len(kept) < len(ss) and kept:
                rep.report(
                    "convert-placeholder-spheres",
                    f"{len(ss) - len(kept)} sphere(s) of radius ≤ 0 on '{link}' dropped",
                    severity=Severity.INFO,
                    at=at,
                )
            if kept:
                spheres.setdefault(link, []).extend(kept)
        d.spheres = spheres


def _passive_joints(srdf: Srdf, tree: RobotTree, rep: Reporter) -> set[str]:
    """The SRDF's passive joints that are joints of the URDF. A virtual joint of the SRDF may
    be passive too (as MoveIt reads it; it is no c-space joint anyway); the others are
    reported at their line."""
    out: set[str] = set()
    virtual = {vj.name for vj in srdf.virtual_joints}
    lines = srdf.passive_joint_lines or (None,) * len(srdf.passive_joints)
    for name, line in zip(srdf.passive_joints, lines, strict=True):
        if name in tree.joints:
            out.add(name)
            continue
        if name in virtual:
            continue
        rep.report(
            "convert-unknown-joint",
            f"passive_joint '{name}' is not a joint of the URDF{did_you_mean(name, tree.joints)}"
            "; ignored",
            at=srdf.where(("passive_joint", name), line),
        )
    return out


def _choose(srdf: Srdf, tree: RobotTree, rep: Reporter) -> list[str]:
    group, why = choose_group(srdf, tree)
    if group is None:
        return []
    sizes = group_sizes(srdf, tree)
    others = [
        f"{g} ({'does not match the URDF' if sizes[g] is None else sizes[g]})"
        for g in srdf.groups
        if g != group
    ]
    rep.report(
        "convert-chosen-group",
        f"planning group '{group}' chosen: {why}"
        + (f"; others (actuated joints): {name_list(others)}" if others else "")
        + "; use --group (repeatable for several groups)",
        at=srdf.at(srdf.groups[group]),
        # the only group of the SRDF (UR's ur_manipulator) is no guess: a note, not a warning
        severity=Severity.WARNING if others else Severity.INFO,
    )
    return [group]


def _defaults(
    srdf: Srdf,
    tree: RobotTree,
    groups: list[str],
    state: str | None,
    d: Draft,
    rep: Reporter,
) -> None:
    """Default positions from one group_state per group (the first group wins a conflict);
    a group without states takes its subgroups' (Baxter's both_arms: left_neutral and
    right_neutral)."""
    chosen: list[GroupState] = []
    targets: list[str | None] = [*groups] or [None]
    seen: set[str | None] = set()
    while targets:
        g = targets.pop(0)
        if g in seen:
            continue
        seen.add(g)
        cspace = cspace_of(srdf, g, tree) if g is not None else (d.cspace or [])
        st, why = choose_state(srdf, g, cspace, state)
        if st is None and g is not None and g in srdf.groups:
            targets[:0] = srdf.groups[g].subgroups
        if st is None or st in chosen:
            continue
        chosen.append(st)
        if why != "requested":
            rep.report(
                "convert-chosen-state",
                f"default positions from group_state '{st.name}' ({why})",
                at=srdf.at(st),
            )
    if state is None and groups:
        chosen += _states_inside(srdf, tree, d.cspace or [], chosen, rep)
    if state is None:
        chosen += _states_of_held(srdf, tree, d.cspace or [], chosen, rep)
    for st in chosen:
        for jname, value in st.values:
            if _state_value_ok(srdf, tree, st, jname, rep) and jname not in d.defaults:
                d.defaults[jname] = value
                d.default_at[jname] = srdf.at(st)


def _more_states(
    srdf: Srdf,
    tree: RobotTree,
    chosen: list[GroupState],
    fits: Callable[[set[str]], bool],
    pick: Callable[[str, list[str]], tuple[GroupState | None, str]],
) -> list[tuple[str, list[str], GroupState, str]]:
    """``(group, its c-space, state, why)`` for the groups, in SRDF order, whose c-space
    ``fits`` and still has joints without a value (after ``chosen`` and the states taken
    before), and whose ``pick`` gives a state not taken yet; broken groups are skipped (warned
    about where they are checked)."""
    given = {n for st in chosen for n, _ in st.values}
    taken: list[tuple[str, list[str], GroupState, str]] = []
    for g in srdf.groups:
        try:
            joints = cspace_of(srdf, g, tree)
        except SourceError:
            continue
        if not (joints and fits(set(joints)) and set(joints) - given):
            continue
        st, why = pick(g, joints)
        if st is None or st in chosen or st in [t[2] for t in taken]:
            continue
        taken.append((g, joints, st, why))
        given |= {n for n, _ in st.values}
    return taken


def _states_inside(
    srdf: Srdf, tree: RobotTree, cspace: list[str], chosen: list[GroupState], rep: Reporter
) -> list[GroupState]:
    """States of other groups whose c-space lies inside ``cspace``, for the c-space joints the
    chosen states leave without a value (Galaxea R1's mobile_both_arms: its subgroups have no
    state, its arms' 'home' is a state of the group both_arms), in SRDF order."""
    inside = set(cspace)
    taken = _more_states(
        srdf, tree, chosen, lambda js: js <= inside, lambda g, js: choose_state(srdf, g, js, None)
    )
    for _, joints, st, why in taken:
        rep.report(
            "convert-chosen-state",
            f"default positions of {name_list(sorted(set(joints) & inside), 4)} from "
            f"group_state '{st.name}' ({why}; a group inside the c-space)",
            at=srdf.at(st),
        )
    return [st for _, _, st, _ in taken]


def _states_of_held(
    srdf: Srdf, tree: RobotTree, cspace: list[str], chosen: list[GroupState], rep: Reporter
) -> list[GroupState]:
    """The home states (:func:`home_state`) of groups outside the c-space, for their joints the
    chosen states leave without a value: every reader holds those joints at their default, so
    the other arm of a two-arm robot converted for one is held at its ``ready``, not at 0."""
    planned = set(cspace)
    taken = _more_states(
        srdf, tree, chosen, lambda js: not js & planned, lambda g, _: (home_state(srdf, g), "")
    )
    for g, joints, st, _ in taken:
        rep.report(
            "convert-chosen-state",
            f"joints outside the c-space ({name_list(joints, 4)}) held at group_state "
            f"'{st.name}' of group '{g}', where every reader holds them",
            severity=Severity.INFO,
            at=srdf.at(st),
        )
    return [st for _, _, st, _ in taken]


def _state_value_ok(srdf: Srdf, tree: RobotTree, st: GroupState, jname: str, rep: Reporter) -> bool:
    j = tree.joints.get(jname)
    virtual = next((v for v in srdf.virtual_joints if v.name == jname), None)
    if j is None and virtual is not None:
        rep.report(
            "convert-dropped-joint-value",
            f"group_state '{st.name}' sets the SRDF's {virtual.type} virtual joint '{jname}' "
            f"(where '{virtual.child or 'the root link'}' stands): an XRDF places no base, so "
            "it is not a default position; dropped",
            severity=Severity.INFO,
            at=srdf.at(st),
        )
        return False
    if j is None and jname in st.multi:
        rep.report(
            "convert-dropped-joint-value",
            f"group_state '{st.name}' gives '{jname}' several numbers, a base's pose (as "
            "Pinocchio's floating root joint takes), and the URDF has no such joint: an XRDF "
            "places no base, so it is not a default position; dropped",
            severity=Severity.INFO,
            at=srdf.at(st),
        )
        return False
    if j is None:
        rep.report(
            "convert-unknown-joint",
            f"group_state '{st.name}' sets '{jname}', which is not a joint of the "
            f"URDF{did_you_mean(jname, tree.joints)}; dropped",
            at=srdf.at(st),
        )
        return False
    if not j.is_actuated or jname in srdf.passive_joints:
        kind = "a mimic" if j.is_mimic else ("a passive" if j.is_movable else f"a {j.type}")
        rep.report(
            "convert-dropped-joint-value",
            f"group_state '{st.name}' sets '{jname}', which is {kind} joint; "
            "XRDF default positions hold only actuated joints; dropped",
            severity=Severity.INFO,
            at=srdf.at(st),
        )
        return False
    if jname in st.multi:
        rep.report(
            "convert-dropped-joint-value",
            f"group_state '{st.name}' gives '{jname}' several numbers; a {j.type} joint takes "
            "one, so MoveIt and pinocchio ignore the value; dropped",
            severity=Severity.INFO,
            at=srdf.at(st),
        )
        return False
    return True


def _tool_frames(srdf: Srdf, tree: RobotTree, groups: list[str], rep: Reporter) -> list[str]:
    """Per group in order: end effectors attached to it (or its subgroups), then chain tips.

    An end effector without ``parent_group`` belongs, as in MoveIt, to the group that moves
    its ``parent_link`` (Interbotix: ``ee_gripper_link`` on a group of joints)."""
    frames: list[str] = []
    for group in groups:
        members = _subgroups(srdf, group)
        effectors = []
        for ee in srdf.end_effectors:
            owned = any(carries_end_effector(srdf, g, ee, tree) for g in members)
            if owned and known_frame(
                ee.parent_link, tree.links, rep, "", f"end effector '{ee.name}'", at=srdf.at(ee)
            ):
                effectors.append(ee.parent_link)
                if note := effector_tool_note(tree, ee.name, ee.parent_link):
                    info = Severity.INFO
                    rep.report("convert-chosen-tool-frame", note, severity=info, at=srdf.at(ee))
        frames += effectors
        for gname in members:
            for _, tip in srdf.groups[gname].chains:
                frames.append(tip)
                note = "" if effectors else chain_tip_note(tree, gname, tip)
                if note:
                    at = srdf.at(srdf.groups[gname])
                    rep.report("convert-chosen-tool-frame", note, severity=Severity.INFO, at=at)
    return list(dict.fromkeys(frames))


def _subgroups(srdf: Srdf, name: str) -> list[str]:
    out: list[str] = []
    seen: set[str] = set()
    stack = [name]
    while stack:
        g = stack.pop()
        if g in seen or g not in srdf.groups:
            continue
        seen.add(g)
        out.append(g)
        stack.extend(reversed(srdf.groups[g].subgroups))
    return out
