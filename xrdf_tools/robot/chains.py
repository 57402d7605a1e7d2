"""Serial chains of a URDF and the c-space and tool frame a robotics engineer would pick.

Without an SRDF group or ``--chain``/``--joints``, :func:`default_cspace` chooses the longest
serial chain of actuated (revolute, continuous, prismatic, non-mimic) joints from the root to a
leaf, leaving out what a motion planner does not plan for:

* **wheels**: joints named like ``wheel``/``caster``, and continuous joints mounted on the base
  (no movable joint above them) with no movable joint below;
* **grippers**: joints named like ``gripper``/``finger``/``hand``/``jaw``/``claw``/``thumb``/
  ``knuckle``/``palm``/``pinky`` (Valkyrie's ``leftPinkyPitch1``), every joint that a mimic
  joint follows (a mimic joint itself is never a c-space joint), and jaws and fingers named
  otherwise (:func:`_is_jaw`). A joint into a hand that fingers hang from (Shadow's
  ``rh_WRJ1``), named like a hand with a roll/pitch/yaw word (Booster T1's
  ``Left_Hand_Roll``), or named like a hand and carrying fingers that move on their own
  (Unitree H1's ``left_hand_joint``) turns the whole hand: a wrist joint;
* **heads and sensors**: joints named like ``head``/``neck``/``camera``/``eye``/``laser``/
  ``lidar``, and ``pan``/``tilt`` joints that are not arm joints (``shoulder_pan`` is an arm,
  and so is a pan/tilt unit that carries a tool frame: a wrist).

A chain ends at its first left-out joint: what hangs below a gripper or a head is not arm.
A joint whose limits hold it still (lower = upper: Toyota HSR's force-torque sensor frame) is
no c-space joint; chains and tool-frame guesses go through it as through a fixed joint.
A leg is planned for only when every chain is one: a humanoid's arm wins over a leg as long
(Unitree H1) or longer (NAO); a hand alone plans for its longest finger.
How names are read into words: :mod:`.names`; the tool frame at the end of the chosen chain:
:mod:`.tool_frame`.

Everything here is a pure function of the :class:`~xrdf_tools.robot.tree.RobotTree`; the
converter reports each choice and ``xrdf inspect`` shows it.
"""

from __future__ import annotations

import shlex
from collections.abc import Collection, Mapping, Sequence
from dataclasses import dataclass, field, replace

from ..util.graph import postorder
from ..util.text import name_list
from .names import (
    ARM,
    HEAD,
    LEG,
    TOOL_WORDS,
    JointRole,
    name_role,
    name_words,
    says_finger,
    says_hand,
    says_jaw,
    turns_hand,
)
from .tool_frame import ToolFrameGuess, guess_tool_frame
from .tree import RobotTree

__all__ = [
    "BELOW_LEFT_OUT",
    "Chain",
    "DefaultCSpace",
    "JointRole",
    "chain_flag",
    "default_cspace",
    "is_leg",
    "joint_roles",
    "leaf_chains",
    "name_words",
]


def joint_roles(tree: RobotTree) -> dict[str, JointRole]:
    """The movable joints a default c-space leaves out, with the reason (see module doc)."""
    leaders = {j.mimic_joint for j in tree.joints.values() if j.mimic_joint is not None}
    below = _Subtrees(tree, leaders)
    roles: dict[str, JointRole] = {}
    for name, j in tree.joints.items():
        if not j.is_movable:
            continue
        words = set(name_words(name))
        wrist = turns_hand(words) or _moves_hand(tree, below, name, words)
        arm = bool(words & ARM) or wrist
        role = None if wrist else name_role(name)
        carries_tool = below.tool[j.child]
        if role == "head" and carries_tool and not words & HEAD:
            role = None  # a pan/tilt unit with a tool on it is a wrist (Schunk PW70)
        if role is None and not arm and not carries_tool:
            role = name_role(j.child)
            if role == "gripper" and below.free[j.child]:
                role = None  # it moves a hand that fingers hang from: a wrist joint
        coupled = j.is_mimic or name in leaders
        if role is None and coupled and not _coupling_moves_below(tree, below, name):
            role = "gripper"
        if role is None and not wrist and _is_jaw(tree, below, name, arm):
            role = "gripper"
        if role is None and j.type == "continuous" and below.is_base_wheel(j.parent, j.child):
            role = "wheel"
        if role is not None:
            roles[name] = role
    return roles


