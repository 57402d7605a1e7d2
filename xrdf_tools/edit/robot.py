"""The robot side of ``xrdf edit``: poses, forward kinematics and live self-collisions.

:class:`EditRobot` holds what does not change while a document is edited (the loaded URDF,
its kinematic model with the XRDF's modifiers) and the document's c-space (which follows the
document: :meth:`EditRobot.follow`), and answers, for any version of the document, which frame
pairs touch at a pose -- with the project's collision engine
(:mod:`xrdf_tools.selfcollision.collision`: buffered radii, the ``ignore`` mask).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from ..diagnostics import Diagnostic
from ..robot.binding import cspace_indices
from ..robot.kinematics import build_kinematic_model, default_configuration, fk
from ..selfcollision.collision import (
    Contact,
    SphereSet,
    build_sphere_set,
    contacts,
    pair_hits,
    sphere_world_centers,
)
from ..util.arrays import FloatArray
from ..util.errors import XrdfToolsError
from ..xrdf.model import CSpace, Xrdf
from .robot_checks import check_edited

if TYPE_CHECKING:
    from ..robot.core import Robot
    from ..robot.kinematics import KinematicModel


__all__ = ["Collisions", "EditRobot"]


@dataclass(frozen=True)
class Collisions:
    """Self-collisions at one pose.

    ``contacts``: every frame pair whose buffered spheres touch, worst first, the ignored
    (masked) ones included with ``masked=True``. ``spheres`` / ``ignored_spheres``: per frame,
    the indices (in the frame's resolved sphere list) of the spheres in a checked / an ignored
    touching pair.
    """

    contacts: tuple[Contact, ...] = ()
    spheres: Mapping[str, frozenset[int]] = field(default_factory=dict)
    ignored_spheres: Mapping[str, frozenset[int]] = field(default_factory=dict)

    @property
    def checked(self) -> tuple[Contact, ...]:
        """The touching pairs the mask does not ignore: real self-collisions."""
        return tuple(c for c in self.contacts if not c.masked)

    @property
    def ignored(self) -> tuple[Contact, ...]:
        return tuple(c for c in self.contacts if c.masked)

    def pairs(self, *, masked: bool | None = None) -> set[frozenset[str]]:
        """The touching frame pairs (all, or only ignored / checked ones)."""
        return {
            frozenset((c.frame_a, c.frame_b))
            for c in self.contacts
            if masked is None or c.masked == masked
        }


class EditRobot:
    """A loaded robot for editing one XRDF (its modifiers must stay fixed; the c-space
    follows the document)."""

    def __init__(self, robot: Robot, xrdf: Xrdf) -> None:
        self.robot = robot
        kin, diags = build_kinematic_model(robot, xrdf)
        self.kin: KinematicModel = kin
        self.diagnostics: tuple[Diagnostic, ...] = tuple(diags)
        self._cache: tuple[Xrdf, SphereSet] | None = None
        self._use_cspace(xrdf)

    def _use_cspace(self, xrdf: Xrdf) -> None:
        names, idx = cspace_indices(self.kin, xrdf)
        self.cspace: tuple[str, ...] = names
        self.cspace_index = idx
        lo = np.array(self.kin.lower[idx], dtype=np.float64)
        hi = np.array(self.kin.upper[idx], dtype=np.float64)
        # continuous joints: one turn either way
        self.lower: FloatArray = np.where(np.isfinite(lo), lo, -math.pi)
        self.upper: FloatArray = np.where(np.isfinite(hi), hi, math.pi)

    def follow(self, xrdf: Xrdf) -> bool:
        """Take ``xrdf``'s c-space (after an edit, undo or redo); True when it changed."""
        names = xrdf.cspace.joint_names if xrdf.cspace is not None else ()
        if tuple(names) == self.cspace:
            return False
        self._use_cspace(xrdf)
        return True

    # --- the c-space -----------------------------------------------------------------------
    def cspace_joint_choices(self) -> tuple[str, ...]:
        """Every joint the c-space can hold, in URDF order: actuated (not fixed, not a mimic
        joint unless the document's modifiers freed it), with limits some position fits."""
        actuated = set(self.kin.actuated_joints)
        return tuple(
            name
            for name in self.robot.joints
            if name in actuated and not self.kin.cspace_reason(name)
        )

    def cspace_with(
        self, xrdf: Xrdf, joint: str, *, included: bool, acceleration: float, jerk: float
    ) -> CSpace:
        """``xrdf``'s c-space with ``joint`` taken in (at its place in URDF order, with these
        limits; a joint already in keeps its place and gets them) or left out."""
        cs = xrdf.cspace or CSpace((), (), ())
        rows = list(zip(cs.joint_names, cs.acceleration_limits, cs.jerk_limits, strict=True))
        names = [r[0] for r in rows]
        if not included:
            rows = [r for r in rows if r[0] != joint]
        elif joint in names:
            rows[names.index(joint)] = (joint, acceleration, jerk)
        else:
            rows.insert(self._place(names, joint), (joint, acceleration, jerk))
        return CSpace(
            tuple(r[0] for r in rows), tuple(r[1] for r in rows), tuple(r[2] for r in rows)
        )

    def _place(self, names: list[str], joint: str) -> int:
        """Where ``joint`` goes in the c-space ``names``: next to its nearest neighbour in URDF
        order among them -- after the one before it, or before the one after it when that is
        nearer. In a c-space in URDF order that is its URDF place; in one that is not (two
        arms, the second in the URDF listed first), the joint goes back into its own arm."""
        order = {n: k for k, n in enumerate(self.cspace_joint_choices())}
        rank = order.get(joint, len(order))
        ranked = [(order.get(n, len(order)), k) for k, n in enumerate(names)]
        before = max((r for r in ranked if r[0] < rank), default=None)
        after = min((r for r in ranked if r[0] > rank), default=None)
        if after is not None and (before is None or after[0] - rank < rank - before[0]):
            return after[1]
        return before[1] + 1 if before is not None else len(names)

    def urdf_ordered(self, xrdf: Xrdf) -> CSpace | None:
        """``xrdf``'s c-space in URDF order (each joint keeping its limits); None when it is
        in that order already. cuRobo fills default positions in URDF order: a c-space in
        another order gets them scrambled."""
        cs = xrdf.cspace
        if cs is None:
            return None
        order = {n: k for k, n in enumerate(self.cspace_joint_choices())}
        rows = list(zip(cs.joint_names, cs.acceleration_limits, cs.jerk_limits, strict=True))
        ranked = sorted(rows, key=lambda r: order.get(r[0], len(order)))
        if ranked == rows:
            return None
        return CSpace(
            tuple(r[0] for r in ranked), tuple(r[1] for r in ranked), tuple(r[2] for r in ranked)
        )

    def moves_curobo_frames(self, xrdf: Xrdf, joint: str) -> bool:
        """Whether ``joint`` moves a frame cuRobo builds its robot from: a tool frame, a frame
        with world-collision spheres or an added frame (a mimic joint counts as its master).
        A c-space joint that moves none is not in that robot, and cuRobo's loader raises
        (``xrdf lint --target curobo``: curobo-joint-outside-tree)."""
        kin = self.kin
        frames = {
            *(xrdf.tool_frames or ()),
            *xrdf.world_collision_spheres(),
            *(a.frame_name for a in xrdf.added_frames()),
        }
        root = kin.frame_names[0]
        return any(
            joint in kin.joints_on_path(root, f) for f in sorted(frames) if f in kin.frame_names
        )

    def check_edit(self, before: Xrdf, after: Xrdf) -> None:
        """:class:`~xrdf_tools.edit.checks.EditError` when the edit from ``before`` to ``after``
        brings in a frame or joint this robot does not have, or a default position outside
        its joint's limits (see :mod:`xrdf_tools.edit.robot_checks`)."""
        check_edited(self.kin, before, after)

    @property
    def frame_names(self) -> tuple[str, ...]:
        return self.kin.frame_names

    # --- poses -----------------------------------------------------------------------------
    def default_pose(self, xrdf: Xrdf) -> FloatArray:
        """Every actuated joint [n] at the document's default position."""
        return default_configuration(self.kin, xrdf.default_joint_positions)

    def random_pose(self, xrdf: Xrdf, seed: int) -> FloatArray:
        """The default pose with every c-space joint drawn uniformly within its limits."""
        q = self.default_pose(xrdf)
        rng = np.random.default_rng(seed)
        q[self.cspace_index] = self.lower + rng.random(len(self.cspace)) * (self.upper - self.lower)
        return q

    def pose_from(self, base: FloatArray, values: Mapping[str, float]) -> FloatArray:
        """``base`` with the named actuated joints set (e.g. a report's witness); raises
        :class:`XrdfToolsError` for a joint the robot does not move."""
        q = np.array(base, dtype=np.float64)
        for name, value in values.items():
            why = self.kin.not_actuated_reason(name)
            if why:
                raise XrdfToolsError(f"cannot pose joint '{name}': it {why}")
            q[self.kin.actuated_index(name)] = float(value)
        return q

    def cspace_values(self, q: FloatArray) -> dict[str, float]:
        """The c-space joints of ``q`` by name."""
        return {n: float(q[i]) for n, i in zip(self.cspace, self.cspace_index, strict=True)}

    def reach(self, q: FloatArray) -> float:
        """The largest distance of a frame from the base at pose ``q`` (metres)."""
        return float(np.linalg.norm(self.poses(q)[:, :3, 3], axis=1).max())

    def poses(self, q: FloatArray) -> FloatArray:
        """Frame-to-base transforms [F, 4, 4] of every frame at ``q``."""
        return np.asarray(fk(self.kin, np.asarray(q, dtype=np.float64)[None, :])[0])

    # --- collisions ------------------------------------------------------------------------
    def sphere_set(self, xrdf: Xrdf) -> SphereSet:
        """The self-collision spheres of ``xrdf`` (masked pairs included), cached for the
        last document asked for."""
        if self._cache is not None and self._cache[0] is xrdf:
            return self._cache[1]
        spheres, _ = build_sphere_set(self.kin, xrdf, include_masked=True)
        self._cache = (xrdf, spheres)
        return spheres

    def collisions(self, xrdf: Xrdf, q: FloatArray) -> Collisions:
        """The frame pairs of ``xrdf`` whose buffered spheres touch at ``q`` [n]."""
        spheres = self.sphere_set(xrdf)
        if spheres.n_pairs == 0:
            return Collisions()
        centers = sphere_world_centers(self.kin, spheres, np.asarray(q, dtype=np.float64))
        hit = np.flatnonzero(pair_hits(spheres, centers))
        checked: dict[str, set[int]] = {}
        ignored: dict[str, set[int]] = {}
        for p in hit.tolist():
            masked = bool(spheres.frame_pair_masked[spheres.pair_frame_pair[p]])
            into = ignored if masked else checked
            for s in (int(spheres.pair_i[p]), int(spheres.pair_j[p])):
                frame = spheres.frame_names[int(spheres.frame_of_sphere[s])]
                into.setdefault(frame, set()).add(int(spheres.sphere_index[s]))
        return Collisions(
            tuple(contacts(spheres, centers)) if hit.size else (),
            {f: frozenset(s) for f, s in checked.items()},
            {f: frozenset(s) for f, s in ignored.items()},
        )
