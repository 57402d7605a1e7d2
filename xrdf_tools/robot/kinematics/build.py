"""Building a :class:`KinematicModel` from a URDF and an XRDF's modifiers.

The steps, each one function: check that the URDF's joints form a tree over its links; apply
the modifiers (:mod:`.modifiers`); order the frames root first; fill the per-frame arrays
(joint type, origin, unit axis, the coordinate or mimic chain driving it); collect the
position limits of the actuated joints.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from ...diagnostics import Diagnostic, Severity
from ...util.arrays import BoolArray, FloatArray, IntArray
from ...util.errors import UrdfError, did_you_mean
from ...util.fixed_order import norm
from ...util.frozen import FrozenMap
from ...util.graph import reachable
from ...xrdf.model import Xrdf
from ..core import Robot, as_robot
from ..urdf_source import JointInfo
from .base import JointType
from .mimic import MimicLink, resolve_mimic
from .model import KinematicModel
from .modifiers import Edit, apply_modifiers

if TYPE_CHECKING:
    import numpy.typing as npt
    import yourdfpy


def build_kinematic_model(
    urdf: Robot | yourdfpy.URDF,
    xrdf: Xrdf | None = None,
    *,
    path: str | None = None,
) -> tuple[KinematicModel, list[Diagnostic]]:
    """Build the :class:`KinematicModel` of ``urdf`` with the modifiers of ``xrdf`` applied.

    Modifiers apply in list order: ``add_frame`` attaches a new fixed frame to a link or an
    earlier added frame; ``set_base_frame`` makes a frame the root and prunes every frame and
    joint outside its subtree; ``remove_mimic_attributes`` turns a mimic follower into an
    independent actuated joint with the given position limits.

    ``path`` overrides the URDF path used in messages (default: where it was loaded from).
    Returns the model and warnings (``joint-held-fixed``, ``joint-limits-missing``). Raises
    :class:`UrdfError` when the URDF is not a tree, a mimic refers to a missing joint or loops,
    or a modifier cannot be applied (located in the XRDF when it has a source position).
    """
    robot = as_robot(urdf)
    upath = path or robot.path
    key: Any = ("kinematic_model", upath, xrdf.modifiers if xrdf is not None else None)
    try:
        hit = robot.derived.get(key)
    except TypeError:  # an unhashable modifier: build without caching
        key, hit = None, None
    if hit is not None:
        return hit[0], list(hit[1])
    kin, diags = build_model(robot, xrdf, upath)
    if key is not None:
        robot.derived[key] = (kin, tuple(diags))
    return kin, diags


def build_model(
    robot: Robot, xrdf: Xrdf | None, upath: str
) -> tuple[KinematicModel, list[Diagnostic]]:
    """:func:`build_kinematic_model` without its cache (kept in :attr:`Robot.derived`). What
    it says about a link or joint a xacro macro made is placed where the macro writes it."""
    from ..xacro_places import located_at_elements, located_error

    diags: list[Diagnostic] = []
    report = _Report(upath, diags, robot.link_lines)
    try:
        kin = _build(report, list(robot.links), dict(robot.joints), xrdf)
    except UrdfError as e:
        raise located_error(e, robot.path, robot.include_places) from None
    return kin, located_at_elements(diags, robot.path, robot.include_places)


@dataclass(frozen=True)
class _Report:
    """Errors and warnings located in the URDF."""

    path: str
    diags: list[Diagnostic]
    link_lines: Mapping[str, int] = field(default_factory=dict)

    def error(self, msg: str, line: int | None = None) -> UrdfError:
        return UrdfError(msg, path=self.path, line=line)

    def warn(self, rule: str, msg: str, line: int | None = None) -> None:
        self.diags.append(Diagnostic(self.path, line, None, rule, Severity.WARNING, msg))


def _build(
    report: _Report,
    links: list[str],
    urdf_joints: dict[str, JointInfo],
    xrdf: Xrdf | None,
) -> KinematicModel:
    upath = report.path
    _check_tree(links, urdf_joints, report)
    edit = Edit.of_urdf(upath.replace("\\", "/").rsplit("/", 1)[-1], links, urdf_joints)
    apply_modifiers(edit, xrdf, upath)
    order, via = _topological_order(edit.frames, edit.joints, report)
    joints = [via[f] for f in order[1:]]
    actuated = tuple(j.name for j in joints if j.is_movable and not j.is_mimic)
    arrays = _frame_arrays(order, via, actuated, edit, report)
    lower, upper, continuous = _limits(actuated, edit.joints, report)
    return KinematicModel(
        frame_names=tuple(order),
        joint_of_frame=(None, *(j.name for j in joints)),
        actuated_joints=actuated,
        lower=lower,
        upper=upper,
        continuous=continuous,
        joints=FrozenMap((j.name, j) for j in joints),
        pruned_joints=tuple(edit.pruned_joints),
        pruned_frames=tuple(edit.pruned_frames),
        added_frames=tuple(f for f in edit.added if f in edit.frames),
        source_path=upath,
        parent=arrays.parent,
        joint_type=arrays.joint_type,
        origin=arrays.origin,
        axis=arrays.axis,
        q_index=arrays.q_index,
        mimic_multiplier=arrays.mimic_multiplier,
        mimic_offset=arrays.mimic_offset,
    )


def _check_tree(links: Sequence[str], joints: Mapping[str, JointInfo], report: _Report) -> None:
    """Every joint connects two known links, and no link is the child of two joints."""
    link_set = set(links)
    parent_joint: dict[str, str] = {}
    for j in joints.values():
        for role, link in (("parent", j.parent), ("child", j.child)):
            if link not in link_set:
                raise report.error(
                    f"joint '{j.name}' refers to unknown {role} link '{link}'"
                    + did_you_mean(link, links),
                    j.line,
                )
        if j.child in parent_joint:
            raise report.error(
                f"link '{j.child}' is the child of two joints, '{parent_joint[j.child]}' and "
                f"'{j.name}'; a URDF must be a tree",
                j.line,
            )
        parent_joint[j.child] = j.name


def _topological_order(
    frames: Mapping[str, None], joints: Mapping[str, JointInfo], report: _Report
) -> tuple[list[str], dict[str, JointInfo]]:
    """The frames depth-first from the single root (children in joint order), and the joint
    attaching each non-root frame to its parent."""
    children: dict[str, list[str]] = {}
    via: dict[str, JointInfo] = {}
    for j in joints.values():
        children.setdefault(j.parent, []).append(j.child)
        via[j.child] = j
    roots = [f for f in frames if f not in via]
    if not roots:
        raise report.error("the joints form a cycle: every link has a parent joint")
    if len(roots) > 1:
        shown = ", ".join(f"'{r}'" for r in roots[:5]) + (", ..." if len(roots) > 5 else "")
        raise report.error(
            f"{len(roots)} links have no parent joint ({shown}); a URDF must be a single tree "
            "(or choose a base with set_base_frame)",
            report.link_lines.get(roots[1]),
        )
    # one parent joint per frame and a root without one: no cycle is reachable from the root
    order = reachable(roots[0], lambda f: children.get(f, ()))[0]
    if len(order) != len(frames):
        reached = set(order)
        lost = [f for f in frames if f not in reached]
        raise report.error(
            f"links {', '.join(repr(x) for x in lost[:5])} are not connected to root "
            f"'{roots[0]}': the joints form a cycle"
        )
    return order, via


@dataclass
class _FrameArrays:
    """The per-frame arrays of a :class:`KinematicModel` (its field names)."""

    parent: IntArray
    joint_type: npt.NDArray[np.int8]
    origin: FloatArray
    axis: FloatArray
    q_index: IntArray
    mimic_multiplier: FloatArray
    mimic_offset: FloatArray

    @classmethod
    def empty(cls, n_frames: int) -> _FrameArrays:
        """Every frame a fixed root-like frame: no parent, identity origin, no coordinate."""
        F = n_frames
        return cls(
            parent=np.full(F, -1, dtype=np.intp),
            joint_type=np.zeros(F, dtype=np.int8),
            origin=np.tile(np.eye(4), (F, 1, 1)),
            axis=np.zeros((F, 3)),
            q_index=np.full(F, -1, dtype=np.intp),
            mimic_multiplier=np.ones(F),
            mimic_offset=np.zeros(F),
        )


def _frame_arrays(
    order: Sequence[str],
    via: Mapping[str, JointInfo],
    actuated: Sequence[str],
    edit: Edit,
    report: _Report,
) -> _FrameArrays:
    """Fill the per-frame arrays; floating/planar joints and mimics of a joint that does not
    move are held fixed (a ``joint-held-fixed`` warning)."""
    index = {f: i for i, f in enumerate(order)}
    q_of = {n: k for k, n in enumerate(actuated)}
    memo: dict[str, MimicLink] = {}
    out = _FrameArrays.empty(len(order))
    for i, f in enumerate(order[1:], start=1):
        j = via[f]
        out.parent[i] = index[j.parent]
        out.joint_type[i] = JointType.from_urdf(j.type)
        out.origin[i] = j.origin
        if j.type in ("floating", "planar"):
            report.warn(
                "joint-held-fixed",
                f"{j.type} joint '{j.name}' is held fixed at its origin (only revolute, "
                "continuous and prismatic joints move)",
                j.line,
            )
            continue
        if not j.is_movable:
            continue
        out.axis[i] = _unit_axis(j, report)
        if not j.is_mimic:
            out.q_index[i] = q_of[j.name]
            continue
        master, m, o, held_reason = resolve_mimic(
            j, edit.joints, edit.urdf_joints, edit.joint_removed_by, report.error, memo
        )
        out.mimic_multiplier[i], out.mimic_offset[i] = m, o
        if master is None:
            out.mimic_multiplier[i] = 0.0
            report.warn(
                "joint-held-fixed",
                f"mimic joint '{j.name}' is held at {o:g}: {held_reason}",
                j.line,
            )
        else:
            out.q_index[i] = q_of[master]
    return out


def _unit_axis(j: JointInfo, report: _Report) -> FloatArray:
    """The joint's axis scaled to unit length; an error for a zero or non-finite one."""
    a = np.asarray(j.axis, dtype=np.float64)
    length = norm(a)
    if not length > 1e-12 or not math.isfinite(length):
        raise report.error(f"joint '{j.name}' has a zero or invalid axis {j.axis}", j.line)
    unit: FloatArray = a / length
    return unit


def _limits(
    actuated: Sequence[str], joints: Mapping[str, JointInfo], report: _Report
) -> tuple[FloatArray, FloatArray, BoolArray]:
    """Position limits of the actuated joints: ``[-pi, pi]`` for continuous ones (marked in
    the third array), the URDF default ``[0, 0]`` (with a warning) for a joint without any."""
    lower = np.empty(len(actuated))
    upper = np.empty(len(actuated))
    cont = np.zeros(len(actuated), dtype=bool)
    for k, name in enumerate(actuated):
        j = joints[name]
        if j.type == "continuous":
            lower[k], upper[k], cont[k] = -math.pi, math.pi, True
            continue
        if j.lower is None and j.upper is None:
            report.warn(
                "joint-limits-missing",
                f"{j.type} joint '{name}' has no position limits; URDF defaults [0, 0] used",
                j.line,
            )
        lower[k] = 0.0 if j.lower is None else j.lower
        upper[k] = 0.0 if j.upper is None else j.upper
    return lower, upper, cont
