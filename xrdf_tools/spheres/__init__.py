"""Collision spheres from link geometry, and how well spheres cover it.

* :func:`fit_link_spheres` -- fit spheres to the links of a URDF/xacro (``xrdf spheres``,
  ``xrdf convert --fit-spheres``).
* :func:`sphere_metrics` -- the one function that measures coverage, surface coverage and
  protrusion of spheres against a solid (see :mod:`xrdf_tools.spheres.metrics`).
* :func:`coverage_for_xrdf` -- those metrics per link and overall for an XRDF's spheres
  (``xrdf report``).
* :func:`merge_spheres` -- put fitted spheres into an XRDF, replacing only the fitted links.

trimesh, scipy and lxml are imported lazily: importing this package is cheap.
"""

from __future__ import annotations

import math
import os
import zlib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from ..diagnostics import Diagnostic, Severity
from ..robot.core import Robot
from ..util.errors import XrdfToolsError
from ..util.frozen import FrozenMap
from ..xrdf.model import CollisionSection, GeometryGroup, SelfCollisionSection, Sphere, Xrdf
from .metrics import SphereMetrics, sphere_metrics

if TYPE_CHECKING:
    from ..robot.link_geometry import GeometryChoice
    from .geometry import LinkGeometry

__all__ = [
    "CoverageSummary",
    "SphereMetrics",
    "coverage_for_xrdf",
    "fit_link_spheres",
    "merge_spheres",
    "sphere_metrics",
]

MAX_PER_LINK = 64
AUTO_COVERAGE_TARGET = 0.9
AUTO_MAX_PER_LINK = 16
RULE_MERGE_CLONED = "spheres-cloned-link"


def link_seed(seed: int, link: str) -> list[int]:
    """Seed of one link: independent of which other links are fitted."""
    return [int(seed) & 0xFFFFFFFF, zlib.crc32(link.encode("utf-8"))]


def _check_counts(
    per_link: int | Mapping[str, int] | None, count: int | None, density: float | None
) -> None:
    given = [
        n
        for n, v in (("per_link", per_link), ("count", count), ("density", density))
        if v is not None
    ]
    if len(given) > 1:
        raise XrdfToolsError(f"give at most one of count, per-link and density (got {given})")
    for n in per_link.values() if isinstance(per_link, Mapping) else [per_link]:
        if n is not None and not 0 <= n <= MAX_PER_LINK:
            raise XrdfToolsError(f"per-link must be between 1 and {MAX_PER_LINK}, got {n}")
    if isinstance(per_link, int) and per_link < 1:
        raise XrdfToolsError(f"per-link must be between 1 and {MAX_PER_LINK}, got {per_link}")
    if count is not None and count < 1:
        raise XrdfToolsError(f"count must be at least 1, got {count}")
    if density is not None and not (density > 0 and math.isfinite(density)):
        raise XrdfToolsError(f"density must be a positive number, got {density}")


def _allocate(
    curves: Mapping[str, Sequence[float]], volumes: Mapping[str, float], total: int
) -> dict[str, int]:
    """Split ``total`` spheres over links: one each, then by largest covered-volume gain."""
    alloc = dict.fromkeys(curves, 1)
    left = total - len(alloc)
    while left > 0:
        best, best_gain = None, -1.0
        for link, curve in curves.items():
            k = alloc[link]
            if k >= len(curve):
                continue
            gain = (curve[k] - curve[k - 1]) * volumes[link]
            if gain > best_gain:
                best, best_gain = link, gain
        if best is None:
            break
        alloc[best] += 1
        left -= 1
    return alloc


