"""MoveIt ``joint_limits.yaml`` → acceleration and jerk limits (MoveIt 1 and 2 conventions).

``joint_limits: {joint: {has_acceleration_limits, max_acceleration, has_jerk_limits, max_jerk}}``.
A limit is taken as ``abs(max_*)`` when ``has_*`` is true, or when ``has_*`` is absent and the
value is present and > 0 (MoveIt 1 style). Integers are accepted; 0 or missing means absent.
"""

from __future__ import annotations

import os

from ...diagnostics import Severity
from ...util.errors import SourceError
from ...yaml.io import YMap, YScalar, load_yaml, positions_of, to_python
from . import Draft, Reporter, RobotTree

__all__ = ["read_joint_limits"]


def read_joint_limits(
    path: str | os.PathLike[str], tree: RobotTree, draft: Draft | None = None
) -> Draft:
    """Add the acceleration/jerk limits of a MoveIt joint_limits.yaml to ``draft``."""
    d = draft or Draft()
    doc = load_yaml(path)
    rep = Reporter(doc.path, positions_of(doc))
    root = doc.root
    if not isinstance(root, YMap) or not isinstance(root.get("joint_limits"), YMap):
        where = root.get("joint_limits") if isinstance(root, YMap) else None
        where = where if where is not None else root
        raise SourceError(
            "a MoveIt joint limits file needs a top-level 'joint_limits' mapping",
            path=doc.path,
            line=where.line if where is not None else 1,
            col=where.col if where is not None else None,
        )
    limits = root.get("joint_limits")
    assert isinstance(limits, YMap)
    for jname, node in limits.items():
        kp = f"joint_limits.{jname}"
        if not isinstance(node, YMap):
            continue
        jname = str(jname)
        if jname not in tree.joints:
            rep.report(
                "convert-unknown-joint",
                f"joint_limits names '{jname}', which is not a joint of the URDF; ignored",
                kp,
            )
            continue
        values = to_python(node)
        for kind, target in (("acceleration", d.acceleration), ("jerk", d.jerk)):
            raw = values.get(f"max_{kind}")
            has = values.get(f"has_{kind}_limits")
            if raw is None or isinstance(raw, bool) or not isinstance(raw, (int, float)):
                if has is True:
                    rep.report(
                        "convert-dropped-key",
                        f"'{jname}' has_{kind}_limits is true but max_{kind} is missing",
                        kp,
                    )
                continue
            if has is False or (has is None and raw <= 0):
                continue
            if raw == 0:
                continue
            if raw < 0:
                rep.report(
                    "convert-negative-limit",
                    f"'{jname}' max_{kind} is {raw}; using its absolute value",
                    f"{kp}.max_{kind}",
                    severity=Severity.INFO,
                )
            target[jname] = abs(float(raw))
    for key, node in root.items():
        if key not in (
            "joint_limits",
            "default_velocity_scaling_factor",
            "default_acceleration_scaling_factor",
        ) and not isinstance(node, YScalar):
            rep.report("convert-dropped-key", f"'{key}' has no XRDF equivalent", str(key))
    d.diagnostics.extend(rep.diagnostics)
    return d
