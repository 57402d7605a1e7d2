"""How one link's solid is fitted, as :func:`~.robot_fit.fit_robot` plans it: a sheet's few
spheres (:mod:`.sheet`), MorphIt's (:mod:`.morphit`), or ours (:class:`~.fit.SphereFitter`):
``k`` spheres within a bound, refined or under a searched bound, the fewest reaching the
coverage target, one for a placeholder; with the notes that say so."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..diagnostics import Diagnostic, Severity
from ..util.fixed_order import norm
from ..util.numbers import PLACEHOLDER_SIZE
from ..xrdf.model import Sphere
from .count_policy import MAX_PER_LINK, CountPolicy
from .fewest import default_fit, fewest_reaching, past_grid_note

if TYPE_CHECKING:
    import trimesh

    from .fit import LinkPlan, SphereFitter
    from .geometry import LinkGeometry
    from .sheet import SheetPlan

__all__ = [
    "fit_mode",
    "fit_note",
    "fit_one",
    "fit_sheet",
    "link_fitter",
    "morphit_one",
    "sheet_of",
]

RULE_TARGET_MISSED = "spheres-target-missed"
RULE_PLACEHOLDER = "spheres-placeholder"
RULE_SHEET = "spheres-sheet"
RULE_PAST_BOUND = "spheres-past-bound"
RULE_SURFACE_GAP = "spheres-surface-gap"


def fit_note(
    path: str, line: int | None, rule: str, message: str, warn: bool = False
) -> Diagnostic:
    """A fit's note on a link: info, or a warning with ``warn``."""
    return Diagnostic(path, line, None, rule, Severity.WARNING if warn else Severity.INFO, message)


def link_fitter(geom: LinkGeometry, plan: LinkPlan, counts: CountPolicy) -> SphereFitter:
    """Our fitter of a link's solid, with the protrusion bound, clip planes and seed of its
    ``plan``."""
    from .fit import SphereFitter

    _key, tau, planes, fit_seed = plan
    return SphereFitter(
        geom.solid,
        seed=fit_seed,
        max_protrusion=tau,
        clips=planes,
        room=_refine_room(geom.solid, tau, counts),
    )


def sheet_of(geom: LinkGeometry, plan: LinkPlan, counts: CountPolicy) -> SheetPlan | None:
    """How the sheet rule fits a link (:func:`.sheet.sheet_plan`), when it applies: no count
    given, no clip plane, not a placeholder."""
    if counts.given or plan[2] or _across(geom) < PLACEHOLDER_SIZE:
        return None
    from .sheet import sheet_plan

    return sheet_plan(geom.solid, plan[1])


def fit_sheet(
    sheet: SheetPlan, geom: LinkGeometry, bound: float | None, path: str, diags: list[Diagnostic]
) -> tuple[Sphere, ...]:
    """A sheet's spheres (:func:`.sheet.sheet_spheres`), said once for the link; ``bound``:
    the link's own protrusion bound."""
    from .fit import default_max_protrusion
    from .sheet import sheet_message, sheet_spheres

    spheres = sheet_spheres(*sheet, geom.solid)
    tau = default_max_protrusion(geom.solid) if bound is None else bound
    message, past = sheet_message(geom.link, sheet[0], spheres, tau, own=bound is not None)
    diags.append(fit_note(path, geom.line, RULE_SHEET, message, warn=past))
    return spheres


def fit_mode(tau: float | None, counts: CountPolicy) -> str:
    """How :func:`fit_one` fits a link whose own bound is ``tau`` (None: the default)."""
    if _refines(tau, counts):
        return "refine"
    return "search" if tau is None and counts.count_coverage is not None else "hard"


def _across(geom: LinkGeometry) -> float:
    """The bounding-box diagonal of a link's solid: under :data:`PLACEHOLDER_SIZE`, a
    placeholder."""
    return norm(np.asarray(geom.solid.extents, dtype=np.float64))  # not a BLAS dot product


def _refines(tau: float | None, counts: CountPolicy) -> bool:
    """Whether a link's count-given fit is refined (:mod:`.refine`): a count is given, the
    link has no bound of its own and no bound is searched for a coverage."""
    return counts.given and tau is None and counts.refine and counts.count_coverage is None


def _refine_room(solid: trimesh.Trimesh, tau: float | None, counts: CountPolicy) -> float | None:
    """How far the distance grid of a refined fit reaches: past the loosest start's bound,
    so that one grid serves every start (None: the fitter's own bound)."""
    if not _refines(tau, counts):
        return None
    from .fit import default_max_protrusion
    from .refine import START_BOUNDS

    return max(START_BOUNDS) * default_max_protrusion(solid)


def morphit_one(
    fitter: SphereFitter,
    k: int | None,
    counts: CountPolicy,
    geom: LinkGeometry,
    plan: LinkPlan,
    path: str,
    diags: list[Diagnostic],
) -> tuple[Sphere, ...]:
    """One link's spheres by MorphIt (:mod:`.morphit`): ``k`` of them, or the count our fit
    needs for the coverage target; an empty solid or a placeholder is handled as ours."""
    from .morphit import fit_link

    if fitter.empty or _across(geom) < PLACEHOLDER_SIZE:
        return fit_one(fitter, k, counts, geom, path, diags)
    if k is None:
        k = len(fewest_reaching(fitter, counts.target_coverage)[0])
    return fit_link(fitter, k, geom, plan, path, diags)