def fit_link_spheres(
    urdf_path: str | os.PathLike[str] | Robot,
    *,
    links: Sequence[str] | None = None,
    per_link: int | Mapping[str, int] | None = None,
    count: int | None = None,
    density: float | None = None,
    seed: int = 0,
    package_paths: Mapping[str, str] | None = None,
    max_protrusion: float | Mapping[str, float] | None = None,
    progress: Any = None,
    source: GeometryChoice = "auto",
) -> tuple[dict[str, tuple[Sphere, ...]], list[Diagnostic]]:
    """Fit spheres to every link with geometry (or to ``links``) of a URDF or xacro file.

    How many spheres per link, at most one of:

    * ``per_link`` -- that many for each link (or ``{link: n}``; links not in it get none);
    * ``count`` -- that many in total (at least one per link), handed out one by one to the
      link whose covered volume grows most;
    * ``density`` -- ``ceil(density * volume in litres)`` per link (1 to 64);
    * none -- per link, the fewest spheres (up to 16) whose greedy cover reaches 90 %.

    ``max_protrusion`` (metres, one value or per link) bounds how far each sphere may reach
    outside its link; by default 6 % of the cube root of the link's volume. ``source`` chooses
    the geometry as in :func:`~xrdf_tools.spheres.geometry.load_link_geometry`. The same inputs
    and ``seed`` give the same spheres. ``progress(link, i, n)`` is called before each link.
    ``urdf_path`` may be a loaded :class:`~xrdf_tools.robot.core.Robot`, whose geometry is then
    read without parsing the URDF again (see
    :func:`~xrdf_tools.spheres.geometry.load_link_geometry`).
    Returns ``({link: spheres}, diagnostics)`` in URDF link order.
    """
    from .fit import SphereFitter
    from .geometry import load_link_geometry

    _check_counts(per_link, count, density)
    geoms, diags = load_link_geometry(
        urdf_path, links=links, package_paths=package_paths, source=source
    )
    if count is not None and count < len(geoms):
        raise XrdfToolsError(
            f"count {count} is less than the number of links to fit ({len(geoms)})"
        )
    fitters: dict[str, SphereFitter] = {}
    for i, (name, g) in enumerate(geoms.items()):
        if progress is not None:
            progress(name, i, len(geoms))
        tau = max_protrusion.get(name) if isinstance(max_protrusion, Mapping) else max_protrusion
        fitters[name] = SphereFitter(g.solid, seed=link_seed(seed, name), max_protrusion=tau)
    if isinstance(per_link, Mapping):
        ks = {n: int(per_link.get(n, 0)) for n in fitters}
    elif per_link is not None:
        ks = dict.fromkeys(fitters, per_link)
    elif density is not None:
        ks = {
            n: min(MAX_PER_LINK, max(1, math.ceil(density * f.volume * 1000.0 - 1e-9)))
            for n, f in fitters.items()
        }
    elif count is not None:
        if count < len(fitters):
            raise XrdfToolsError(
                f"count {count} is less than the number of links to fit ({len(fitters)})"
            )
        cap = min(MAX_PER_LINK, count - len(fitters) + 1)
        curves = {n: f.greedy(cap)[1] for n, f in fitters.items()}
        ks = _allocate(curves, {n: f.volume for n, f in fitters.items()}, count)
    else:
        ks = {}
        for n, f in fitters.items():
            curve = f.greedy(AUTO_MAX_PER_LINK)[1]
            reach = [k + 1 for k, c in enumerate(curve) if c >= AUTO_COVERAGE_TARGET]
            ks[n] = reach[0] if reach else AUTO_MAX_PER_LINK
    fitted = {n: fitters[n].fit(ks[n]) for n in fitters if ks[n] > 0}
    return fitted, diags


# --------------------------------------------------------------------------------------------
# Coverage of an XRDF
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class CoverageSummary:
    """Metrics of an XRDF's spheres per link (links with geometry) and overall.

    ``overall`` pools all links: coverage weighted by volume, surface coverage by area,
    protrusion over the pooled union-boundary samples. ``unmeasured`` lists frames that carry
    spheres but have no geometry (added frames, links without meshes).
    """

    group: str
    links: FrozenMap[str, SphereMetrics]
    overall: SphereMetrics
    unmeasured: tuple[str, ...] = ()
    diagnostics: tuple[Diagnostic, ...] = field(default=(), compare=False)

    def to_dict(self) -> dict[str, Any]:
        return {
            "group": self.group,
            "links": {k: v.to_dict() for k, v in self.links.items()},
            "overall": self.overall.to_dict(),
            "unmeasured": list(self.unmeasured),
        }

    @property
    def per_frame(self) -> dict[str, dict[str, float]]:
        """The numeric metrics of each measured link (what ``xrdf report --coverage`` shows)."""
        return {k: _numbers(v.to_dict()) for k, v in self.links.items()}

    @property
    def overall_numbers(self) -> dict[str, float]:
        return _numbers(self.overall.to_dict()) if self.links else {}

    @property
    def note(self) -> str:
        return (
            f"not measured (no geometry): {', '.join(self.unmeasured)}" if self.unmeasured else ""
        )


