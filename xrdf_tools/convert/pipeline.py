"""A robot in one call: URDF/xacro (+ SRDF) → spheres → self-collision mask → linted XRDF.

:func:`convert_robot` is the headless setup assistant behind ``xrdf convert --fit-spheres``:

1. load the robot once (a xacro is expanded with its arguments; every later step uses this
   URDF object and its text, never a re-read of the file);
2. convert it (:func:`xrdf_tools.convert.core.convert`);
3. fit spheres to the links that have none, from their collision geometry (visual-only links
   get none unless ``FitOptions.source`` says ``visual`` or ``auto``);
4. compute the self-collision mask exactly like ``xrdf report --write-mask``
   (:func:`xrdf_tools.report.self_collision_report` + :func:`~xrdf_tools.report.recommended_xrdf`):
   adjacent pairs, pairs colliding at the default configuration or almost always, and pairs
   never seen colliding are ignored; pairs that sometimes collide are checked;
5. lint the result against the same URDF object.

With a ``target``, the XRDF is linted for it before step 3: errors that fitting cannot change
(:func:`xrdf_tools.convert.targets.target_errors`) come back at once, without fitting.

It prints nothing: the XRDF, its text and every diagnostic come back in a
:class:`ConvertResult`. Two summary diagnostics say what was fitted (``convert-fitted-spheres``)
and what was masked and why (``convert-computed-mask``, counts per reason).
"""

from __future__ import annotations

import os
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING

from ..diagnostics import Diagnostic, Severity
from ..robot.core import Robot, as_robot
from ..robot.link_geometry import require_meshes
from ..robot.xacro_places import located_at_elements
from ..util.frozen import FrozenMap
from ..util.numbers import REPORT_SAMPLES
from ..util.text import name_list
from .core import ConvertOptions, convert, with_spheres
from .fit_check import RULE_UNFITTED, moving_links_without_spheres, unfitted_links
from .mask_notes import default_pose_pairs, mask_summary, nothing_checked
from .sources.curobo_lula import RULE_NO_MASK

if TYPE_CHECKING:
    import yourdfpy

    from ..report import Report, Sampler
    from ..robot.link_geometry import GeometryChoice
    from ..robot.packages import PackagePaths
    from ..spheres.fit import Plane
    from ..spheres.visual_agreement import VisualCheck
    from ..xrdf.model import Sphere, Xrdf

__all__ = ["ConvertResult", "FitOptions", "MaskOptions", "Progress", "convert_robot"]

RULE_FITTED = "convert-fitted-spheres"

#: ``progress(stage, done, total, item)``; ``stage`` is ``"fitting"`` (``item``: the link
#: being fitted) or ``"sampling"`` (``item``: "").
Progress = Callable[[str, int, int, str], None]


@dataclass(frozen=True)
class FitOptions:
    """How spheres are fitted (see :func:`xrdf_tools.spheres.fit_link_spheres`)."""

    source: GeometryChoice = "collision"
    seed: int = 0
    per_link: int | None = None
    max_protrusion: float | None = None
    #: Go on without mesh files that cannot be found (a warning each) instead of raising
    #: :class:`~xrdf_tools.robot.link_geometry.MissingMeshError`.
    allow_missing_meshes: bool = False
    sphere_budget: int | None = None
    clips: Mapping[str, Sequence[Plane]] = field(default_factory=dict)
    #: ``ours`` or ``morphit`` (:mod:`xrdf_tools.spheres.morphit`, an optional extra).
    method: str = "ours"
    #: How collision geometry is compared with visual geometry (``fast``, ``all``, ``off``:
    #: :mod:`xrdf_tools.spheres.visual_agreement`).
    visual_check: VisualCheck = "fast"


@dataclass(frozen=True)
class MaskOptions:
    """How the self-collision mask is computed (``xrdf report`` sampling options)."""

    samples: int = REPORT_SAMPLES
    seed: int = 0
    sampler: Sampler = "uniform"


