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

Modules
-------
* :mod:`.model` -- :class:`KinematicModel` and its name lookups;
* :mod:`.build` -- building it from a URDF; :mod:`.modifiers` (``add_frame``,
  ``set_base_frame``, ``remove_mimic_attributes``) and :mod:`.mimic` (mimic chains) are its
  steps;
* :mod:`.plan` and :mod:`.batch_fk` -- the per-frame FK constants and batched FK;
* :mod:`.configurations` -- default, MoveIt default and c-space-expanded configurations.

Everything is importable from ``xrdf_tools.robot.kinematics``.
"""

from __future__ import annotations

from ...util.arrays import BoolArray as BoolArray
from ...util.arrays import FloatArray as FloatArray
from ...util.arrays import IntArray as IntArray
from .base import FrameSelection as FrameSelection
from .base import JointType
from .batch_fk import fk, fk_batch_last, fk_rt
from .build import build_kinematic_model
from .configurations import (
    default_configuration,
    full_configuration,
    moveit_default_configuration,
    unset_defaults,
)
from .mimic import MimicLink as MimicLink
from .mimic import resolve_mimic
from .model import KinematicModel

_resolve_mimic = resolve_mimic  # its name before the module was split (tests use it)

__all__ = [
    "JointType",
    "KinematicModel",
    "build_kinematic_model",
    "default_configuration",
    "fk",
    "fk_batch_last",
    "fk_rt",
    "full_configuration",
    "moveit_default_configuration",
    "unset_defaults",
]
