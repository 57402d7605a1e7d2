"""Lula / Isaac Sim robot description YAML → Draft (``cspace``, ``default_q``, limits,
``root_link``, fixed ``cspace_to_urdf_rules`` and ``collision_spheres``).

Called by :func:`xrdf_tools.convert.sources.curobo.read_curobo` when the layout is ``lula``.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from ...diagnostics import Severity
from ...util.errors import SourceError, did_you_mean
from ...xrdf.model import SetBaseFrame, Sphere
from . import Draft, Reporter, RobotTree, known_frame, not_a_joint
from .curobo_keys import changes_nothing, key_text
from .curobo_spheres import is_num, spheres_of

__all__ = ["LULA_HANDLED", "RULE_NO_MASK", "read_lula"]

#: A Lula description has spheres but no self-collision mask (Lula checks no self-collision).
RULE_NO_MASK = "convert-lula-no-mask"

#: The Lula keys read; others are reported as dropped.
LULA_HANDLED = {
    "cspace",
    "default_q",
    "acceleration_limits",
    "jerk_limits",
    "collision_spheres",
    "root_link",
    "cspace_to_urdf_rules",
    "api_version",
}


def read_lula(data: Mapping[str, Any], tree: RobotTree, d: Draft, rep: Reporter) -> None:
    """Map a Lula robot description onto ``d``; keys it does not know are reported dropped
    (an empty one, ``composite_task_spaces: []``, holds nothing to drop)."""
    for key in data:
        if key not in LULA_HANDLED and not changes_nothing(key, data[key]):  # `[]` says nothing
            rep.report(
                "convert-dropped-key", f"'{key_text(key)}' has no XRDF equivalent; dropped", key
            )
    frames = list(tree.links)
    root = data.get("root_link")
    root_ok = bool(root) and known_frame(str(root), frames, rep, "root_link", "root_link")
    if root_ok and str(root) != tree.root:
        d.modifiers.append(SetBaseFrame(str(root)))
    names = [str(n) for n in data.get("cspace") or []]
    cspace = _known_cspace(names, tree, rep)
    d.cspace = cspace
    _read_joint_vectors(data, names, cspace, d, rep)
    _read_fixed_rules(data.get("cspace_to_urdf_rules") or [], tree, d, rep)
    spheres = data.get("collision_spheres")
    if isinstance(spheres, list):
        d.spheres = _lula_spheres(spheres, frames, rep)
        if len(d.spheres) > 1:
            _report_no_mask(rep)


def _report_no_mask(rep: Reporter) -> None:
    """Lula checks no self-collision, so its description has no ignore list: as written,
    cuRobo would check every pair of sphere frames, adjacent links included."""
    rep.report(
        RULE_NO_MASK,
        "a Lula robot description has no self-collision mask (Lula checks no self-collision): "
        "the XRDF ignores no pair, so cuRobo checks adjacent links against each other and may "
        "find no valid configuration; compute one: xrdf report ROBOT.xrdf --urdf ROBOT.urdf "
        "--write-mask MASKED.xrdf",
        "collision_spheres",
    )


def _known_cspace(names: list[str], tree: RobotTree, rep: Reporter) -> list[str]:
    cspace = []
    for i, n in enumerate(names):
        if n not in tree.joints:
            rep.report(
                "convert-unknown-joint",
                f"c-space joint '{n}' {not_a_joint(n, tree)}; dropped",
                f"cspace[{i}]",
            )
        else:
            cspace.append(n)
    return cspace


def _read_joint_vectors(
    data: Mapping[str, Any], names: list[str], cspace: list[str], d: Draft, rep: Reporter
) -> None:
    """default_q, acceleration and jerk limits: one number per Lula c-space joint."""
    for key, target in (
        ("default_q", d.defaults),
        ("acceleration_limits", d.acceleration),
        ("jerk_limits", d.jerk),
    ):
        vals = data.get(key)
        if vals is None:
            continue
        if not (isinstance(vals, list) and len(vals) == len(names) and all(map(is_num, vals))):
            raise SourceError(
                f"{key} must be a list of {len(names)} numbers (one per cspace joint)",
                path=rep.path,
                line=rep.position(key)[0],
            )
        for n, v in zip(names, vals, strict=True):
            if n in cspace:
                target[n] = float(v)


def _read_fixed_rules(rules: Any, tree: RobotTree, d: Draft, rep: Reporter) -> None:
    """``cspace_to_urdf_rules`` of kind ``fixed`` become default positions; a rule that is not
    read (another kind, no numeric ``value``) and one on a joint that is not actuated are said."""
    for i, rule in enumerate(rules):
        where = f"cspace_to_urdf_rules[{i}]"
        if not (
            isinstance(rule, Mapping) and rule.get("rule") == "fixed" and is_num(rule.get("value"))
        ):
            _report_unread_rule(rule, rep, where)
            continue
        n = str(rule.get("name"))
        j = tree.joints.get(n)
        if j is not None and j.is_actuated:
            d.defaults[n] = float(rule["value"])
            d.default_at[n] = (rep.path, rep.position(where)[0])
        elif j is not None:
            kind = (
                f"a mimic joint (it follows '{j.mimic_joint}')"
                if j.is_mimic
                else f"a {j.type} joint"
            )
            rep.report(
                "convert-dropped-joint-value",
                f"cspace_to_urdf_rules fixes '{n}', which is {kind}; XRDF default positions "
                "hold only actuated joints; dropped",
                where,
                severity=Severity.INFO,
            )
        else:
            rep.report(
                "convert-unknown-joint",
                f"cspace_to_urdf_rules fixes '{n}', which is not a joint of the URDF"
                f"{did_you_mean(n, tree.joints)}; dropped",
                where,
            )


def _report_unread_rule(rule: Any, rep: Reporter, where: str) -> None:
    """A rule the conversion does not read: Lula's rules are ``{name, rule: fixed, value}``."""
    if isinstance(rule, Mapping) and rule.get("rule") == "fixed":
        why = "a fixed rule without a numeric 'value' (Lula reads the position from 'value')"
    elif isinstance(rule, Mapping):
        why = f"a '{rule.get('rule')}' rule; only fixed rules give a position"
    else:
        why = "not a mapping {name, rule, value}"
    rep.report("convert-dropped-key", f"{where} is {why}; dropped", where)


def _lula_spheres(spheres: list[Any], frames: list[str], rep: Reporter) -> dict[str, list[Sphere]]:
    out: dict[str, list[Sphere]] = {}
    for i, entry in enumerate(spheres):
        if not isinstance(entry, Mapping):
            continue
        for link, items in entry.items():
            w = f"collision_spheres[{i}].{link}"
            if known_frame(str(link), frames, rep, w, "collision spheres"):
                out.setdefault(str(link), []).extend(spheres_of(items, rep, w))
    return {k: v for k, v in out.items() if v}