@dataclass(frozen=True)
class ConvertResult:
    """What :func:`convert_robot` made.

    ``robot`` is the loaded robot the XRDF was made for; ``diagnostics`` are the
    conversion's (every guess, the fitting and mask summaries); ``lint`` the findings of
    linting ``text`` against ``robot``; ``fitted`` the number of spheres per fitted link;
    ``report`` the self-collision report the mask came from.
    """

    xrdf: Xrdf
    text: str
    robot: Robot
    diagnostics: tuple[Diagnostic, ...]
    lint: tuple[Diagnostic, ...] = ()
    fitted: FrozenMap[str, int] = field(default_factory=FrozenMap)
    report: Report | None = None

    @property
    def lint_errors(self) -> list[Diagnostic]:
        return [d for d in self.lint if d.severity is Severity.ERROR]


def convert_robot(
    robot: str | os.PathLike[str] | Robot,
    options: ConvertOptions,
    *,
    xacro_args: Mapping[str, str] | None = None,
    package_paths: PackagePaths | None = None,
    fit: FitOptions | None = None,
    mask: MaskOptions | None = None,
    lint: bool = True,
    label: str = "<xrdf>",
    progress: Progress | None = None,
    allow_missing_meshes: bool = False,
    missing_mask: MaskOptions | None = None,
) -> ConvertResult:
    """Load ``robot`` (or take it loaded), convert it and, with ``fit``, fit spheres and
    compute the mask.

    ``mask`` defaults to :class:`MaskOptions` when ``fit`` is given (a fitted sphere model
    needs its own mask); pass it without ``fit`` to recompute the mask of the inputs' spheres.
    A source with spheres and no mask (a Lula description, ``convert-lula-no-mask``) gets
    one computed with ``missing_mask`` (default :class:`MaskOptions`).
    ``label`` names the XRDF in lint diagnostics; ``allow_missing_meshes`` tells lint that
    mesh files that cannot be found are expected (``fit`` has its own). Raises
    :class:`~xrdf_tools.util.errors.XrdfToolsError` for unusable inputs.
    """
    from ..xrdf.io import dump_xrdf

    loaded = (
        robot if isinstance(robot, Robot) else _load(robot, xacro_args, package_paths, options.srdf)
    )
    x, diags = convert(loaded, options)
    _check_kinematics(loaded, x)
    diags = [*loaded.warnings, *diags]
    fitted: dict[str, int] = {}
    if fit is not None and lint:
        early = _checked_before_fitting(x, loaded, options, label)
        if early is not None:  # nothing fitted yet: "add spheres (--fit-spheres)" misleads
            kept = tuple(d for d in diags if d.rule != "convert-no-spheres")
            return ConvertResult(x, early[0], loaded, kept, tuple(early[1]))
    if fit is not None:
        x, fitted, diags = _with_fitted_spheres(x, loaded, fit, diags, progress)
        mask = mask or MaskOptions()
    no_mask = mask is None and any(d.rule == RULE_NO_MASK for d in diags)
    if no_mask:
        mask = missing_mask or MaskOptions()
    unfitted = [d for d in diags if d.rule == RULE_UNFITTED]
    report = None
    if unfitted:
        mask = None  # the command fails: no point sampling a mask for an incomplete model
    if mask is not None and x.self_collision_spheres():
        x, report = compute_mask(x, loaded, mask, progress=progress)
        if no_mask:  # the summary says what the warning asked for
            diags = [d for d in diags if d.rule != RULE_NO_MASK]
        diags.extend(_mask_notes(report, x, lula=no_mask))
    text = dump_xrdf(x)
    lint_diags: list[Diagnostic] = []
    if lint:
        lint_diags = _lint_findings(text, label, loaded, options, allow_missing_meshes, diags)
    return ConvertResult(
        x, text, loaded, tuple(diags), tuple(lint_diags), FrozenMap(fitted), report
    )


def _load(
    path: str | os.PathLike[str],
    xacro_args: Mapping[str, str] | None,
    package_paths: PackagePaths | None,
    srdf: str | os.PathLike[str] | None = None,
) -> Robot:
    """The robot of the URDF or xacro at ``path`` (a xacro expanded with ``xacro_args``, which
    ``srdf`` may read too)."""
    from ..robot.xacro_source import load_robot

    return load_robot(path, xacro_args=xacro_args, package_paths=package_paths, srdf=srdf)


