"""The XRDF linter: rules as modules, results as diagnostics.

:func:`lint` checks files, :func:`lint_text` one document held in memory. Both return sorted
:class:`~xrdf_tools.diagnostics.Diagnostic` lists and never print. A rule that crashes becomes
an ``internal-error`` diagnostic instead of stopping the run. Without a URDF no URDF library is
imported.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..diagnostics import Diagnostic, Severity, sort_key
from ..util.errors import SourceError, UrdfReadError, XrdfToolsError, YamlError, did_you_mean
from ..util.fileio import STDIN
from ..yaml.io import read_text
from .config import LintConfig
from .context import LintContext, Rule
from .rules import (
    add_frame,
    buffered_radius,
    clone_cycle,
    cspace_joint,
    cspace_joint_held,
    curobo_default_order,
    curobo_different_groups,
    curobo_dropped,
    curobo_floating_joint,
    curobo_format_version,
    curobo_integer,
    curobo_joint_axis,
    curobo_joint_outside_tree,
    curobo_joint_type,
    curobo_missing_key,
    curobo_no_pair,
    curobo_quoted_version,
    curobo_self_buffer,
    curobo_zero_velocity,
    default_position,
    default_self_collision,
    duplicate_key,
    empty_collision_group,
    format_key,
    format_version,
    limits_length,
    limits_value,
    mesh_without_spheres,
    reader_number,
    repeated_cspace_joint,
    repeated_tool_frame,
    required_key,
    sphere_center,
    sphere_outside_geometry,
    sphere_radius,
    unconfirmed_syntax,
    undefined_frame,
    undefined_group,
    unknown_frame,
    unknown_key,
    urdf_invalid,
    urdf_modifiers,
    version_key,
    wrong_type,
    yaml_syntax,
)

if TYPE_CHECKING:
    from ..robot.core import Robot

__all__ = ["RULES", "LintConfig", "Rule", "lint", "lint_text", "rule_by_id", "select_rules"]

#: Every rule, in documentation order: spec rules, URDF-bound rules, cuRobo compatibility.
RULES: tuple[Rule, ...] = (
    yaml_syntax.RULE,
    duplicate_key.RULE,
    format_key.RULE,
    format_version.RULE,
    required_key.RULE,
    wrong_type.RULE,
    unknown_key.RULE,
    version_key.RULE,
    undefined_group.RULE,
    clone_cycle.RULE,
    sphere_center.RULE,
    sphere_radius.RULE,
    buffered_radius.RULE,
    limits_length.RULE,
    limits_value.RULE,
    repeated_cspace_joint.RULE,
    repeated_tool_frame.RULE,
    add_frame.RULE,
    undefined_frame.RULE,
    unconfirmed_syntax.RULE,
    urdf_invalid.RULE,
    urdf_modifiers.RULE,
    unknown_frame.RULE,
    cspace_joint.RULE,
    default_position.RULE,
    default_self_collision.RULE,
    empty_collision_group.RULE,
    mesh_without_spheres.RULE,
    sphere_outside_geometry.RULE,
    curobo_format_version.RULE,
    curobo_missing_key.RULE,
    curobo_dropped.RULE,
    curobo_different_groups.RULE,
    curobo_default_order.RULE,
    curobo_joint_type.RULE,
    curobo_floating_joint.RULE,
    curobo_zero_velocity.RULE,
    cspace_joint_held.RULE,
    curobo_integer.RULE,
    curobo_self_buffer.RULE,
    curobo_joint_outside_tree.RULE,
    curobo_joint_axis.RULE,
    curobo_no_pair.RULE,
    reader_number.RULE,
    curobo_quoted_version.RULE,
)

#: Reported when a rule raises: a bug in the linter, never in the input.
INTERNAL_ERROR = "internal-error"


def rule_by_id(rule_id: str) -> Rule:
    for r in RULES:
        if r.id == rule_id:
            return r
    raise XrdfToolsError(f"unknown rule '{rule_id}'" + did_you_mean(rule_id, [r.id for r in RULES]))


def _matches(rule_id: str, patterns: Iterable[str]) -> bool:
    """A pattern is a rule id or an id prefix ending in '-' (``curobo-``)."""
    return any(rule_id == p or (p.endswith("-") and rule_id.startswith(p)) for p in patterns)


def select_rules(
    select: Sequence[str] = (), ignore: Sequence[str] = (), rules: Sequence[Rule] = RULES
) -> tuple[Rule, ...]:
    """Rules kept by ``--select`` (none given: all) minus ``--ignore``; unknown ids raise."""
    ids = [r.id for r in rules]
    for p in (*select, *ignore):
        if not any(_matches(i, [p]) for i in ids):
            raise XrdfToolsError(f"unknown rule '{p}'" + did_you_mean(p, ids))
    return tuple(
        r for r in rules if (not select or _matches(r.id, select)) and not _matches(r.id, ignore)
    )


#: Loads the ``--urdf`` robot of a file when a rule first asks for it (see
#: :attr:`LintContext.robot`).
UrdfLoader = Callable[[], "Robot"]


def _level(rule: Rule, config: LintConfig, target: str | None) -> tuple[Severity | None, bool]:
    """The severity ``rule`` runs at (None: off) and whether it replaces each finding's own:
    the user's configuration first, then the target, then the rule's default."""
    if config.overrides(rule.id):
        return config.severity(rule.id, rule.severity), True
    return rule.level(target), rule.reader is not None and target is not None


def _run(ctx: LintContext, rules: Sequence[Rule], config: LintConfig) -> list[Diagnostic]:
    out: list[Diagnostic] = []
    parsed = ctx.doc is not None
    for rule in rules:
        severity, forced = _level(rule, config, ctx.target)
        if severity is None:
            continue
        if rule.needs_urdf and not ctx.has_urdf:
            continue
        if not parsed and rule is not yaml_syntax.RULE:
            continue
        try:
            problems = list(rule.check(ctx))
        except XrdfToolsError:
            raise  # URDF load failures are usage errors, reported by the caller
        except Exception as exc:  # a rule bug must not stop the run
            out.append(
                Diagnostic(
                    ctx.path,
                    None,
                    None,
                    INTERNAL_ERROR,
                    Severity.ERROR,
                    f"rule {rule.id} crashed ({type(exc).__name__}: {exc}); please report it",
                )
            )
            continue
        for p in problems:
            sev = severity if forced or p.severity is None else p.severity
            out.append(Diagnostic(ctx.path, p.line, p.col, rule.id, sev, p.message, p.key_path))
    return sorted(out, key=sort_key)


def lint_text(
    text: str,
    path: str = "<string>",
    *,
    urdf: str | os.PathLike[str] | None = None,
    config: LintConfig | None = None,
    rules: Sequence[Rule] = RULES,
    target: str | None = None,
    urdf_model: Any = None,
    allow_missing_meshes: bool = False,
) -> list[Diagnostic]:
    """Lint one XRDF document given as text (``path`` is used in the diagnostics).

    ``target`` (default: the configuration's) names the reader the file is for.
    ``urdf_model`` is a :class:`~xrdf_tools.robot.core.Robot` (or its yourdfpy object) already
    loaded by :mod:`xrdf_tools.robot.urdf_source` (e.g. an expanded xacro), used as it is instead
    of reading ``urdf``, or the :class:`UrdfError` its loading raised.

    Raises :class:`XrdfToolsError` only when ``urdf`` cannot be read at all or the target is
    unknown; a URDF that is not a valid robot is an ``urdf-invalid`` finding.
    """
    cfg = config or LintConfig()
    loader = _urdf_loader(urdf, {}) if urdf is not None else None
    if urdf_model is not None:
        loader = _model_loader(urdf_model)
    return _run(
        LintContext(
            text,
            path,
            urdf_loader=loader,
            target=_target(target, cfg),
            allow_missing_meshes=allow_missing_meshes,
        ),
        rules,
        cfg,
    )


def _target(target: str | None, config: LintConfig) -> str | None:
    from ..xrdf.readers import parse_target

    chosen = parse_target(target if target is not None else config.target)
    return chosen.id if chosen is not None else None


def _model_loader(model: Any) -> UrdfLoader:
    """A loader of an already loaded URDF (a :class:`~xrdf_tools.robot.core.Robot` or its yourdfpy
    object), or of the :class:`UrdfError` its loading raised (reported as ``urdf-invalid``)."""

    def load() -> Robot:
        if isinstance(model, XrdfToolsError):
            raise model
        from ..robot.core import as_robot

        return as_robot(model)

    return load


def _urdf_loader(urdf: str | os.PathLike[str], cache: dict[str, Robot]) -> UrdfLoader:
    """A loader of the URDF (or xacro, expanded) file ``urdf``, read once for all the files
    that use it."""
    upath = os.fspath(urdf)

    def load() -> Robot:
        if upath not in cache:
            from ..robot.xacro_source import load_robot

            cache[upath] = load_robot(upath)
        return cache[upath]

    return load


def _named_by(loader: UrdfLoader, where: tuple[str | None, int | None, int | None]) -> UrdfLoader:
    """``loader`` of a URDF the configuration maps a file to: a URDF that cannot be read is
    the configuration's mistake, so the error points at the entry that names it."""
    path, line, col = where

    def load() -> Robot:
        try:
            return loader()
        except UrdfReadError as e:
            raise UrdfReadError(
                f"the URDF this entry names cannot be read: {e}", path=path, line=line, col=col
            ) from None
        except SourceError as e:  # a xacro that does not expand without arguments
            raise UrdfReadError(
                f"the xacro this entry names cannot be expanded: {e}; "
                "the urdf map passes no xacro arguments: map the expanded URDF (xrdf expand "
                "XACRO --xacro-arg NAME:=VALUE -o ROBOT.urdf) or lint with --urdf XACRO "
                "--xacro-arg NAME:=VALUE",
                path=path,
                line=line,
                col=col,
            ) from None

    return load


def lint(
    paths: Iterable[str | os.PathLike[str]],
    *,
    urdf: str | os.PathLike[str] | None = None,
    config: LintConfig | None = None,
    select: Sequence[str] = (),
    ignore: Sequence[str] = (),
    target: str | None = None,
    urdf_model: Any = None,
    allow_missing_meshes: bool = False,
) -> list[Diagnostic]:
    """Lint XRDF files. ``urdf`` applies to every file; otherwise the config's ``urdf`` map
    picks one per file (or none). ``urdf_model`` (a URDF already loaded, e.g. an expanded
    xacro) applies to every file and replaces ``urdf``. ``target`` (default: the
    configuration's) names the reader. A path ``-`` reads standard input (named ``<stdin>`` in
    the diagnostics; the configuration's ``urdf`` map does not apply to it).
    ``allow_missing_meshes``: collision mesh files that cannot be found are expected (the
    checks that need them are skipped with an info, not a warning).

    A file that cannot be read as UTF-8 text raises :class:`YamlError`, an unreadable URDF
    :class:`UrdfError` (both: usage/input errors, exit code 2); a URDF that is read but is not a
    valid robot is an ``urdf-invalid`` finding.
    """
    cfg = config or LintConfig()
    rules = select_rules(select, ignore)
    chosen = _target(target, cfg)
    cache: dict[str, Robot] = {}
    out: list[Diagnostic] = []
    for p in paths:
        stdin = os.fspath(p) == STDIN
        text = _read_stdin() if stdin else read_text(p)
        u = urdf if urdf is not None or stdin else cfg.urdf_for(Path(p))
        loader = _urdf_loader(u, cache) if u is not None else None
        if loader is not None and urdf is None and not stdin:
            loader = _named_by(loader, cfg.urdf_where(Path(p)))
        if urdf_model is not None:
            loader = _model_loader(urdf_model)
        label = "<stdin>" if stdin else os.fspath(p)
        ctx = LintContext(
            text,
            label,
            urdf_loader=loader,
            target=chosen,
            allow_missing_meshes=allow_missing_meshes,
        )
        out.extend(_run(ctx, rules, cfg))
    return sorted(out, key=sort_key)


def _read_stdin() -> str:
    from ..util.fileio import read_input_text

    return read_input_text(STDIN, what="file", error=YamlError, allow_stdin=True)


__all__ += ["INTERNAL_ERROR", "YamlError"]
