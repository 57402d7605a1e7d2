"""Array aliases and the joint-type code shared by the kinematics modules."""

from __future__ import annotations

from collections.abc import Sequence
from enum import IntEnum
from typing import Any

import numpy as np
import numpy.typing as npt

FrameSelection = Sequence[int | str] | npt.NDArray[np.integer[Any]] | None
"""Frames asked of FK: names or indices in model order; None means every frame."""


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


MOVING_TYPES = frozenset((JointType.REVOLUTE, JointType.CONTINUOUS, JointType.PRISMATIC))
"""The joint types FK moves (floating and planar joints are held at their origin)."""
