"""MoveIt ``joint_limits.yaml`` → acceleration and jerk limits (MoveIt 1 and 2 conventions).

``joint_limits: {joint: {has_acceleration_limits, max_acceleration, has_jerk_limits, max_jerk}}``.
A limit is taken as ``abs(max_*)`` when ``has_*`` is true, or when ``has_*`` is absent and the
value is present and > 0 (MoveIt 1 style). Integers are accepted; 0 or missing means absent.

The ``joint_limits`` mapping is the file's top level, or, in a ROS 2 parameter file
(``NODE: {ros__parameters: {robot_description_planning: {joint_limits: …}}}``), under a node's
``ros__parameters`` (its ``robot_description_planning``, else itself). A launch substitution
``$(var NAME)`` in a joint name (a ``tf_prefix``) takes ``--xacro-arg NAME``'s value, else the
empty string; both are reported.

An XRDF holds no velocity or position limits (its readers take them from the URDF), so a
``max_velocity`` or ``min_position``/``max_position`` tighter than the URDF's is recorded in
``Draft.uncarried_limits``; :mod:`~xrdf_tools.convert.core` reports those of c-space joints.
"""

from __future__ import annotations

import os
import re
from collections.abc import Iterable, Mapping

from ...diagnostics import Diagnostic, Severity
from ...robot.urdf_joints import JointInfo
from ...util.errors import SourceError, did_you_mean
from ...util.numbers import bound_problem
from ...util.text import name_list
from ...yaml.io import YamlDocument, YMap, YScalar, load_yaml, positions_of, to_python
from ...yaml.rules import YAML11_BOOLEANS
from . import Draft, Reporter, RobotTree

__all__ = ["read_joint_limits"]

#: A xacro expression in a joint name of a template's joint limits: ``${name}_joint_1``.
_XACRO_EXPRESSION = re.compile(r"\$\{[^}]*\}")
#: A ROS 2 launch substitution in a parameter file: ``$(var tf_prefix)``.
_LAUNCH_VAR = re.compile(r"\$\(var\s+([^)\s]+)\s*\)")

#: How much tighter than the URDF's a MoveIt limit must be to be reported: a velocity by this
#: share (Fetch's config rounds 1.571 to 1.57), a position by this many rad or m.
_VELOCITY_SLACK = 0.01
_POSITION_SLACK = 1e-3


def read_joint_limits(
    path: str | os.PathLike[str],
    tree: RobotTree,
    draft: Draft | None = None,
    substitutions: Mapping[str, str] | None = None,
) -> Draft:
    """Add the acceleration/jerk limits of a MoveIt joint_limits.yaml to ``draft``.

    ``substitutions`` (the robot's xacro arguments) give ``$(var NAME)`` in joint names."""
    d = draft or Draft()
    doc = load_yaml(path)
    rep = Reporter(doc.path, positions_of(doc))
    root, prefix = _limits_holder(doc, rep)
    limits = root.get("joint_limits")
    assert isinstance(limits, YMap)
    unset: dict[str, str] = {}
    unknown: dict[str, str] = {}  # joint name -> key path of its entry
    for jname, node in limits.items():
        kp = f"{prefix}joint_limits.{jname}"
        if not isinstance(node, YMap):
            continue
        jname = _substituted(str(jname), substitutions or {}, unset, kp)
        if jname not in tree.joints:
            unknown.setdefault(jname, kp)
            continue
        values = _switches_checked(node, jname, kp, rep)
        if tighter := _tighter_than_urdf(values, tree.joints[jname]):
            line, col = rep.position(kp)
            d.uncarried_limits[jname] = Diagnostic(
                rep.path, line, col, "convert-limit-not-carried", Severity.WARNING, tighter, kp
            )
        for kind in ("acceleration", "jerk"):
            _read_limit(kind, jname, values, kp, d, rep)
    for key, node in root.items():
        if key not in (
            "joint_limits",
            "default_velocity_scaling_factor",
            "default_acceleration_scaling_factor",
        ) and not isinstance(node, YScalar):
            rep.report("convert-dropped-key", f"'{key}' has no XRDF equivalent", f"{prefix}{key}")
    _report_unknown(rep, unknown, tree)
    for name, kp in unset.items():
        rep.report(
            "convert-launch-substitution",
            f"$(var {name}) in joint names taken as '' (no --xacro-arg {name}:=VALUE given)",
            kp,
            severity=Severity.INFO,
        )
    d.diagnostics.extend(rep.diagnostics)
    return d


