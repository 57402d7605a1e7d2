"""Spheres fitted by MorphIt (``morphit-rs``, the optimiser behind cuRobo v2's robot builder).

``xrdf spheres --method morphit`` and ``xrdf convert --fit-spheres --method morphit`` hand each
link's solid, as :func:`~.robot_fit.fit_robot` prepares it (meshes united, thin shells and open
meshes replaced by hulls or boxes, identical solids fitted once), to MorphIt's gradient
optimiser, preset :data:`PRESET`. Everything around the fit stays ours:

* the count per link is the one our count policy gives (``--count``, ``--per-link``,
  ``--density``; without them, the count our own fit needs to reach the coverage target);
* a placeholder (under 2 cm across) gets our single sphere, as with our method;
* the generator of MorphIt is seeded from the seed and the solid's content (as our fits are)
  and MorphIt's results do not depend on its thread count, so the same inputs give the same
  bytes;
* clip planes: MorphIt fits the part of the solid on the kept side (the solid cut by the
  planes and capped), then a sphere crossing a plane is replaced by the largest sphere inside
  both it and the kept side, so ``n . c - r >= d`` holds as with our fitter;
* ``--max-protrusion``: MorphIt has no hard bound, so every sphere is shrunk to the largest
  radius within the bound (the radius our fitter would give a sphere at that centre).

A sphere that cannot keep 0.1 mm of radius under those bounds is dropped, and said; so is a
solid MorphIt refuses (the link then gets no spheres, which fails the commands).
``morphit_rs`` is imported only when a fit runs: it is an optional extra.
"""

from __future__ import annotations

from collections.abc import Sequence
from types import ModuleType
from typing import TYPE_CHECKING

import numpy as np

from ..diagnostics import Diagnostic, Severity
from ..util.errors import XrdfToolsError
from ..xrdf.model import Sphere

if TYPE_CHECKING:
    import trimesh

    from ..util.arrays import FloatArray
    from .fit import LinkPlan, Plane, SphereFitter
    from .geometry import LinkGeometry

#: The fitting methods: ``ours`` (:mod:`.fit`, the default) and ``morphit`` (this module).
METHODS = ("ours", "morphit")
#: MorphIt's preset: the one cuRobo v2's robot builder uses.
PRESET = "MorphIt-B"
#: The smallest radius (metres) a bounded sphere keeps; below it the sphere is dropped.
MIN_RADIUS = 1e-4

RULE_DROPPED = "spheres-morphit-dropped"
RULE_FAILED = "spheres-morphit-failed"


def require_morphit() -> ModuleType:
    """The ``morphit_rs`` module, or a one-line error naming the extra that installs it."""
    from ..util.extras import require

    require(("morphit_rs",), "morphit", "--method morphit")
    import morphit_rs

    return morphit_rs


def check_method(method: str, *, searched_bound: bool = False) -> None:
    """Raise for an unknown method, or for ``morphit`` when morphit-rs is not installed or
    with a count policy only our fitter follows (``searched_bound``: a bound searched for a
    coverage)."""
    if method not in METHODS:
        raise XrdfToolsError(f"method must be one of {', '.join(METHODS)}, not '{method}'")
    if method != "morphit":
        return
    require_morphit()
    if searched_bound:
        raise XrdfToolsError(
            "method morphit has no protrusion bound to search for a coverage (count_coverage)"
        )


def morphit_seed(fit_seed: Sequence[int]) -> int:
    """One 64-bit seed for MorphIt from the two 32-bit words of a link's fit seed (the user's
    seed and the solid's content)."""
    words = [int(w) & 0xFFFFFFFF for w in fit_seed]
    return (words[0] << 32) | (words[1] if len(words) > 1 else 0)


def pack(solid: trimesh.Trimesh, k: int, seed: int) -> tuple[FloatArray, FloatArray]:
    """MorphIt's ``k`` spheres for ``solid`` (preset :data:`PRESET`): centres and radii.
    Raises :class:`XrdfToolsError` when MorphIt refuses the solid."""
    mi = require_morphit()
    try:
        mesh = mi.Mesh.from_arrays(
            np.asarray(solid.vertices, dtype=np.float64), np.asarray(solid.faces, dtype=np.uint32)
        )
        result = mi.pack(mesh, mi.Config.preset(PRESET, num_spheres=int(k), seed=int(seed)))
    except mi.MorphItError as e:
        raise XrdfToolsError(f"MorphIt cannot fit it: {e}") from None
    centers = np.asarray(result.centers, dtype=np.float64).reshape(-1, 3)
    return centers, np.asarray(result.radii, dtype=np.float64).reshape(-1)