def _with_fitted_spheres(
    x: Xrdf,
    robot: Robot,
    fit: FitOptions,
    diags: Sequence[Diagnostic],
    progress: Progress | None,
) -> tuple[Xrdf, dict[str, int], list[Diagnostic]]:
    """``x`` with spheres fitted to the links that have none, the spheres per fitted link,
    and ``diags`` then the fit's: ``convert-no-spheres`` goes once spheres are fitted, and is
    an error when none could be."""
    x, fitted, more = fit_missing_spheres(x, robot, fit, progress=progress)
    if fitted:
        kept = [d for d in diags if d.rule != "convert-no-spheres"]
    else:  # "add spheres (--fit-spheres ...)" would send the user round in a circle
        kept = [_fitted_none(d) if d.rule == "convert-no-spheres" else d for d in diags]
    return x, fitted, [*kept, *more]


def _mask_notes(report: Report, x: Xrdf, *, lula: bool = False) -> list[Diagnostic]:
    """What the computed mask says: its summary (``lula``: computed because the Lula
    description has none), the pairs ignored for colliding at the default pose, and that
    nothing is left to check."""
    summary = mask_summary(report, x)
    if lula:
        why = "the Lula robot description has no self-collision mask (Lula checks none), so "
        summary = replace(summary, message=why + summary.message)
    return [summary, *default_pose_pairs(report), *nothing_checked(report)]


def _lint_findings(
    text: str,
    label: str,
    robot: Robot,
    options: ConvertOptions,
    allow_missing_meshes: bool,
    diags: Sequence[Diagnostic],
) -> list[Diagnostic]:
    """Lint's findings on ``text`` against ``robot`` (for ``options.target``), without those
    the conversion's ``diags`` already say: a link without spheres when no sphere was
    fitted at all, a link the fit left without spheres."""
    from ..lint import lint_text

    found = lint_text(
        text,
        label,
        urdf_model=robot,
        target=options.target,
        allow_missing_meshes=allow_missing_meshes,
    )
    if any(d.rule == "convert-no-spheres" for d in diags):
        # one loud "no spheres at all" says it; a line per link is noise. For a planning
        # target the empty group stays the error it is (the file is not written, exit 1)
        found = [d for d in found if not _said_by_no_spheres(d)]
    said = tuple(d.message.split("'")[1] for d in diags if d.rule == RULE_UNFITTED)
    return [d for d in found if not _about_links(d, "mesh-without-spheres", said)]


def _said_by_no_spheres(d: Diagnostic) -> bool:
    """A lint finding that ``convert-no-spheres`` already says: a link without spheres, or
    the empty group when it is no error (no planning target)."""
    if d.rule == "mesh-without-spheres":
        return True
    return d.rule == "empty-collision-group" and d.severity is not Severity.ERROR


def _fitted_none(no_spheres: Diagnostic) -> Diagnostic:
    """``convert-no-spheres`` after a fit that fitted nothing, as an error: no mesh could be
    read (every one missing, allowed by --allow-missing-meshes). Spheres were what the user
    asked for, so the command fails whatever the target."""
    from dataclasses import replace

    return replace(
        no_spheres,
        severity=Severity.ERROR,
        message=(
            "NO COLLISION SPHERES: --fit-spheres fitted none (no link has collision geometry "
            "it could read; spheres-mesh-unreadable says why): the XRDF would have an empty "
            "geometry group, so cuRobo/cuMotion would check no collision for this robot"
        ),
    )


def _check_kinematics(robot: Robot, x: Xrdf) -> None:
    """Raise the URDF's error, at its line, when no reader can load the robot (a mimic of a
    name that is no joint, mimic joints in a loop): before any work, and never as a finding of
    an XRDF that is not written."""
    from ..robot.kinematics import build_kinematic_model

    build_kinematic_model(robot, x)