def _switches_checked(node: YMap, jname: str, kp: str, rep: Reporter) -> dict[str, object]:
    """The values of ``node`` without the ``has_*_limits`` switches that are not booleans,
    each reported: a quoted ``"false"`` is a string, which MoveIt does not read as a switch.
    A plain ``yes``/``no``/``on``/``off`` is the boolean MoveIt's YAML 1.1 readers make of it."""
    kept: dict[str, object] = {}
    for key, item in node.items():
        switch = _yaml11_switch(item) if str(key).startswith("has_") else None
        value = to_python(item) if switch is None else switch
        if str(key).startswith("has_") and value is not None and not isinstance(value, bool):
            rep.report(
                "convert-dropped-key",
                f"'{jname}' {key} is {value!r}, not true or false: MoveIt does not read it as "
                "a switch; read as absent (write true or false, without quotes)",
                f"{kp}.{key}",
            )
            continue
        kept[str(key)] = value
    return kept


def _yaml11_switch(item: object) -> bool | None:
    """The boolean a plain ``yes``/``no``/``on``/``off`` is to MoveIt (None: not one)."""
    if isinstance(item, YScalar) and not item.quoted and isinstance(item.value, str):
        return YAML11_BOOLEANS.get(item.value)
    return None


def _read_limit(
    kind: str,
    jname: str,
    values: Mapping[str, object],
    kp: str,
    d: Draft,
    rep: Reporter,
) -> None:
    """``max_KIND`` of one joint into ``d.limits(kind)`` when the file gives it (see the
    module), or where it turns it off (``has_KIND_limits: false``) into ``d.limits_off``."""
    raw = values.get(f"max_{kind}")
    has = values.get(f"has_{kind}_limits")
    if has is False:
        d.limits_off[(kind, jname)] = (rep.path, rep.position(kp)[0])
        return
    if raw is None or isinstance(raw, bool) or not isinstance(raw, (int, float)):
        if has is True:
            rep.report(
                "convert-dropped-key",
                f"'{jname}' has_{kind}_limits is true but max_{kind} is missing",
                kp,
            )
        return
    if has is None and raw <= 0:
        return
    if raw == 0:
        return
    if (problem := bound_problem(raw)) is not None:
        rep.report(
            "convert-dropped-key",
            f"'{jname}' max_{kind} {problem}; dropped",
            f"{kp}.max_{kind}",
        )
        return
    if raw < 0:
        rep.report(
            "convert-negative-limit",
            f"'{jname}' max_{kind} is {raw}; using its absolute value",
            f"{kp}.max_{kind}",
            severity=Severity.INFO,
        )
    d.limits(kind)[jname] = abs(float(raw))


def _report_unknown(rep: Reporter, unknown: Mapping[str, str], tree: RobotTree) -> None:
    """One warning for the entries naming joints the URDF lacks, at the first (REEM-C's config
    limits 14 finger joints its URDF does not have: one line, not fourteen)."""
    if not unknown:
        return
    names = list(unknown)
    if len(names) == 1:
        what = (
            f"'{names[0]}', which is not a joint of the URDF{did_you_mean(names[0], tree.joints)}"
        )
    else:
        what = f"{len(names)} joints the URDF does not have ({name_list(names, 8)})"
    templated = sorted({m for n in names for m in _XACRO_EXPRESSION.findall(n)})
    if templated:  # Clearpath's kinova_gen3_7dof/joint_limits.yaml: '${name}_joint_1'
        what += (
            f"; ignored: {name_list(templated, 3)} in a joint name is a template's expression "
            "that a generator or xacro fills in: give the file it writes"
        )
    else:
        what += "; ignored" + _prefixed_note(names, tree.joints)
    rep.report("convert-unknown-joint", f"joint_limits names {what}", unknown[names[0]])


def _prefixed_note(names: list[str], joints: Iterable[str]) -> str:
    """What to do when the URDF has every one of ``names`` behind the same prefixes: the
    file is for the robot without them (xArm's single-arm ``joint_limits.yaml`` given for its
    dual arm, whose joints are ``L_joint1`` … and ``R_joint1`` …)."""
    have = set(joints)
    first = names[0]
    prefixes = sorted(
        j[: -len(first)]
        for j in have
        if j.endswith(first)
        and len(j) > len(first)
        and all(j[: -len(first)] + n in have for n in names)
    )
    if not prefixes:
        return ""
    shown = name_list([f"'{p}'" for p in prefixes], 4)
    return (
        f" (the URDF has each of them prefixed with {shown}: a file for the robot without "
        "those prefixes; give one naming this URDF's joints)"
    )