def _numbers(m: Mapping[str, Any]) -> dict[str, float]:
    return {
        str(k): float(v)
        for k, v in m.items()
        if isinstance(v, (int, float)) and not isinstance(v, bool)
    }


def _default_group(xrdf: Xrdf) -> str | None:
    if xrdf.world_collision is not None:
        return xrdf.world_collision.geometry
    if xrdf.self_collision is not None:
        return xrdf.self_collision.geometry
    groups = list(xrdf.geometry or {})
    return groups[0] if groups else None


def measure_links(
    geoms: Mapping[str, LinkGeometry],
    spheres: Mapping[str, Sequence[Sphere]],
    *,
    samples: int,
    seed: int,
) -> tuple[dict[str, SphereMetrics], SphereMetrics]:
    """Per-link metrics for ``geoms`` and the pooled overall metrics."""
    from .metrics import measure

    per: dict[str, SphereMetrics] = {}
    prot: list[np.ndarray[Any, np.dtype[np.float64]]] = []
    weights: list[np.ndarray[Any, np.dtype[np.float64]]] = []
    for name, g in geoms.items():
        m, p, w = measure(
            g.solid, spheres.get(name, ()), samples=samples, seed=link_seed(seed, name)
        )
        per[name] = m
        prot.append(p)
        weights.append(w)
    return per, pooled(per, prot, weights)


def pooled(
    per: Mapping[str, SphereMetrics],
    prot: Sequence[np.ndarray[Any, np.dtype[np.float64]]],
    weights: Sequence[np.ndarray[Any, np.dtype[np.float64]]],
) -> SphereMetrics:
    """Overall metrics of several links (see :class:`CoverageSummary`)."""
    from .metrics import weighted_quantile

    vol = sum(m.volume for m in per.values())
    area = sum(m.area for m in per.values())
    p = np.concatenate(prot) if prot else np.zeros(0)
    w = np.concatenate(weights) if weights else np.zeros(0)
    kinds = {m.solid for m in per.values()}
    return SphereMetrics(
        sphere_count=sum(m.sphere_count for m in per.values()),
        coverage=sum(m.coverage * m.volume for m in per.values()) / vol if vol else 0.0,
        surface_coverage=(
            sum(m.surface_coverage * m.area for m in per.values()) / area if area else 0.0
        ),
        protrusion_mean=float((p * w).sum() / w.sum()) if len(p) else 0.0,
        protrusion_p95=weighted_quantile(p, w, 0.95),
        protrusion_max=float(p.max()) if len(p) else 0.0,
        volume=vol,
        area=area,
        solid=kinds.pop() if len(kinds) == 1 else "mixed",
    )


def coverage_for_xrdf(
    urdf_path: str | os.PathLike[str] | Robot,
    xrdf: Xrdf,
    *,
    package_paths: Mapping[str, str] | None = None,
    samples: int = 20_000,
    seed: int = 0,
    group: str | None = None,
) -> CoverageSummary:
    """Coverage metrics of the XRDF's spheres against the URDF's link geometry.

    ``group`` defaults to the world-collision group (else the self-collision group, else the
    first group); clones are resolved. Every link with geometry is measured (a link without
    spheres has coverage 0). ``urdf_path`` may be a loaded :class:`~xrdf_tools.robot.core.Robot`.
    """
    from .geometry import load_link_geometry

    name = group or _default_group(xrdf)
    spheres = xrdf.resolved_spheres(name) if name is not None else FrozenMap()
    geoms, diags = load_link_geometry(urdf_path, package_paths=package_paths)
    per, overall = measure_links(geoms, spheres, samples=samples, seed=seed)
    unmeasured = tuple(f for f, s in spheres.items() if s and f not in geoms)
    return CoverageSummary(name or "", FrozenMap(per), overall, unmeasured, tuple(diags))


# --------------------------------------------------------------------------------------------
# Merging into an XRDF
# --------------------------------------------------------------------------------------------
def target_group(xrdf: Xrdf) -> str:
    """The group fitted spheres go into: world collision, else self collision, else the
    only group, else ``"collision_spheres"``."""
    name = _default_group(xrdf)
    if name is None or (
        xrdf.world_collision is None
        and xrdf.self_collision is None
        and len(xrdf.geometry or {}) > 1
    ):
        return "collision_spheres" if not xrdf.geometry else next(iter(xrdf.geometry))
    return name