class _Subtrees:
    """What lies above and below each link, found in one walk of the tree (a walk per joint
    would cost a long chain its length squared).

    ``tool``: a TCP, tool, end-effector or flange frame is the link or below it (the joint
    into the link is then a wrist joint, whatever the link is called, as fingers carry no
    tool frame). ``free``: an actuated joint that no mimic joint follows lies below the link;
    ``fingers``: an actuated joint named like a finger's, followed or not. ``movable``: a
    movable joint lies below it; ``movable_above``: one lies above it.
    """

    def __init__(self, tree: RobotTree, leaders: Collection[str]) -> None:
        def kids(link: str) -> list[str]:
            return [tree.joints[jn].child for jn in tree.child_joints.get(link, ())]

        order = postorder(tree.links, kids)
        self.tool: dict[str, bool] = {}
        self.free: dict[str, bool] = {}
        self.fingers: dict[str, bool] = {}
        self.movable: dict[str, bool] = {}
        for link in order:
            joints = [tree.joints[jn] for jn in tree.child_joints.get(link, ())]
            self.tool[link] = bool(set(name_words(link)) & TOOL_WORDS) or any(
                self.tool.get(k.child, False) for k in joints
            )
            self.free[link] = any(
                (k.is_actuated and k.name not in leaders) or self.free.get(k.child, False)
                for k in joints
            )
            self.fingers[link] = any(
                (k.is_actuated and says_finger(name_words(k.name)))
                or self.fingers.get(k.child, False)
                for k in joints
            )
            self.movable[link] = any(
                k.is_movable or self.movable.get(k.child, False) for k in joints
            )
        self.movable_above: dict[str, bool] = {}
        for link in reversed(order):
            jn = tree.parent_joint.get(link)
            up = tree.joints[jn] if jn is not None else None
            self.movable_above[link] = up is not None and (
                up.is_movable or self.movable_above.get(up.parent, False)
            )

    def is_base_wheel(self, parent: str, child: str) -> bool:
        """A joint from ``parent`` to ``child`` on the base (nothing movable above) with
        nothing movable below."""
        return not self.movable_above[parent] and not self.movable[child]


def _moves_hand(tree: RobotTree, below: _Subtrees, joint: str, words: set[str]) -> bool:
    """A joint named like a whole hand (no finger word) that carries finger joints moving on
    their own, off a link that is no gripper's: it moves the hand they hang from, a wrist
    joint (Unitree H1's 'left_hand_joint' above 'L_index_proximal_joint'). A hand joint that
    the fingers follow as mimics (NAO's 'LHand') closes the hand: a gripper's."""
    j = tree.joints[joint]
    return says_hand(words) and below.fingers[j.child] and name_role(j.parent) != "gripper"


def _is_jaw(tree: RobotTree, below: _Subtrees, joint: str, arm: bool) -> bool:
    """A jaw or finger whose own name says nothing, with no tool frame below: into a finger or
    jaw link with nothing actuated below, even named like an arm's (Spot's 'arm_f1x' into
    'arm_link_fngr'); not named like an arm's, on a link named like a gripper (the Piper's
    'joint7' on 'gripper_base', the Shadow Hand's 'rh_FFJ4' on 'rh_palm') or one of two or
    more prismatic joints with nothing actuated below on one link (a parallel gripper)."""
    j = tree.joints[joint]
    if below.tool[j.child]:
        return False
    if not arm and name_role(j.parent) == "gripper":
        return True  # a jaw on a gripper's base, or a finger's first joint on a palm
    if below.free[j.child]:
        return False
    if says_jaw(j.child):
        return True
    if arm or j.type != "prismatic":
        return False
    jaws = [
        s
        for s in tree.child_joints.get(j.parent, ())
        if tree.joints[s].type == "prismatic" and not below.free[tree.joints[s].child]
    ]
    return len(jaws) >= 2


def _coupling_moves_below(tree: RobotTree, below: _Subtrees, joint: str) -> bool:
    """Whether an actuated joint that no mimic joint follows lies below ``joint`` or below the
    joint it mimics: a gripper's fingers move nothing else, a torso lift's follower (a mimic
    of a joint that carries the arms) is no gripper."""
    j = tree.joints[joint]
    leader = tree.joints.get(j.mimic_joint) if j.mimic_joint is not None else None
    links = [j.child] if leader is None else [j.child, leader.child]
    return any(below.free[link] for link in links)


def chain_flag(base: str, tip: str) -> str:
    """``--chain BASE:TIP`` as a shell takes it (quoted when a name has a space or a quote,
    as CAD exports name links: ``'base link:tip 2'``)."""
    return f"--chain {shlex.quote(f'{base}:{tip}')}"


@dataclass(frozen=True)
class Chain:
    """The path from the tree's root to one leaf link.

    ``joints`` are every joint on the path (fixed ones included), root first; ``cspace`` the
    actuated joints a default c-space takes from it (ending before the first left-out joint);
    ``stopped_at`` that left-out joint, if any.
    """

    base: str
    leaf: str
    joints: tuple[str, ...]
    cspace: tuple[str, ...]
    stopped_at: str | None = None