def _number(values: Mapping[str, object], key: str) -> float | None:
    """``values[key]`` when it is a usable number (not a bool), else None."""
    raw = values.get(key)
    if isinstance(raw, bool) or not isinstance(raw, (int, float)) or bound_problem(raw):
        return None
    return float(raw)


def _tighter_than_urdf(values: Mapping[str, object], joint: JointInfo) -> str:
    """What of a joint's MoveIt velocity and position limits is tighter than its URDF's
    (``"max_velocity 0.75 (URDF 1.5)"``), '' when nothing is. A value rounded from the URDF's
    (a velocity less than 1 % below it, a position within 1e-3) is no tighter.

    MoveIt applies ``max_velocity`` when ``has_velocity_limits`` is true (or absent and the
    value > 0), ``min_position``/``max_position`` when ``has_position_limits`` is true. A URDF
    velocity of 0 or less is lint's ``curobo-zero-velocity``, not compared here."""
    found = []
    velocity = _number(values, "max_velocity")
    has = values.get("has_velocity_limits")
    if velocity is not None and (has is True or (has is None and velocity > 0)):
        urdf = joint.velocity
        if urdf is None or (urdf > 0 and abs(velocity) < urdf * (1 - _VELOCITY_SLACK)):
            found.append(f"max_velocity {abs(velocity):g} (URDF {_shown(urdf)})")
    if values.get("has_position_limits") is True:
        low, high = _number(values, "min_position"), _number(values, "max_position")
        if low is not None and (joint.lower is None or low > joint.lower + _POSITION_SLACK):
            found.append(f"min_position {low:g} (URDF {_shown(joint.lower)})")
        if high is not None and (joint.upper is None or high < joint.upper - _POSITION_SLACK):
            found.append(f"max_position {high:g} (URDF {_shown(joint.upper)})")
    return ", ".join(found)


def _shown(value: float | None) -> str:
    return "none" if value is None else f"{value:g}"


def _limits_holder(doc: YamlDocument, rep: Reporter) -> tuple[YMap, str]:
    """The mapping that holds ``joint_limits`` and its key path prefix: the top level, else a
    node's ``ros__parameters`` (its ``robot_description_planning``, else itself) in a ROS 2
    parameter file (reported)."""
    root = doc.root
    if isinstance(root, YMap) and isinstance(root.get("joint_limits"), YMap):
        return root, ""
    for node, value in root.items() if isinstance(root, YMap) else ():
        params = value.get("ros__parameters") if isinstance(value, YMap) else None
        if not isinstance(params, YMap):
            continue
        for sub in ("robot_description_planning", ""):
            holder = params.get(sub) if sub else params
            if isinstance(holder, YMap) and isinstance(holder.get("joint_limits"), YMap):
                prefix = f"{node}.ros__parameters.{sub + '.' if sub else ''}"
                rep.report(
                    "convert-ros-parameters",
                    f"a ROS 2 parameter file: joint limits read from {prefix}joint_limits",
                    f"{prefix}joint_limits",
                    severity=Severity.INFO,
                )
                return holder, prefix
    where = root.get("joint_limits") if isinstance(root, YMap) else None
    where = where if where is not None else root
    raise SourceError(
        "a MoveIt joint limits file needs a 'joint_limits' mapping, at the top level or "
        "under NODE.ros__parameters[.robot_description_planning] (a ROS 2 parameter file)",
        path=doc.path,
        line=where.line if where is not None else 1,
        col=where.col if where is not None else None,
    )


def _substituted(name: str, values: Mapping[str, str], unset: dict[str, str], kp: str) -> str:
    """``name`` with each ``$(var NAME)`` replaced by ``values[NAME]``, else '' (recorded in
    ``unset`` with the first key path that uses it)."""

    def value(m: re.Match[str]) -> str:
        if m.group(1) in values:
            return values[m.group(1)]
        unset.setdefault(m.group(1), kp)
        return ""

    return _LAUNCH_VAR.sub(value, name)