def _checked_before_fitting(
    x: Xrdf, robot: Robot, options: ConvertOptions, label: str
) -> tuple[str, list[Diagnostic]] | None:
    """The text and the target's errors when the XRDF fails ``options.target`` whatever
    spheres are fitted (:func:`~xrdf_tools.convert.targets.target_errors`), else None."""
    from ..xrdf.io import dump_xrdf
    from .targets import target_errors

    if options.target is None:
        return None
    text = dump_xrdf(x)
    errors = target_errors(
        text, robot, options.target, label, not (x.cspace and x.cspace.joint_names)
    )
    return (text, errors) if errors else None


def _about_links(d: Diagnostic, rule: str, links: Sequence[str]) -> bool:
    """``d`` is a ``rule`` finding about one of ``links`` (already said otherwise)."""
    return d.rule == rule and any(d.message.startswith(f"link '{link}'") for link in links)


# ------------------------------------------------------------------------------------------
# Spheres
# ------------------------------------------------------------------------------------------
def geometry_links(
    urdf: Robot | yourdfpy.URDF, source: GeometryChoice
) -> tuple[list[str], list[str]]:
    """Links with geometry of kind ``source``, and links that have only visual geometry."""
    usable: list[str] = []
    visual_only: list[str] = []
    for name, link in as_robot(urdf).urdf.link_map.items():
        has_col, has_vis = bool(link.collisions), bool(link.visuals)
        if has_vis and not has_col:
            visual_only.append(name)
        wanted = {"collision": has_col, "visual": has_vis, "auto": has_col or has_vis}
        if wanted[source]:
            usable.append(name)
    return usable, visual_only


def fit_missing_spheres(
    x: Xrdf,
    urdf: Robot | yourdfpy.URDF,
    fit: FitOptions,
    *,
    progress: Progress | None = None,
) -> tuple[Xrdf, dict[str, int], list[Diagnostic]]:
    """Fit spheres to the links of ``urdf`` that have geometry of kind ``fit.source`` and no
    spheres in ``x`` yet; returns the XRDF, the spheres per fitted link and diagnostics."""
    from ..util.extras import FIT, require

    require(FIT, "fit", "--fit-spheres")
    from ..robot.kinematics import build_kinematic_model
    from ..spheres import fit_link_spheres

    have = {k: list(v) for k, v in x.world_collision_spheres().items() if v}
    # only the robot's links: a URDF part the base does not reach is no part of it
    frames = set(build_kinematic_model(urdf, x)[0].frame_names)
    usable, visual_only = (
        [link for link in links if link in frames] for links in geometry_links(urdf, fit.source)
    )
    todo = [link for link in usable if link not in have]
    if not have and not todo:
        _nothing_to_fit(as_robot(urdf).path, fit.source, visual_only)
    _check_frame_ceiling(as_robot(urdf).path, len(set(have) | set(todo)))

    def step(link: str, i: int, n: int) -> None:
        if progress is not None:
            progress("fitting", i, n, link)

    def read(link: str, i: int, n: int) -> None:
        if progress is not None:
            progress("reading", i, n, link)

    robot = as_robot(urdf)
    # before the work: a mesh that cannot be found is an input error (or, allowed, a warning)
    missing = require_meshes(robot, fit.source, links=todo, allow_missing=fit.allow_missing_meshes)
    fitted, diags = fit_link_spheres(
        robot,
        links=todo,
        per_link=fit.per_link,
        count=fit.sphere_budget,
        clips=fit.clips,
        seed=fit.seed,
        max_protrusion=fit.max_protrusion,
        progress=step,
        reading=read,
        source=fit.source,
        method=fit.method,
        visual_check=fit.visual_check,
    )
    merged: dict[str, Sequence[Sphere]] = {**have}
    for link, spheres in fitted.items():
        merged[link] = [*merged.get(link, ()), *spheres]
    counts = {k: len(v) for k, v in fitted.items()}
    summary = fit_summary(robot.path, counts, fit.source, visual_only, len(have))
    errors = unfitted_links(
        robot.path, todo, fitted, diags, allowed_missing=missing, lines=robot.link_lines
    )
    if fit.source == "collision":
        moved_by = _moved_by_cspace(robot, x)
        errors += moving_links_without_spheres(robot.path, visual_only, moved_by, robot.link_lines)
    said = located_at_elements([*diags, summary, *errors], robot.path, robot.include_places)
    return with_spheres(x, dict(merged)), counts, said