def fit_one(
    fitter: SphereFitter,
    k: int | None,
    counts: CountPolicy,
    geom: LinkGeometry,
    path: str,
    diags: list[Diagnostic],
    mode: str = "hard",
    own_bound: bool = False,
    moved_by: str | None = None,
) -> tuple[Sphere, ...]:
    """One link's spheres: ``k`` of them (``mode``: ``hard`` within the fitter's bound,
    ``refine`` then refined on coverage and protrusion, ``search`` under the smallest bound
    at which they cover ``counts.count_coverage``), or the fewest reaching the coverage
    target (past the default bound when it cannot be reached within it, unless the link has
    a bound of its own: :mod:`.fewest`). ``moved_by``: the joint nearest above the link that
    moves it (None: fixed to the root), for the advice on a plate."""
    if fitter.empty and k != 0:
        diags.append(
            fit_note(
                path,
                geom.line,
                RULE_TARGET_MISSED,
                f"link '{geom.link}': nothing of it lies on the kept side of its clip planes; "
                "no spheres",
                warn=True,
            )
        )
        return ()
    size = _across(geom)
    if size < PLACEHOLDER_SIZE and (k is None or k > 1):
        diags.append(
            fit_note(
                path,
                geom.line,
                RULE_PLACEHOLDER,
                f"link '{geom.link}' is a placeholder ({size * 1000:.0f} mm across): one sphere",
            )
        )
        return fitter.fit(1)
    if k is not None and mode == "search" and counts.count_coverage is not None:
        from .fit import bound_for_coverage

        return bound_for_coverage(fitter, k, counts.count_coverage)
    if k is not None and mode == "refine":
        from .refine import refined_fit

        return refined_fit(fitter, k)
    if k is not None:
        spheres = fitter.fit(k)
        said = past_grid_note(fitter, spheres, own_bound)
        if said is not None:
            message = f"link '{geom.link}': {said}"
            diags.append(fit_note(path, geom.line, RULE_PAST_BOUND, message, warn=True))
        return spheres
    past = not own_bound and counts.refine
    spheres, note = default_fit(fitter, counts.target_coverage, past=past, most=MAX_PER_LINK)
    if past and note is not None and not len(fitter.clips):
        plate = _plate_instead(fitter, geom, spheres, (path, moved_by), diags)
        if plate is not None:
            return plate
    if note is not None:
        rule = RULE_TARGET_MISSED if note.missed else RULE_PAST_BOUND
        message = f"link '{geom.link}': {note.text}"
        diags.append(fit_note(path, geom.line, rule, message, warn=note.warn))
    if counts.reach_surface:
        spheres = _reach_surface(fitter, spheres, geom, (path, own_bound), diags)
    return spheres


def _reach_surface(
    fitter: SphereFitter,
    spheres: tuple[Sphere, ...],
    geom: LinkGeometry,
    where: tuple[str, bool],
    diags: list[Diagnostic],
) -> tuple[Sphere, ...]:
    """``spheres`` with more where a part of the link's surface lies far from them
    (:func:`.surface_gap.reach_far_surface`, up to :data:`MAX_PER_LINK`), said once for the
    link: info when they reach it, a warning when they cannot. ``where``: the URDF path the
    note names and whether the link's bound is the user's."""
    from .fit import default_max_protrusion
    from .surface_gap import reach_far_surface

    path, own = where
    bound = fitter.tau if own else default_max_protrusion(geom.solid)
    spheres, reached = reach_far_surface(fitter, spheres, MAX_PER_LINK, bound)
    if reached is not None:
        message = reached.said(geom.link, bound, own)
        diags.append(fit_note(path, geom.line, RULE_SURFACE_GAP, message, warn=not reached.met))
    return spheres


def _plate_instead(
    fitter: SphereFitter,
    geom: LinkGeometry,
    spheres: tuple[Sphere, ...],
    where: tuple[str, str | None],
    diags: list[Diagnostic],
) -> tuple[Sphere, ...] | None:
    """A plate's sheet spheres (:func:`.sheet.sheet_spheres`) in place of ``spheres``, refined
    past the default bound, when they reach less far from its faces; said once for the link.
    A plate thicker than its bound is no sheet (:func:`.sheet.as_sheet`), and refining a few
    spheres past the bound over a wide one makes them huge: 16 over the 1.2 m table of
    Trossen's Stationary AI reached 156 mm above it, so every arm link near the table
    collided with it. ``where``: the URDF path the note names and the joint that moves the
    link (None: fixed to the root)."""
    from .sheet import as_plate, face_reach, plate_message, sheet_spheres

    plate = as_plate(geom.solid)
    if plate is None:
        return None
    flat = sheet_spheres(plate, solid=geom.solid)
    past = face_reach(plate, spheres)
    if face_reach(plate, flat) >= past:
        return None
    from .fit import default_max_protrusion

    bound = default_max_protrusion(geom.solid)  # fitter.tau is widened past it by now
    path, moved_by = where
    message, warn = plate_message(geom.link, plate, flat, bound, past, len(spheres), moved_by)
    diags.append(fit_note(path, geom.line, RULE_SHEET, message, warn=warn))
    return flat
