"""One cuRobo ``kinematics`` mapping being read: where it is, what it says, where it goes."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ...util.errors import SourceError
from . import Draft, Reporter, RobotTree

__all__ = ["KinSection"]


@dataclass
class KinSection:
    """One ``kinematics`` mapping being read: where it is, what it says, where it goes."""

    data: Mapping[str, Any]
    tree: RobotTree
    d: Draft
    rep: Reporter
    prefix: str
    config_path: Path
    frames: list[str]
    #: Joints of extra links that move in cuRobo (``joint_type`` other than FIXED) → the extra
    #: link; written fixed, so the c-space and the locks leave them out (said once, per link).
    moving_joints: dict[str, str] = field(default_factory=dict)

    def kp(self, *parts: object) -> str:
        return ".".join([self.prefix, *(str(p) for p in parts)])

    def fail(self, message: str, *parts: object) -> SourceError:
        """A :class:`SourceError` located at ``kinematics.<parts>``."""
        return SourceError(message, path=self.rep.path, line=self.rep.position(self.kp(*parts))[0])

    def mapping(self, key: str) -> Mapping[str, Any]:
        """``kinematics.<key>`` as a mapping (absent or null: empty)."""
        value = self.data.get(key) or {}
        if not isinstance(value, Mapping):
            raise self.fail(f"{key} must be a mapping", key)
        return value
