"""What urdfdom, the URDF parser of ROS, refuses in a URDF the loader reads.

urdfdom (robot_state_publisher, MoveIt, pinocchio and every tool built on them) refuses the
whole robot when a joint lacks what the URDF specification requires: a ``<limit>`` on a
revolute or prismatic joint; ``effort`` and ``velocity`` on a ``<limit>``; ``k_velocity`` on a
``<safety_controller>``; ``damping`` or ``friction`` on a ``<dynamics>``. The loader reads such
a robot as yourdfpy and cuRobo do (a missing ``<limit>`` is ``[0, 0]``, a missing effort or
velocity no limit), so every command still works; :func:`urdfdom_refusals` says, once per
kind, at the first joint, which joints ROS would stop at.
"""

from __future__ import annotations

from typing import Any

from ..diagnostics import Diagnostic, Severity
from ..util.text import name_list

__all__ = ["RULE_ROS_REFUSES", "urdfdom_refusals"]

RULE_ROS_REFUSES = "urdf-ros-refuses"

#: What each kind of refusal means here.
_READ_AS = {
    "limit": "read here as position limits [0, 0], as yourdfpy and cuRobo do",
    "effort": "read here as no effort limit",
    "velocity": "read here as no velocity limit",
    "k_velocity": "not used here",
    "dynamics": "not used here",
}


def _refusals(el: Any) -> list[tuple[str, str, Any]]:
    """``(kind, what is missing, element)`` for each thing urdfdom refuses in joint ``el``
    (it reads the first ``<limit>``, ``<safety_controller>`` and ``<dynamics>`` only)."""
    out: list[tuple[str, str, Any]] = []
    jtype = el.get("type")
    limit = el.find("limit")
    if limit is None and jtype in ("revolute", "prismatic"):
        out.append((f"limit:{jtype}", f"{jtype} joint without <limit>", el))
    for attr in ("effort", "velocity"):
        if limit is not None and limit.get(attr) is None:
            out.append((attr, f"<limit> without '{attr}'", limit))
    safety = el.find("safety_controller")
    if safety is not None and safety.get("k_velocity") is None:
        out.append(("k_velocity", "<safety_controller> without 'k_velocity'", safety))
    dynamics = el.find("dynamics")
    if (
        dynamics is not None
        and dynamics.get("damping") is None
        and dynamics.get("friction") is None
    ):
        out.append(("dynamics", "<dynamics> with neither 'damping' nor 'friction'", dynamics))
    return out


def urdfdom_refusals(root: Any, path: str) -> list[Diagnostic]:
    """One ``urdf-ros-refuses`` warning per kind of refusal in the ``<robot>`` element
    ``root``, at the first element that has it, naming the joints (the spec requires what is
    missing; urdfdom stops at it)."""
    found: dict[str, tuple[str, Any, list[str]]] = {}
    for el in root.findall("joint"):
        for kind, what, at in _refusals(el):
            found.setdefault(kind, (what, at, []))[2].append(str(el.get("name")))
    out = []
    for kind, (what, at, joints) in found.items():
        message = (
            f"{what} (joint{'s' if len(joints) > 1 else ''} {name_list(joints, 4)}): ROS's URDF "
            "parser (urdfdom: robot_state_publisher, MoveIt) refuses the robot, the URDF spec "
            f"requires it; {_READ_AS[kind.split(':')[0]]}"
        )
        line = getattr(at, "sourceline", None) or None  # 0: a xacro macro wrote it
        out.append(Diagnostic(path, line, None, RULE_ROS_REFUSES, Severity.WARNING, message))
    return out
