"""What a chosen ``--target`` needs of a conversion, fixed or checked before the slow work.

:func:`order_for_target` fixes what has a known fix: cuRobo fills default positions in the
URDF's joint order and pairs them with ``cspace.joint_names`` in the file's order, so for
``--target curobo`` a c-space in another order is put in the URDF's order (default positions
are kept by joint name) and the change is reported. :func:`target_errors` lints the XRDF
before spheres are fitted: findings for the target that fitting and the mask cannot change
stop the command before minutes of fitting.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

from ..diagnostics import Diagnostic, Severity
from ..util.text import name_list
from ..xrdf.readers import parse_target

if TYPE_CHECKING:
    from ..robot.core import Robot
    from .sources import Reporter, RobotTree

__all__ = ["RULE_ORDER", "RULE_STOPPED", "order_for_target", "target_errors"]

RULE_ORDER = "convert-cspace-order"
RULE_STOPPED = "convert-target-check"

#: XRDF sections that sphere fitting and the computed mask never change: a target's error
#: located there stays whatever is fitted. Errors elsewhere (spheres, the mask, the geometry
#: groups) are decided after fitting.
_FIXED_SECTIONS = (
    "format",
    "format_version",
    "modifiers",
    "cspace",
    "default_joint_positions",
    "tool_frames",
)


def order_for_target(
    cspace: Sequence[str], tree: RobotTree, target: str | None, rep: Reporter
) -> list[str]:
    """``cspace`` in the order ``target`` needs (reported when it changes)."""
    chosen = parse_target(target)
    names = list(cspace)
    if chosen is None or chosen.id != "curobo" or any(j not in tree.joints for j in names):
        return names
    wanted = set(names)
    urdf_order = [j for j in tree.joints if j in wanted]
    if urdf_order == names:
        return names
    rep.report(
        RULE_ORDER,
        f"--target {chosen.id}: c-space put in the URDF's joint order "
        f"({name_list(urdf_order, 12)}) instead of {name_list(names, 12)}: default "
        f"positions are filled in URDF order by {chosen.label}, which would scramble them "
        "otherwise; default positions (SRDF states) are kept by joint name",
        "cspace.joint_names",
    )
    return urdf_order


def target_errors(
    text: str, robot: Robot, target: str | None, label: str, empty_cspace: bool = False
) -> list[Diagnostic]:
    """Lint errors of ``text`` for ``target`` that fitting spheres cannot remove.

    Empty without a target. When there are any, a last ``convert-target-check`` error says
    that the fitting was not started, and, with ``empty_cspace``, that the c-space is empty
    (the cause of a missing tool frame, and what the user must choose first)."""
    chosen = parse_target(target)
    if chosen is None:
        return []
    from ..lint import lint_text

    found = [
        d
        for d in lint_text(text, label, urdf_model=robot, target=chosen.id)
        if d.severity is Severity.ERROR and _section(d.key_path) in _FIXED_SECTIONS
    ]
    if not found:
        return []
    stop = Diagnostic(
        label,
        None,
        None,
        RULE_STOPPED,
        Severity.ERROR,
        f"the XRDF would fail --target {chosen.id} whatever spheres are fitted "
        f"({len(found)} error(s), each on its own line): stopped before fitting"
        + (_EMPTY_CSPACE if empty_cspace else ""),
        "",
    )
    return [*found, stop]


_EMPTY_CSPACE = "; the c-space is empty: choose its joints with --joints, --chain or --srdf"


def _section(key_path: str) -> str:
    """The top-level key of ``key_path`` (``cspace.joint_names[2]`` → ``cspace``)."""
    for i, ch in enumerate(key_path):
        if ch in ".[":
            return key_path[:i]
    return key_path
