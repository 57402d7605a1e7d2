"""Kinematics of a URDF with the XRDF modifiers applied, as flat arrays; batched FK.

:func:`build_kinematic_model` turns a URDF (and optionally an XRDF's ``modifiers``) into a
:class:`KinematicModel`: one entry per frame in topological order (root first), each frame
attached to its parent by at most one joint. :func:`fk` and :func:`fk_rt` evaluate forward
kinematics for a batch of configurations at once, looping only over frames.

Conventions
-----------
* A configuration ``q`` has one value per *actuated* joint (movable and not a mimic follower),
  in :attr:`KinematicModel.actuated_joints` order: radians for revolute and continuous joints,
  metres for prismatic ones.
* A mimic follower moves as ``multiplier * q_master + offset``; chains of mimics are resolved
  to the actuated joint at their end.
* Floating and planar joints are held fixed at their origin (a ``joint-held-fixed`` warning).
* Poses are relative to the root frame: the URDF root, or the last ``set_base_frame``.
"""

from __future__ import annotations

import math
import threading
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from enum import IntEnum
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

from .diagnostics import Diagnostic, Severity
from .errors import UrdfError, did_you_mean
from .frozen import FrozenMap
from .graph import show_path
from .model import AddFrame, RemoveMimicAttributes, SetBaseFrame, Xrdf
from .urdf_source import JointInfo, joints_of, links_of, urdf_path

if TYPE_CHECKING:
    import yourdfpy

FloatArray = npt.NDArray[np.float64]
IntArray = npt.NDArray[np.intp]
BoolArray = npt.NDArray[np.bool_]
FrameSelection = Sequence[int | str] | npt.NDArray[np.integer[Any]] | None

__all__ = [
    "JointType",
    "KinematicModel",
    "build_kinematic_model",
    "default_configuration",
    "fk",
    "fk_batch_last",
    "fk_rt",
    "full_configuration",
]


class JointType(IntEnum):
    """Code of the joint that attaches a frame to its parent (the root uses ``FIXED``)."""

    FIXED = 0
    REVOLUTE = 1
    CONTINUOUS = 2
    PRISMATIC = 3
    FLOATING = 4
    PLANAR = 5

    @classmethod
    def from_urdf(cls, name: str) -> JointType:
        return cls[name.upper()]


# How the FK loop treats a frame.
_KIND_FIXED, _KIND_ROT, _KIND_PRISM = 0, 1, 2


@dataclass(frozen=True)
class _FkPlan:
    """Per-frame constants for :func:`fk_rt` (index 0, the root, is unused).

    The constants of frame ``f`` form a (3, c) matrix ``M`` multiplied by the parent rotation:
    fixed ``[A | t]``, revolute ``[A | A·K | A·aaᵀ − A | t]``, prismatic ``[A | t | A·a]``,
    where ``A``/``t`` are the joint origin's rotation/translation, ``a`` the unit axis and
    ``K`` its cross-product matrix (Rodrigues: ``A·R(θ) = A + sinθ·A·K + (1−cosθ)(A·aaᵀ − A)``).
    """

    parents: tuple[int, ...]
    kinds: tuple[int, ...]
    consts_t: tuple[FloatArray, ...]  # (c, 3): the constants transposed, for the matmul
    consts_root: tuple[FloatArray, ...]  # (3, c, 1): the product when the parent is the root
    rows: tuple[int, ...]  # prismatic: row of the joint values; revolute: row of sin/cos
    row_q: IntArray  # [n_rows] index into q
    row_mult: FloatArray  # [n_rows]
    row_off: FloatArray  # [n_rows]
    rot_rows: IntArray  # rows of revolute/continuous joints (the ones needing sin/cos)