def kept_part(solid: trimesh.Trimesh, planes: Sequence[Plane]) -> trimesh.Trimesh:
    """The part of ``solid`` on the kept side of every plane, capped; the whole solid when
    cutting leaves no closed solid with volume (the spheres are bounded afterwards anyway)."""
    part = solid
    for (nx, ny, nz), d in planes:
        normal = np.array([nx, ny, nz], dtype=np.float64)
        try:
            cut = part.slice_plane(plane_origin=normal * d, plane_normal=normal, cap=True)
        except (ValueError, IndexError):
            return solid
        if cut is None or len(cut.faces) == 0 or not cut.is_watertight or cut.volume <= 0.0:
            return solid
        part = cut
    return part


def inscribed(
    centers: FloatArray, radii: FloatArray, planes: Sequence[Plane]
) -> tuple[FloatArray, FloatArray]:
    """Spheres kept on the positive side of ``planes``: one crossing a plane becomes the
    largest sphere inside both it and the kept half-space (centre moved along the normal by
    half the overshoot, radius shrunk by as much). It reaches no further than before, so it
    stays on the kept side of the planes already applied. Radii may end up negative (a
    sphere wholly on the wrong side)."""
    c: FloatArray = np.array(centers, dtype=np.float64).reshape(-1, 3)
    r: FloatArray = np.array(radii, dtype=np.float64).reshape(-1)
    for (nx, ny, nz), d in planes:
        gap = c[:, 0] * nx + c[:, 1] * ny + c[:, 2] * nz - d
        over = np.maximum(r - gap, 0.0)
        c += 0.5 * over[:, None] * np.array([nx, ny, nz], dtype=np.float64)
        r = r - 0.5 * over
    return c, r


def bounded(
    fitter: SphereFitter,
    centers: FloatArray,
    radii: FloatArray,
    planes: Sequence[Plane],
    tau: float | None,
) -> tuple[tuple[Sphere, ...], int]:
    """MorphIt's spheres within the clip planes (:func:`inscribed`) and, with a protrusion
    bound ``tau``, with each radius cut to the largest within it
    (:meth:`SphereFitter.max_radius`, the radius our fitter gives that centre); rounded as
    ours are (the fitter holds the same planes), and how many were dropped for having under
    :data:`MIN_RADIUS` of room."""
    c, r = inscribed(centers, radii, planes)
    if tau is not None:
        r = np.minimum(r, fitter.max_radius(c))
    keep = r >= MIN_RADIUS
    return fitter.as_spheres(c[keep], r[keep]), int((~keep).sum())


def fit_link(
    fitter: SphereFitter,
    k: int,
    geom: LinkGeometry,
    plan: LinkPlan,
    path: str,
    diags: list[Diagnostic],
) -> tuple[Sphere, ...]:
    """One link's ``k`` spheres by MorphIt, within the bounds of ``fitter``; ``plan`` is the
    link's (cache key, protrusion bound, clip planes, seed). Spheres MorphIt did not return or
    the bounds left no room for are said in ``diags``."""
    if k <= 0:
        return ()
    _key, tau, planes, seed = plan
    solid = kept_part(geom.solid, planes) if planes else geom.solid
    try:
        centers, radii = pack(solid, k, morphit_seed(seed))
    except XrdfToolsError as e:
        diags.append(_warning(path, geom, RULE_FAILED, f"{e}; no spheres"))
        return ()
    spheres, dropped = bounded(fitter, centers, radii, planes, tau)
    if len(spheres) < k:
        why = [f"MorphIt returned {len(radii)}"] if len(radii) < k else []
        if dropped:
            bounds = ["clip planes"] * bool(planes) + ["protrusion bound"] * (tau is not None)
            within = f" within its {' and '.join(bounds)}" if bounds else ""
            why.append(f"{dropped} had under 0.1 mm of radius{within}")
        message = f"{len(spheres)} of the {k} spheres asked of MorphIt kept: {'; '.join(why)}"
        diags.append(_warning(path, geom, RULE_DROPPED, message))
    return spheres


def _warning(path: str, geom: LinkGeometry, rule: str, message: str) -> Diagnostic:
    return Diagnostic(
        path, geom.line, None, rule, Severity.WARNING, f"link '{geom.link}': {message}"
    )