def _moved_by_cspace(robot: Robot, x: Xrdf) -> dict[str, str]:
    """Child link -> joint, for each c-space joint of ``x``."""
    cspace = set(x.cspace.joint_names) if x.cspace is not None else set()
    return {j.child: name for name, j in robot.tree.joints.items() if name in cspace}


def _check_frame_ceiling(path: str, frames: int) -> None:
    """Raise before the fit when more links would carry spheres than the self-collision mask
    can check (:data:`~xrdf_tools.selfcollision.collision.MAX_SPHERE_FRAMES`): the mask
    would refuse them only after every link was fitted."""
    from ..selfcollision.collision import MAX_SPHERE_FRAMES, SphereLimitError

    if frames > MAX_SPHERE_FRAMES:
        raise SphereLimitError(
            f"--fit-spheres: {frames:,} links would carry spheres, more than the "
            f"self-collision mask checks (at most {MAX_SPHERE_FRAMES:,} frames); merge links "
            "joined by fixed joints, or leave the collision geometry out of links no planner "
            "needs (markers, sensors)",
            path=path,
        )


def _nothing_to_fit(path: str, source: GeometryChoice, visual_only: Sequence[str]) -> None:
    """Raise: spheres were asked for, and no link has geometry of kind ``source`` to fit them
    to (a URDF with visual geometry only would give an XRDF that checks no collision)."""
    from ..util.errors import XrdfToolsError

    if visual_only:
        shown = name_list(visual_only)
        raise XrdfToolsError(
            f"--fit-spheres: no link has {source} geometry to fit spheres to; "
            f"{len(visual_only)} link(s) have visual geometry only ({shown}): --from visual "
            "fits spheres to it",
            path=path,
        )
    raise XrdfToolsError(
        f"--fit-spheres: no link has {source} geometry to fit spheres to (the URDF has no "
        "<collision> and no <visual> geometry)",
        path=path,
    )


def fit_summary(
    path: str,
    counts: Mapping[str, int],
    source: GeometryChoice,
    visual_only: Sequence[str],
    kept: int,
) -> Diagnostic:
    """One line: how many spheres on how many links, from what, and who got none."""
    what = {"collision": "collision", "visual": "visual", "auto": "collision (else visual)"}
    msg = (
        f"fitted {sum(counts.values())} sphere(s) to {len(counts)} link(s) from their "
        f"{what[source]} geometry"
    )
    if kept:
        msg += f"; {kept} link(s) kept the spheres of the inputs"
    if source == "collision" and visual_only:
        shown = name_list(visual_only)
        msg += (
            f"; {len(visual_only)} link(s) with visual geometry only get none ({shown}); "
            "--from visual fits them too"
        )
    return Diagnostic(path, None, None, RULE_FITTED, Severity.INFO, msg, "geometry")


# ------------------------------------------------------------------------------------------
# Mask
# ------------------------------------------------------------------------------------------
def compute_mask(
    x: Xrdf,
    urdf: Robot | yourdfpy.URDF,
    mask: MaskOptions,
    *,
    progress: Progress | None = None,
) -> tuple[Xrdf, Report]:
    """``x`` with ``self_collision.ignore`` as ``xrdf report --write-mask`` recommends."""
    from ..report import recommended_xrdf, self_collision_report

    def step(done: int, total: int) -> None:
        if progress is not None:
            progress("sampling", done, total, "")

    report = self_collision_report(
        urdf,
        x,
        samples=mask.samples,
        seed=mask.seed,
        sampler=mask.sampler,
        progress=step if progress is not None else None,
    )
    return recommended_xrdf(x, report), report