@dataclass(frozen=True, eq=False)
class KinematicModel:
    """A kinematic tree as flat arrays in topological order (``parent[i] < i``, root first).

    Per frame (``F = len(frame_names)``):

    * ``parent`` [F] int: parent frame index, -1 for the root;
    * ``joint_of_frame`` [F]: name of the joint attaching the frame to its parent (None: root);
    * ``joint_type`` [F] int8: :class:`JointType` code;
    * ``origin`` [F, 4, 4]: joint origin in the parent frame (identity for the root);
    * ``axis`` [F, 3]: unit joint axis (zero for fixed joints);
    * ``q_index`` [F] int: index into the configuration vector driving the frame, -1 if none;
    * ``mimic_multiplier``, ``mimic_offset`` [F]: joint value ``= mult * q[q_index] + offset``
      (1 and 0 for actuated joints; a movable frame with ``q_index == -1`` stays at ``offset``).

    Per actuated joint (``n = len(actuated_joints)``): ``lower``, ``upper`` [n] position limits
    (``-pi``, ``pi`` for continuous joints, marked in ``continuous`` [n] bool).

    ``joints`` holds every joint kept after the modifiers (URDF joints, as changed by
    ``remove_mimic_attributes``, and added frames' joints) in topological order;
    ``pruned_joints``/``pruned_frames`` list what ``set_base_frame`` removed.
    """

    frame_names: tuple[str, ...]
    parent: IntArray
    joint_of_frame: tuple[str | None, ...]
    joint_type: npt.NDArray[np.int8]
    origin: FloatArray
    axis: FloatArray
    q_index: IntArray
    mimic_multiplier: FloatArray
    mimic_offset: FloatArray
    actuated_joints: tuple[str, ...]
    lower: FloatArray
    upper: FloatArray
    continuous: BoolArray
    joints: Mapping[str, JointInfo] = field(default_factory=FrozenMap)
    pruned_joints: tuple[str, ...] = ()
    pruned_frames: tuple[str, ...] = ()
    added_frames: tuple[str, ...] = ()
    source_path: str = "<urdf>"
    _frame_idx: dict[str, int] = field(init=False, repr=False)
    _joint_idx: dict[str, int] = field(init=False, repr=False)
    _plan: _FkPlan = field(init=False, repr=False)

    def __post_init__(self) -> None:
        F = len(self.frame_names)
        n = len(self.actuated_joints)
        arrays: dict[str, tuple[Any, tuple[int, ...]]] = {
            "parent": (np.intp, (F,)),
            "joint_type": (np.int8, (F,)),
            "origin": (np.float64, (F, 4, 4)),
            "axis": (np.float64, (F, 3)),
            "q_index": (np.intp, (F,)),
            "mimic_multiplier": (np.float64, (F,)),
            "mimic_offset": (np.float64, (F,)),
            "lower": (np.float64, (n,)),
            "upper": (np.float64, (n,)),
            "continuous": (np.bool_, (n,)),
        }
        for name, (dtype, shape) in arrays.items():
            arr = np.array(getattr(self, name), dtype=dtype, copy=True)
            if arr.shape != shape:
                raise ValueError(f"KinematicModel.{name} must have shape {shape}, not {arr.shape}")
            arr.flags.writeable = False
            object.__setattr__(self, name, arr)
        if F == 0 or self.parent[0] != -1 or np.any(self.parent[1:] >= np.arange(1, F)):
            raise ValueError("KinematicModel frames must be in topological order, root first")
        if len(self.joint_of_frame) != F:
            raise ValueError("KinematicModel.joint_of_frame must have one entry per frame")
        if np.any((self.q_index < -1) | (self.q_index >= n)):
            raise ValueError("KinematicModel.q_index out of range")
        object.__setattr__(self, "joints", FrozenMap(self.joints))
        object.__setattr__(self, "_frame_idx", {f: i for i, f in enumerate(self.frame_names)})
        object.__setattr__(self, "_joint_idx", {j: i for i, j in enumerate(self.actuated_joints)})
        object.__setattr__(self, "_plan", _make_plan(self))

    # --- sizes and names -------------------------------------------------------------------
    @property
    def n_frames(self) -> int:
        return len(self.frame_names)

    @property
    def n_actuated(self) -> int:
        return len(self.actuated_joints)

    @property
    def base_frame(self) -> str:
        """The root frame: poses are expressed in it."""
        return self.frame_names[0]

    @property
    def mimic_joints(self) -> tuple[str, ...]:
        """Kept mimic followers, in topological order."""
        return tuple(n for n, j in self.joints.items() if j.is_movable and j.is_mimic)

    def has_frame(self, name: str) -> bool:
        return name in self._frame_idx

    def joints_on_path(self, frame_a: str, frame_b: str) -> tuple[str, ...]:
        """The actuated joints whose values change the pose of ``frame_b`` relative to
        ``frame_a`` (the joints between each frame and their common ancestor; a mimic joint
        counts as its master)."""
        a, b = self.frame_index(frame_a), self.frame_index(frame_b)
        up_a = self._chain_up(a)
        up_b = self._chain_up(b)
        common = set(up_a) & set(up_b)
        moving = [f for f in (*up_a, *up_b) if f not in common]
        found = {int(self.q_index[f]) for f in moving if int(self.q_index[f]) >= 0}
        return tuple(self.actuated_joints[i] for i in sorted(found))

    def _chain_up(self, frame: int) -> list[int]:
        """``frame`` and its ancestors up to the base (each visited once)."""
        out: list[int] = []
        while frame >= 0 and frame not in out:
            out.append(frame)
            frame = int(self.parent[frame])
        return out

    def frame_index(self, name: str) -> int:
        """Index of frame ``name``; :class:`UrdfError` with a suggestion when unknown."""
        try:
            return self._frame_idx[name]
        except KeyError:
            pass
        if name in self.pruned_frames:
            raise UrdfError(
                f"frame '{name}' was removed by set_base_frame '{self.base_frame}' (only frames "
                f"below the base frame are kept)",
                path=self.source_path,
            )
        raise UrdfError(
            f"unknown frame '{name}'" + did_you_mean(name, self.frame_names),
            path=self.source_path,
        )

    def actuated_index(self, name: str) -> int:
        """Index of an actuated joint in ``q``; :class:`UrdfError` says why a joint is not."""
        try:
            return self._joint_idx[name]
        except KeyError:
            pass
        j = self.joints.get(name)
        why: str
        if j is not None and j.is_mimic and j.is_movable:
            why = f"is a mimic joint (it follows '{j.mimic_joint}'), not a coordinate"
        elif j is not None:
            why = f"is a {j.type} joint, which has no coordinate"
        elif name in self.pruned_joints:
            why = f"was removed by set_base_frame '{self.base_frame}'"
        else:
            why = "is not a joint of the robot" + did_you_mean(name, self.actuated_joints)
        raise UrdfError(f"joint '{name}' {why}", path=self.source_path)

    def frame_indices(self, frames: FrameSelection) -> IntArray:
        """Indices for ``frames`` (names or indices; None = all) as an int array [F']."""
        if frames is None:
            return np.arange(self.n_frames, dtype=np.intp)
        if isinstance(frames, str):
            frames = [frames]
        out = np.empty(len(frames), dtype=np.intp)
        for k, f in enumerate(frames):
            if isinstance(f, str):
                out[k] = self.frame_index(f)
            else:
                i = int(f)
                if not 0 <= i < self.n_frames:
                    raise ValueError(f"frame index {i} out of range [0, {self.n_frames})")
                out[k] = i
        return out

    def ancestors(self, frame: int | str) -> list[int]:
        """Indices from ``frame`` up to the root (both included)."""
        i = self.frame_index(frame) if isinstance(frame, str) else int(frame)
        chain = []
        while i >= 0:
            chain.append(i)
            i = int(self.parent[i])
        return chain


