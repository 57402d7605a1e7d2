"""Mimic chains: which actuated joint drives a mimic follower, and how.

A follower moves as ``multiplier * q_master + offset``; when its master is itself a follower
the chain is folded into one multiplier and offset on the actuated joint at its end.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping

from ...util.errors import did_you_mean
from ...util.graph import show_path
from ..urdf_source import JointInfo

MimicLink = tuple[str | None, float, float, str]
"""``(actuated master or None, multiplier, offset, why the follower is held when no master)``."""


def resolve_mimic(
    j: JointInfo,
    joints: Mapping[str, JointInfo],
    urdf_joints: Mapping[str, JointInfo],
    removed_by: Mapping[str, str],
    uerr: Callable[[str, int | None], Exception],
    memo: dict[str, MimicLink] | None = None,
) -> MimicLink:
    """Follow a mimic chain: ``(actuated master or None, multiplier, offset, why held)``.

    Every joint of the chain is resolved once and kept in ``memo`` (shared by the calls of one
    model build), so long chains cost linear time. ``uerr(message, line)`` makes the error for
    a loop or a mimic of a name that is no joint; a master pruned by ``set_base_frame`` or a
    joint that does not move holds the follower (master None, the reason last).
    """
    memo = {} if memo is None else memo
    chain: list[JointInfo] = []  # mimic joints, each following the next
    seen: set[str] = set()
    cur = j
    while True:
        if cur.name in memo:
            result = memo[cur.name]
            break
        chain.append(cur)
        seen.add(cur.name)
        target = cur.mimic_joint
        assert target is not None
        if target in seen:
            names = [c.name for c in chain]
            loop = show_path([*names[names.index(target) :], target])
            raise uerr(f"mimic joints form a loop: {loop}", j.line)
        if target not in joints:
            if target in removed_by:
                why = f"it mimics '{target}', removed by set_base_frame '{removed_by[target]}'"
                result = (None, 1.0, 0.0, why)
                break
            raise uerr(
                f"joint '{cur.name}' mimics '{target}', which is not a joint"
                + did_you_mean(target, urdf_joints),
                cur.line,
            )
        nxt = joints[target]
        if not nxt.is_movable:
            result = (None, 1.0, 0.0, f"it mimics '{target}', a {nxt.type} joint")
            break
        if nxt.mimic_joint is None:
            result = (nxt.name, 1.0, 0.0, "")
            break
        cur = nxt
    # q_c = c.mult * q_next + c.offset, folded from the end of the chain back to j
    for c in reversed(chain):
        master, m, o, why = result
        result = (master, c.mimic_multiplier * m, c.mimic_multiplier * o + c.mimic_offset, why)
        memo[c.name] = result
    return result