def merge_spheres(
    xrdf: Xrdf, fitted: Mapping[str, Sequence[Sphere]], *, group: str | None = None
) -> tuple[Xrdf, list[Diagnostic]]:
    """``xrdf`` with the spheres of the fitted links replaced in ``group``'s own spheres.

    Other links keep their spheres; links new to the group are appended in ``fitted`` order.
    A missing group is created, and so are world/self collision sections naming it when the
    XRDF has neither. Spheres a link also receives through ``clone`` are left alone and
    reported (``spheres-cloned-link``).
    """
    name = group or target_group(xrdf)
    geometry = dict(xrdf.geometry or {})
    old = geometry.get(name, GeometryGroup())
    merged = dict(old.spheres)
    for link, spheres in fitted.items():
        merged[link] = tuple(spheres)
    geometry[name] = GeometryGroup(FrozenMap(merged), old.clone)
    changes: dict[str, object] = {"geometry": FrozenMap(geometry)}
    if xrdf.world_collision is None and xrdf.self_collision is None:
        changes["world_collision"] = CollisionSection(name)
        changes["self_collision"] = SelfCollisionSection(name)
    out = xrdf.replace(**changes)
    diags: list[Diagnostic] = []
    if old.clone:
        from ..xrdf.model import clone_order

        groups: Mapping[str, GeometryGroup] = out.geometry or FrozenMap()
        for child in clone_order(groups, name)[1:]:
            for link in fitted:
                if groups[child].spheres.get(link):
                    diags.append(
                        Diagnostic(
                            xrdf.source.path,
                            None,
                            None,
                            RULE_MERGE_CLONED,
                            Severity.WARNING,
                            f"link '{link}' also gets spheres from cloned group '{child}', "
                            "which were kept",
                            f"geometry.{child}.spheres.{link}",
                        )
                    )
    return out, diags


RULE_ADJACENT = "spheres-adjacent-ignored"


def ignore_adjacent(
    xrdf: Xrdf,
    urdf_path: str | os.PathLike[str] | Robot,
    *,
    package_paths: Mapping[str, str] | None = None,
    urdf: Any = None,
) -> tuple[Xrdf, list[Diagnostic]]:
    """Add each pair of *adjacent* sphere frames to the self-collision ignore mask.

    Two frames with spheres are adjacent when one is the nearest ancestor with spheres of the
    other (frames without spheres in between, such as fixed flange frames, are skipped). This
    is MoveIt's "adjacent links" rule: their spheres overlap at the joint by construction.
    Used for a freshly drafted XRDF; a mask written by a user is left to the user. ``urdf``
    is the robot already loaded (an expanded xacro); otherwise ``urdf_path`` is read (or is
    the loaded :class:`~xrdf_tools.robot.core.Robot`).
    """
    from ..robot.urdf_source import joints_of
    from ..robot.xacro_source import load_robot

    if isinstance(urdf_path, Robot):
        urdf = urdf_path if urdf is None else urdf
        urdf_path = urdf_path.path
    if xrdf.self_collision is None:
        return xrdf, []
    spheres = xrdf.self_collision_spheres()
    with_spheres = {f for f, s in spheres.items() if s}
    if urdf is None:
        urdf = load_robot(urdf_path, package_paths=dict(package_paths or {}))
    parent = {j.child: j.parent for j in joints_of(urdf).values()}
    ignore = {k: list(v) for k, v in xrdf.self_collision.ignore.items()}
    added = 0
    for frame in spheres:
        if frame not in with_spheres:
            continue
        up = parent.get(frame)
        while up is not None and up not in with_spheres:
            up = parent.get(up)
        if up is None or xrdf.self_collision.is_ignored(up, frame):
            continue
        ignore.setdefault(up, []).append(frame)
        added += 1
    if not added:
        return xrdf, []
    section = SelfCollisionSection(
        xrdf.self_collision.geometry,
        xrdf.self_collision.buffer_distance,
        FrozenMap((k, tuple(v)) for k, v in ignore.items()),
    )
    diag = Diagnostic(
        xrdf.source.path or os.fspath(urdf_path),
        None,
        None,
        RULE_ADJACENT,
        Severity.INFO,
        f"{added} pair(s) of adjacent links added to self_collision.ignore (their spheres "
        "meet at the joint)",
        "self_collision.ignore",
    )
    return xrdf.replace(self_collision=section), [diag]