def leaf_chains(
    tree: RobotTree,
    roles: Mapping[str, JointRole] | None = None,
    passive: Collection[str] = (),
) -> list[Chain]:
    """The chain from ``tree.root`` to every leaf link, leaves in depth-first order."""
    roles = joint_roles(tree) if roles is None else roles
    out: list[Chain] = []
    stack = [tree.root]
    seen = {tree.root}
    while stack:
        link = stack.pop()
        kids = tree.child_joints.get(link, ())
        if not kids and link != tree.root:
            out.append(_chain(tree, link, _path(tree, link), roles, passive))
        for jn in reversed(kids):
            child = tree.joints[jn].child
            if child not in seen:
                seen.add(child)
                stack.append(child)
    return out


def _path(tree: RobotTree, leaf: str) -> tuple[str, ...]:
    """The joints from ``tree.root`` down to ``leaf`` (built from the leaf: no path is kept
    per link, so a deep chain costs its depth, not its depth squared)."""
    up: list[str] = []
    link = leaf
    while link != tree.root and link in tree.parent_joint:
        jn = tree.parent_joint[link]
        up.append(jn)
        link = tree.joints[jn].parent
    return tuple(reversed(up))


def _chain(
    tree: RobotTree,
    leaf: str,
    path: tuple[str, ...],
    roles: Mapping[str, JointRole],
    passive: Collection[str],
) -> Chain:
    cspace: list[str] = []
    for jn in path:
        if jn in roles:
            return Chain(tree.root, leaf, path, tuple(cspace), jn)
        if tree.is_actuated(jn) and jn not in passive and not tree.is_held(jn):
            cspace.append(jn)
    return Chain(tree.root, leaf, path, tuple(cspace))


#: The key of :attr:`DefaultCSpace.left_out` for the joints below a left-out one.
BELOW_LEFT_OUT = "below"


@dataclass(frozen=True)
class DefaultCSpace:
    """The c-space and tool frame :func:`default_cspace` picks, and everything it weighed."""

    joints: tuple[str, ...]
    tool: ToolFrameGuess | None
    chain: Chain | None
    #: Movable joints left out, by reason (``wheel``/``gripper``/``head``, and ``below`` for
    #: the actuated joints below those), in tree order.
    left_out: Mapping[str, tuple[str, ...]] = field(default_factory=dict)
    #: Other chains with as many c-space joints and a different c-space (two arms), each
    #: with its tool frame.
    ties: tuple[tuple[Chain, ToolFrameGuess], ...] = ()
    #: Legs as long as the choice or longer, passed over for it, each with its tool frame.
    legs: tuple[tuple[Chain, ToolFrameGuess], ...] = ()
    hand_alone: bool = False  #: nothing but fingers to plan: the c-space is a finger
    #: Revolute/prismatic joints on the chosen chain held still by equal limits, left out.
    held: tuple[str, ...] = ()

    def describe(self, srdf_given: bool = False) -> str:
        """One sentence: what was chosen, what was left out, and the flags that change it
        (``srdf_given``: an SRDF was read, so the other way is a group in it, not --srdf)."""
        if self.chain is None or not self.joints:
            if not self.left_out:
                return "no serial chain of actuated joints"
            out = [_left_out_text(role, js) for role, js in self.left_out.items()]
            return "no serial chain of actuated joints besides " + ", ".join(out)
        tip = self.tool.frame if self.tool is not None else self.chain.leaf
        text = (
            f"c-space is the longest serial chain of actuated joints from '{self.chain.base}' "
            f"({len(self.joints)}: {name_list(self.joints, 12)})"
        )
        if self.hand_alone:
            text = f"the robot is a hand alone (only finger joints): {text}, a finger"
        out = [_left_out_text(role, js) for role, js in self.left_out.items()]
        if out:
            text += "; left out: " + ", ".join(out)
        if self.held:
            text += (
                f"; left out, held still by equal lower and upper limits: {name_list(self.held, 4)}"
                " (a CAD exporter writes 0 0 for limits never set: give the URDF the real ones "
                "to plan them)"
            )
        if self.ties:
            other = "; ".join(
                f"{name_list(c.cspace, 2)} ({chain_flag(c.base, t.frame)})" for c, t in self.ties
            )
            text += f"; as long: {other}"
        if self.legs:
            legs = "; ".join(
                f"{name_list(c.cspace, 2)} ({chain_flag(c.base, t.frame)})" for c, t in self.legs
            )
            text += f"; as long or longer but a leg, passed over: {legs}"
        other = "a planning group in the SRDF" if srdf_given else "--srdf"
        return text + f"; change it with {chain_flag(self.chain.base, tip)}, --joints or {other}"