# ------------------------------------------------------------------------------------------
# Building
# ------------------------------------------------------------------------------------------
def build_kinematic_model(
    urdf: yourdfpy.URDF,
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
    upath = path or urdf_path(urdf)
    diags: list[Diagnostic] = []
    links = links_of(urdf)
    joints = joints_of(urdf)
    return _build(upath, links, joints, xrdf, diags), diags


def _build(
    upath: str,
    links: list[str],
    urdf_joints: dict[str, JointInfo],
    xrdf: Xrdf | None,
    diags: list[Diagnostic],
) -> KinematicModel:
    fname = upath.replace("\\", "/").rsplit("/", 1)[-1]
    link_set = set(links)

    def uerr(msg: str, line: int | None = None) -> UrdfError:
        return UrdfError(msg, path=upath, line=line)

    def warn(rule: str, msg: str, line: int | None = None) -> None:
        diags.append(Diagnostic(upath, line, None, rule, Severity.WARNING, msg))

    # --- the URDF must be a tree-shaped graph over its links ----------------------------------
    parent_joint: dict[str, str] = {}
    for j in urdf_joints.values():
        for role, link in (("parent", j.parent), ("child", j.child)):
            if link not in link_set:
                raise uerr(
                    f"joint '{j.name}' refers to unknown {role} link '{link}'"
                    + did_you_mean(link, links),
                    j.line,
                )
        if j.child in parent_joint:
            raise uerr(
                f"link '{j.child}' is the child of two joints, '{parent_joint[j.child]}' and "
                f"'{j.name}'; a URDF must be a tree",
                j.line,
            )
        parent_joint[j.child] = j.name

    # --- modifiers, in list order ----------------------------------------------------------
    frames: dict[str, None] = dict.fromkeys(links)
    joints: dict[str, JointInfo] = dict(urdf_joints)
    all_frames: set[str] = set(links)
    all_joints: set[str] = set(urdf_joints)
    added: list[str] = []
    pruned_frames: list[str] = []
    pruned_joints: list[str] = []
    frame_removed_by: dict[str, str] = {}  # pruned frame -> the set_base_frame that did it
    joint_removed_by: dict[str, str] = {}

    def xerr(msg: str, key_path: str) -> UrdfError:
        if xrdf is not None and xrdf.source.path:
            line, col = xrdf.source.position(key_path)
            return UrdfError(msg, path=xrdf.source.path, line=line, col=col)
        return UrdfError(msg, path=upath)

    def missing_frame(name: str, what: str) -> str:
        if name in frame_removed_by:
            base = frame_removed_by[name]
            return f"{what} '{name}' was removed by set_base_frame '{base}'"
        return f"{what} '{name}' is not a frame of {fname}" + did_you_mean(name, frames)

    for i, mod in enumerate(xrdf.modifiers if xrdf is not None else ()):
        if isinstance(mod, AddFrame):
            kp = f"modifiers[{i}].add_frame"
            if mod.joint_type.lower() != "fixed":
                raise xerr(
                    f"add_frame '{mod.frame_name}': joint_type must be FIXED, not "
                    f"'{mod.joint_type}'",
                    f"{kp}.joint_type",
                )
            if mod.frame_name in all_frames:
                where = "an earlier add_frame" if mod.frame_name in added else f"a link of {fname}"
                raise xerr(
                    f"add_frame: frame '{mod.frame_name}' already exists ({where}); frame "
                    "names must be unique",
                    f"{kp}.frame_name",
                )
            if mod.joint_name in all_joints:
                where = (
                    f"a joint of {fname}"
                    if mod.joint_name in urdf_joints
                    else "used by an earlier add_frame"
                )
                raise xerr(
                    f"add_frame '{mod.frame_name}': joint name '{mod.joint_name}' already "
                    f"exists ({where}); joint names must be unique",
                    f"{kp}.joint_name",
                )
            if mod.parent_frame_name not in frames:
                raise xerr(
                    f"add_frame '{mod.frame_name}': "
                    + missing_frame(mod.parent_frame_name, "parent frame"),
                    f"{kp}.parent_frame_name",
                )
            joints[mod.joint_name] = JointInfo(
                name=mod.joint_name,
                type="fixed",
                parent=mod.parent_frame_name,
                child=mod.frame_name,
                origin=_pose_matrix(mod.position, mod.orientation.as_wxyz()),
            )
            frames[mod.frame_name] = None
            all_frames.add(mod.frame_name)
            all_joints.add(mod.joint_name)
            added.append(mod.frame_name)
        elif isinstance(mod, SetBaseFrame):
            kp = f"modifiers[{i}].set_base_frame"
            if mod.frame not in frames:
                raise xerr("set_base_frame: " + missing_frame(mod.frame, "frame"), kp)
            keep = _subtree(mod.frame, joints)
            for f in list(frames):
                if f not in keep:
                    del frames[f]
                    pruned_frames.append(f)
                    frame_removed_by[f] = mod.frame
            for jn, j in list(joints.items()):
                if j.parent not in keep or j.child not in keep:
                    del joints[jn]
                    pruned_joints.append(jn)
                    joint_removed_by[jn] = mod.frame
        elif isinstance(mod, RemoveMimicAttributes):
            kp = f"modifiers[{i}].remove_mimic_attributes.joint_name"
            jn = mod.joint_name
            if jn not in joints:
                if jn in joint_removed_by:
                    raise xerr(
                        f"remove_mimic_attributes: joint '{jn}' was removed by set_base_frame "
                        f"'{joint_removed_by[jn]}'",
                        kp,
                    )
                raise xerr(
                    f"remove_mimic_attributes: joint '{jn}' is not a joint of {fname}"
                    + did_you_mean(jn, joints),
                    kp,
                )
            j = joints[jn]
            if not j.is_mimic:
                mimics = [n for n, x in joints.items() if x.is_mimic]
                hint = did_you_mean(jn, mimics) or (
                    f" (mimic joints: {', '.join(mimics)})" if mimics else " (it has none)"
                )
                raise xerr(
                    f"remove_mimic_attributes: joint '{jn}' has no <mimic> in {fname}{hint}",
                    kp,
                )
            lo, hi = mod.position_limits if mod.position_limits is not None else (j.lower, j.upper)
            joints[jn] = j.replace(
                mimic_joint=None,
                mimic_multiplier=1.0,
                mimic_offset=0.0,
                lower=lo,
                upper=hi,
                velocity=mod.velocity_limits if mod.velocity_limits is not None else j.velocity,
            )

    # --- topological order -----------------------------------------------------------------
    children: dict[str, list[JointInfo]] = {}
    has_parent: set[str] = set()
    for j in joints.values():
        children.setdefault(j.parent, []).append(j)
        has_parent.add(j.child)
    roots = [f for f in frames if f not in has_parent]
    if not roots:
        raise uerr("the joints form a cycle: every link has a parent joint")
    if len(roots) > 1:
        shown = ", ".join(f"'{r}'" for r in roots[:5]) + (", ..." if len(roots) > 5 else "")
        raise uerr(
            f"{len(roots)} links have no parent joint ({shown}); a URDF must be a single tree "
            "(or choose a base with set_base_frame)"
        )
    order: list[str] = []
    via: dict[str, JointInfo] = {}
    stack = [roots[0]]
    while stack:
        f = stack.pop()
        order.append(f)
        for j in reversed(children.get(f, [])):
            via[j.child] = j
            stack.append(j.child)
    if len(order) != len(frames):
        lost = [f for f in frames if f not in set(order)]
        raise uerr(
            f"links {', '.join(repr(x) for x in lost[:5])} are not connected to root "
            f"'{roots[0]}': the joints form a cycle"
        )
    index = {f: i for i, f in enumerate(order)}

    # --- actuated joints, mimics, limits ---------------------------------------------------
    F = len(order)
    actuated: list[str] = []
    for f in order[1:]:
        j = via[f]
        if j.is_movable and not j.is_mimic:
            actuated.append(j.name)
    q_of = {n: k for k, n in enumerate(actuated)}
    mimic_memo: dict[str, MimicLink] = {}

    parent = np.full(F, -1, dtype=np.intp)
    jtype = np.zeros(F, dtype=np.int8)
    origin = np.tile(np.eye(4), (F, 1, 1))
    axis = np.zeros((F, 3))
    q_index = np.full(F, -1, dtype=np.intp)
    mult = np.ones(F)
    off = np.zeros(F)
    for f in order[1:]:
        i = index[f]
        j = via[f]
        parent[i] = index[j.parent]
        jtype[i] = JointType.from_urdf(j.type)
        origin[i] = j.origin
        if j.type in ("floating", "planar"):
            warn(
                "joint-held-fixed",
                f"{j.type} joint '{j.name}' is held fixed at its origin (only revolute, "
                "continuous and prismatic joints move)",
                j.line,
            )
            continue
        if not j.is_movable:
            continue
        a = np.asarray(j.axis, dtype=np.float64)
        norm = float(np.linalg.norm(a))
        if not norm > 1e-12 or not math.isfinite(norm):
            raise uerr(f"joint '{j.name}' has a zero or invalid axis {j.axis}", j.line)
        axis[i] = a / norm
        if not j.is_mimic:
            q_index[i] = q_of[j.name]
            continue
        master, m, o, held_reason = _resolve_mimic(
            j, joints, urdf_joints, joint_removed_by, uerr, mimic_memo
        )
        mult[i], off[i] = m, o
        if master is None:
            mult[i] = 0.0
            warn(
                "joint-held-fixed",
                f"mimic joint '{j.name}' is held at {o:g}: {held_reason}",
                j.line,
            )
        else:
            q_index[i] = q_of[master]

    lower = np.empty(len(actuated))
    upper = np.empty(len(actuated))
    cont = np.zeros(len(actuated), dtype=bool)
    for k, name in enumerate(actuated):
        j = joints[name]
        if j.type == "continuous":
            lower[k], upper[k], cont[k] = -math.pi, math.pi, True
            continue
        if j.lower is None and j.upper is None:
            warn(
                "joint-limits-missing",
                f"{j.type} joint '{name}' has no position limits; URDF defaults [0, 0] used",
                j.line,
            )
        lower[k] = 0.0 if j.lower is None else j.lower
        upper[k] = 0.0 if j.upper is None else j.upper

    return KinematicModel(
        frame_names=tuple(order),
        parent=parent,
        joint_of_frame=(None, *(via[f].name for f in order[1:])),
        joint_type=jtype,
        origin=origin,
        axis=axis,
        q_index=q_index,
        mimic_multiplier=mult,
        mimic_offset=off,
        actuated_joints=tuple(actuated),
        lower=lower,
        upper=upper,
        continuous=cont,
        joints=FrozenMap((via[f].name, via[f]) for f in order[1:]),
        pruned_joints=tuple(pruned_joints),
        pruned_frames=tuple(pruned_frames),
        added_frames=tuple(f for f in added if f in index),
        source_path=upath,
    )


def _subtree(base: str, joints: Mapping[str, JointInfo]) -> set[str]:
    children: dict[str, list[str]] = {}
    for j in joints.values():
        children.setdefault(j.parent, []).append(j.child)
    keep = {base}
    stack = [base]
    while stack:
        for c in children.get(stack.pop(), []):
            if c not in keep:
                keep.add(c)
                stack.append(c)
    return keep


MimicLink = tuple[str | None, float, float, str]


def _resolve_mimic(
    j: JointInfo,
    joints: Mapping[str, JointInfo],
    urdf_joints: Mapping[str, JointInfo],
    removed_by: Mapping[str, str],
    uerr: Any,
    memo: dict[str, MimicLink] | None = None,
) -> MimicLink:
    """Follow a mimic chain: ``(actuated master or None, multiplier, offset, why held)``.

    Every joint of the chain is resolved once and kept in ``memo`` (shared by the calls of one
    model build), so long chains cost linear time; a loop is a :class:`UrdfError`.
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


def _pose_matrix(position: Sequence[float], wxyz: tuple[float, float, float, float]) -> FloatArray:
    w, x, y, z = wxyz
    T = np.eye(4)
    T[:3, :3] = [
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ]
    T[:3, 3] = position
    return T


def _joint_transform(jt: int, axis: FloatArray, value: float) -> FloatArray:
    T = np.eye(4)
    if jt in (JointType.REVOLUTE, JointType.CONTINUOUS):
        K = _skew(axis)
        T[:3, :3] = np.eye(3) + math.sin(value) * K + (1 - math.cos(value)) * (K @ K)
    elif jt == JointType.PRISMATIC:
        T[:3, 3] = value * axis
    return T


def _skew(a: FloatArray) -> FloatArray:
    return np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])


def _make_plan(model: KinematicModel) -> _FkPlan:
    kinds = [_KIND_FIXED]
    consts: list[FloatArray] = [np.zeros((3, 4))]
    rows = [-1]
    rot_rows: list[int] = []
    row_q: list[int] = []
    row_mult: list[float] = []
    row_off: list[float] = []
    for i in range(1, model.n_frames):
        jt = int(model.joint_type[i])
        T = np.array(model.origin[i])
        a = model.axis[i]
        movable = jt in (JointType.REVOLUTE, JointType.CONTINUOUS, JointType.PRISMATIC)
        if movable and model.q_index[i] < 0:
            # a mimic of something held fixed: bake its constant value into the origin
            T = T @ _joint_transform(jt, a, float(model.mimic_offset[i]))
            movable = False
        A, t = T[:3, :3], T[:3, 3:4]
        if not movable:
            kinds.append(_KIND_FIXED)
            consts.append(np.ascontiguousarray(np.hstack([A, t])))
            rows.append(-1)
            continue
        if jt != JointType.PRISMATIC:
            rows.append(len(rot_rows))
            rot_rows.append(len(row_q))
        else:
            rows.append(len(row_q))
        row_q.append(int(model.q_index[i]))
        row_mult.append(float(model.mimic_multiplier[i]))
        row_off.append(float(model.mimic_offset[i]))
        if jt == JointType.PRISMATIC:
            kinds.append(_KIND_PRISM)
            consts.append(np.ascontiguousarray(np.hstack([A, t, (A @ a)[:, None]])))
        else:
            kinds.append(_KIND_ROT)
            K = _skew(a)
            consts.append(np.ascontiguousarray(np.hstack([A, A @ K, A @ np.outer(a, a) - A, t])))
    consts_t = tuple(np.ascontiguousarray(c.T) for c in consts)
    consts_root = tuple(np.ascontiguousarray(c[:, :, None]) for c in consts)
    for c in (*consts_t, *consts_root):
        c.flags.writeable = False
    return _FkPlan(
        parents=tuple(int(p) for p in model.parent),
        kinds=tuple(kinds),
        consts_t=consts_t,
        consts_root=consts_root,
        rows=tuple(rows),
        row_q=np.array(row_q, dtype=np.intp),
        rot_rows=np.array(rot_rows, dtype=np.intp),
        row_mult=np.array(row_mult, dtype=np.float64),
        row_off=np.array(row_off, dtype=np.float64),
    )


# ------------------------------------------------------------------------------------------
# Forward kinematics
# ------------------------------------------------------------------------------------------
def _as_batch(model: KinematicModel, q: npt.ArrayLike) -> tuple[FloatArray, bool]:
    arr = np.asarray(q, dtype=np.float64)
    n = model.n_actuated
    if arr.ndim == 1 and arr.shape[0] == n:
        return arr[None, :], True
    if arr.ndim == 2 and arr.shape[1] == n:
        return arr, False
    raise ValueError(
        f"q must have shape [{n}] or [B, {n}] (one value per actuated joint: "
        f"{', '.join(model.actuated_joints) or 'none'}), got {list(arr.shape)}"
    )


def _needed(model: KinematicModel, sel: IntArray) -> list[int]:
    mark = np.zeros(model.n_frames, dtype=bool)
    parent = model._plan.parents
    for i in sel.tolist():
        while i >= 0 and not mark[i]:
            mark[i] = True
            i = parent[i]
    return [int(i) for i in np.flatnonzero(mark)]


_WORK = threading.local()
_WORK_MAX_BATCH = 1 << 16  # larger batches get fresh scratch buffers each call


def _scratch(B: int) -> dict[int, FloatArray]:
    """Per-thread scratch buffers [3, c, B] (c = 3, 4, 5, 10), reused across calls."""
    cached: tuple[int, dict[int, FloatArray]] | None = getattr(_WORK, "buffers", None)
    if cached is not None and cached[0] == B:
        return cached[1]
    bufs = {c: np.empty((3, c, B)) for c in (3, 4, 5, 10)}
    if B <= _WORK_MAX_BATCH:
        _WORK.buffers = (B, bufs)
    return bufs


def _fk_batch_last(
    model: KinematicModel,
    q2: FloatArray,
    needed: Iterable[int],
    R: FloatArray,
    t: FloatArray,
) -> None:
    """Fill rotations ``R`` [F, 3, 3, B] and translations ``t`` [F, 3, B] of ``needed``.

    Batch-last keeps every elementwise operation on contiguous rows of length B, and the
    parent rotation times the frame constants is one stacked matmul ``(c, 3) @ (3, 3, B)``.
    """
    plan = model._plan
    B = q2.shape[0]
    R[0] = np.eye(3)[:, :, None]
    t[0] = 0.0
    vals = sin = omc = np.empty((0, B))
    if len(plan.row_q):
        vals = q2.T[plan.row_q]  # [rows, B], a copy
        vals *= plan.row_mult[:, None]
        vals += plan.row_off[:, None]
        angles = vals[plan.rot_rows]
        sin = np.sin(angles)
        omc = np.cos(angles)
        np.subtract(1.0, omc, out=omc)
    work = _scratch(B)
    tmp = work[3]
    for f in needed:
        if f == 0:
            continue
        p = plan.parents[f]
        M = plan.consts_t[f]
        # X = parent rotation times the constants: (c, 3) @ (3, 3, B) -> [3, c, B]; when the
        # parent is the root (identity) it is the constants themselves, [3, c, 1]
        X = plan.consts_root[f] if p == 0 else np.matmul(M, R[p], out=work[M.shape[0]])
        kind = plan.kinds[f]
        Rf, tf = R[f], t[f]
        if kind == _KIND_ROT:
            r = plan.rows[f]
            np.multiply(X[:, 3:6], sin[r], out=Rf)
            Rf += X[:, 0:3]
            np.multiply(X[:, 6:9], omc[r], out=tmp)
            Rf += tmp
            tcol = 9
        else:
            Rf[...] = X[:, 0:3]
            tcol = 3
        if p == 0:
            tf[...] = X[:, tcol]
        else:
            np.add(t[p], X[:, tcol], out=tf)
        if kind == _KIND_PRISM:
            tf += vals[plan.rows[f]] * X[:, 4]


def fk_batch_last(
    model: KinematicModel,
    q: npt.ArrayLike,
    frames: FrameSelection = None,
    *,
    out: tuple[FloatArray, FloatArray] | None = None,
) -> tuple[FloatArray, FloatArray]:
    """Forward kinematics in the fast batch-last layout.

    ``q``: [B, n] (or [n], treated as B = 1). Returns rotations [F', 3, 3, B] and
    translations [F', 3, B] (``R[f, :, :, b]`` is the 3x3 rotation of frame ``f`` for
    configuration ``b``). Sphere centres of frame ``f`` are then
    ``einsum("ikb,k->ib", R[f], c) + t[f]``, every operation on contiguous rows.

    ``out``: optional ``(R, t)`` arrays of those shapes to write into, so that a loop over
    chunks of a large sample does not allocate (and page-fault) new result arrays each time.
    """
    q2, _ = _as_batch(model, q)
    sel = model.frame_indices(frames)
    B = q2.shape[0]
    shape_r, shape_t = (len(sel), 3, 3, B), (len(sel), 3, B)
    if out is not None and (out[0].shape != shape_r or out[1].shape != shape_t):
        raise ValueError(
            f"out must be arrays of shapes {list(shape_r)} and {list(shape_t)}, got "
            f"{list(out[0].shape)} and {list(out[1].shape)}"
        )
    if frames is None:
        R, t = out if out is not None else (np.empty(shape_r), np.empty(shape_t))
        _fk_batch_last(model, q2, range(model.n_frames), R, t)
        return R, t
    F = model.n_frames
    R_all, t_all = np.empty((F, 3, 3, B)), np.empty((F, 3, B))
    _fk_batch_last(model, q2, _needed(model, sel), R_all, t_all)
    if out is None:
        return R_all[sel], t_all[sel]
    np.take(R_all, sel, axis=0, out=out[0])
    np.take(t_all, sel, axis=0, out=out[1])
    return out


def fk_rt(
    model: KinematicModel, q: npt.ArrayLike, frames: FrameSelection = None
) -> tuple[FloatArray, FloatArray]:
    """Batched forward kinematics as rotation and translation.

    ``q``: [B, n] (or [n]) actuated joint values. ``frames``: names or indices of the frames
    wanted (default all); only these and their ancestors are computed.

    Returns ``(R, t)``: base-frame rotations [B, F', 3, 3] and translations [B, F', 3] (or
    [F', 3, 3] and [F', 3] for a single configuration). They are strided views of the
    batch-last result of :func:`fk_batch_last` (no copy); use ``np.ascontiguousarray`` if a
    caller needs contiguous memory.
    """
    q2, single = _as_batch(model, q)
    R, t = fk_batch_last(model, q2, frames)
    Rb, tb = R.transpose(3, 0, 1, 2), t.transpose(2, 0, 1)
    return (Rb[0], tb[0]) if single else (Rb, tb)


def fk(model: KinematicModel, q: npt.ArrayLike, frames: FrameSelection = None) -> FloatArray:
    """Batched forward kinematics: homogeneous transforms [B, F', 4, 4] of the frames.

    ``q``: [B, n] (or [n], giving [F', 4, 4]) actuated joint values in
    :attr:`KinematicModel.actuated_joints` order. ``frames``: names or indices (default all
    frames, in model order); only these and their ancestors are computed. Each transform maps
    frame coordinates to base-frame coordinates. The result is a strided view of a batch-last
    buffer (no transposing copy).

    Raises ``ValueError`` for a wrongly shaped ``q`` or an out-of-range index, and
    :class:`UrdfError` for an unknown frame name.
    """
    q2, single = _as_batch(model, q)
    sel = model.frame_indices(frames)
    B = q2.shape[0]
    out = np.empty((len(sel), 4, 4, B))
    if frames is None:  # write straight into the output
        _fk_batch_last(model, q2, range(model.n_frames), out[:, :3, :3], out[:, :3, 3])
    else:
        fk_batch_last(model, q2, sel, out=(out[:, :3, :3], out[:, :3, 3]))
    out[:, 3, :3] = 0.0
    out[:, 3, 3] = 1.0
    view = out.transpose(3, 0, 1, 2)
    return view[0] if single else view


# ------------------------------------------------------------------------------------------
# Configurations
# ------------------------------------------------------------------------------------------
def default_configuration(
    model: KinematicModel, defaults: Mapping[str, float] | None = None
) -> FloatArray:
    """Default value [n] of every actuated joint.

    ``defaults`` (XRDF ``default_joint_positions``) wins; other joints get zero clamped to
    their position limits. Entries for joints that are not actuated (mimic, fixed, unknown)
    are ignored here; the linter reports them.
    """
    q = np.clip(np.zeros(model.n_actuated), model.lower, model.upper)
    for name, value in (defaults or {}).items():
        k = model._joint_idx.get(name)
        if k is not None:
            q[k] = float(value)
    return q


def moveit_default_configuration(model: KinematicModel) -> FloatArray:
    """The default state as MoveIt's Setup Assistant computes it: each joint at 0 when 0 is
    within its limits, else the middle of its limits."""
    zero_ok = (model.lower <= 0.0) & (model.upper >= 0.0)
    mid = np.where(
        np.isfinite(model.lower) & np.isfinite(model.upper), (model.lower + model.upper) / 2, 0.0
    )
    return np.where(zero_ok, 0.0, mid)


def full_configuration(
    model: KinematicModel,
    cspace_joint_names: Sequence[str],
    q_cspace: npt.ArrayLike,
    defaults: Mapping[str, float] | None = None,
) -> FloatArray:
    """Expand c-space values [B, n_c] (or [n_c]) into full configurations [B, n] (or [n]).

    Joints not in ``cspace_joint_names`` (auxiliary coordinates) are held at their default
    (see :func:`default_configuration`). Raises :class:`UrdfError` for a c-space name that is
    not an actuated joint (saying whether it is a mimic, fixed or pruned joint) and
    ``ValueError`` for a repeated name or a wrongly shaped ``q_cspace``.
    """
    names = list(cspace_joint_names)
    if len(set(names)) != len(names):
        dup = sorted({n for n in names if names.count(n) > 1})
        raise ValueError(f"c-space joint names repeat: {', '.join(dup)}")
    idx = np.array([model.actuated_index(n) for n in names], dtype=np.intp)
    qc = np.asarray(q_cspace, dtype=np.float64)
    single = qc.ndim == 1
    if qc.ndim not in (1, 2) or qc.shape[-1] != len(names):
        raise ValueError(
            f"q_cspace must have shape [{len(names)}] or [B, {len(names)}], got {list(qc.shape)}"
        )
    qc2 = qc[None, :] if single else qc
    out = np.repeat(default_configuration(model, defaults)[None, :], qc2.shape[0], axis=0)
    out[:, idx] = qc2
    return out[0] if single else out