def default_cspace(
    tree: RobotTree,
    passive: Collection[str] = (),
    collision_links: Collection[str] | None = None,
) -> DefaultCSpace:
    """The longest serial chain of actuated joints from the root (see the module doc).

    ``passive`` joints never enter the c-space. A leg (``hip``/``knee``/``ankle`` names, no
    ``shoulder``/``elbow``/``wrist`` ones) is taken only when every chain is one. Among chains
    of equal length, one whose tool frame has a tool-like name wins, then an arm, then the
    first in depth-first order (siblings by name).
    """
    roles = joint_roles(tree)
    chains = leaf_chains(tree, roles, passive)
    order = tree.dfs_joints()
    left_out: dict[str, tuple[str, ...]] = {}
    for role in ("wheel", "gripper", "head"):
        names = tuple(j for j in order if roles.get(j) == role)
        if names:
            left_out[role] = names
    if below := _below_left_out(tree, roles, order):
        left_out[BELOW_LEFT_OUT] = below
    hand = not any(c.cspace for c in chains) and "gripper" in left_out
    if hand:  # a hand alone (its root the palm): its longest finger, if it has joints
        fingers = leaf_chains(tree, {j: r for j, r in roles.items() if r != "gripper"}, passive)
        chains = fingers if max((len(c.cspace) for c in fingers), default=0) >= 2 else chains
    legs = {c.cspace for c in chains if c.cspace and is_leg(tree, c.cspace)}
    pool = [c for c in chains if c.cspace and c.cspace not in legs] or chains
    best_len = max((len(c.cspace) for c in pool), default=0)
    if best_len == 0:
        return DefaultCSpace((), None, None, left_out)
    distinct = _distinct([c for c in pool if len(c.cspace) == best_len])
    guesses = {cs: guess_tool_frame(tree, cs[-1], collision_links) for cs in distinct}
    pick = min(distinct, key=lambda cs: (not guesses[cs].named, *_limb_rank(tree, cs)))
    ties = tuple((c, guesses[cs]) for cs, c in distinct.items() if cs != pick)
    # legs passed over for an arm; when every chain is a leg the others are ties, said once
    long_legs = _distinct(
        [c for c in chains if c.cspace in legs and len(c.cspace) >= best_len]
        if pick not in legs
        else []
    )
    passed = tuple(
        (c, guess_tool_frame(tree, cs[-1], collision_links))
        for cs, c in long_legs.items()
        if cs != pick
    )
    chosen = distinct[pick]
    on_path = (
        chosen.joints[: chosen.joints.index(chosen.stopped_at)]
        if chosen.stopped_at
        else chosen.joints
    )
    held = tuple(j for j in on_path if tree.joints[j].is_held)
    out = DefaultCSpace(pick, guesses[pick], chosen, left_out, ties, passed, held=held)
    return replace(out, left_out={}, hand_alone=True) if hand else out


def _left_out_text(role: str, joints: Sequence[str]) -> str:
    if role == BELOW_LEFT_OUT:
        return f"{len(joints)} joint(s) below those ({name_list(joints, 4)})"
    return f"{len(joints)} {role} joint(s) ({name_list(joints, 4)})"


def _below_left_out(
    tree: RobotTree, roles: Mapping[str, JointRole], order: Sequence[str]
) -> tuple[str, ...]:
    """The actuated joints without a role of their own below a left-out joint (an Allegro
    finger's joints below its first): left out with it, as a chain ends there."""
    out: list[str] = []
    for jn in order:
        if jn in roles or not tree.is_actuated(jn):
            continue
        link = tree.joints[jn].parent
        while (up := tree.parent_joint.get(link)) is not None and up not in roles:
            link = tree.joints[up].parent
        if up is not None:
            out.append(jn)
    return tuple(out)


def _distinct(chains: Sequence[Chain]) -> dict[tuple[str, ...], Chain]:
    """The first chain of each c-space, in order."""
    out: dict[tuple[str, ...], Chain] = {}
    for c in chains:
        out.setdefault(c.cspace, c)
    return out


def _limb_words(tree: RobotTree, joints: Sequence[str]) -> set[str]:
    """The words of ``joints`` and of the links they move."""
    words: set[str] = set()
    for jn in joints:
        words.update(name_words(jn), name_words(tree.joints[jn].child))
    return words


def is_leg(tree: RobotTree, joints: Sequence[str]) -> bool:
    """Whether ``joints`` are a leg's (or legs'): named like legs (hip, knee, ankle, foot …)
    and nothing like an arm. A planner plans arms, not legs."""
    words = _limb_words(tree, joints)
    return bool(words & LEG) and not words & ARM


def _limb_rank(tree: RobotTree, cspace: Sequence[str]) -> tuple[bool, bool]:
    """Sort key of a chain among equally long ones: an arm first, a leg last."""
    words = _limb_words(tree, cspace)
    arm = bool(words & ARM)
    return (bool(words & LEG) and not arm, not arm)
