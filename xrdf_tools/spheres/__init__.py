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

import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any

from ..diagnostics import Diagnostic, Severity
from ..robot.adjacency import Edges, adjacent_pairs, edges_of_joints
from ..robot.core import Robot
from ..util.frozen import FrozenMap
from ..util.text import name_list
from ..xrdf.model import CollisionSection, GeometryGroup, SelfCollisionSection, Sphere, Xrdf
from .count_policy import AUTO_COVERAGE_TARGET, MAX_PER_LINK
from .metrics import SphereMetrics, sphere_metrics
from .robot_fit import link_seed

if TYPE_CHECKING:
    from ..robot.link_geometry import GeometryChoice
    from ..robot.packages import PackagePaths
    from .fit import Plane
    from .geometry import LinkGeometry
    from .visual_agreement import VisualCheck

__all__ = [
    "MAX_PER_LINK",
    "CoverageSummary",
    "SphereMetrics",
    "coverage_for_xrdf",
    "fit_link_spheres",
    "link_seed",
    "merge_spheres",
    "sphere_metrics",
]

RULE_MERGE_CLONED = "spheres-cloned-link"


def fit_link_spheres(
    urdf_path: str | os.PathLike[str] | Robot,
    *,
    links: Sequence[str] | None = None,
    per_link: int | Mapping[str, int] | None = None,
    count: int | None = None,
    density: float | None = None,
    seed: int = 0,
    package_paths: PackagePaths | None = None,
    max_protrusion: float | Mapping[str, float] | None = None,
    progress: Any = None,
    source: GeometryChoice = "auto",
    target_coverage: float = AUTO_COVERAGE_TARGET,
    clips: Mapping[str, Sequence[Plane]] | None = None,
    method: str = "ours",
    visual_check: VisualCheck = "fast",
    reading: Any = None,
) -> tuple[dict[str, tuple[Sphere, ...]], list[Diagnostic]]:
    """Fit spheres to every link with geometry (or to ``links``) of a URDF or xacro file.

    How many spheres per link, at most one of:

    * ``per_link`` -- that many for each link (or ``{link: n}``; links not in it get none);
    * ``count`` -- that many in total (at least one per link), handed out one by one to the
      link whose covered volume grows most;
    * ``density`` -- ``ceil(density * volume in litres)`` per link (1 to 64);
    * none -- per link, the fewest spheres (up to 16) that cover ``target_coverage`` of its
      volume (default 0.9) within the protrusion bound.

    A placeholder smaller than 2 cm across gets one sphere. ``max_protrusion`` (metres, one
    value or per link) bounds how far each sphere may reach outside its link; by default 6 %
    of the cube root of the link's volume. With a count given, a link without a bound of its
    own gets the greedy spheres refined on coverage and on the 95th percentile of their
    protrusion instead (:mod:`xrdf_tools.spheres.refine`). ``clips`` (``{link: [((nx, ny,
    nz), d), ...]}``, unit normals, link frame) keeps each sphere of that link on the side the
    normal points to: ``n . centre - radius >= d``. ``source`` chooses the geometry as in
    :func:`~xrdf_tools.spheres.geometry.load_link_geometry`. The same inputs and ``seed`` give
    the same spheres; links with identical geometry are fitted once and get the same spheres.
    ``progress(link, i, n)`` is called before each of the ``n`` steps, two per link
    (prepared, then fitted), after ``reading(link, i, n)`` before each link's geometry is
    read. ``method="morphit"`` fits each
    link's solid with MorphIt (the optional ``morphit-rs``; :mod:`xrdf_tools.spheres.morphit`)
    at the same counts and bounds instead of our fitter. ``visual_check`` says how each link
    fitted from collision geometry is compared with its visual geometry
    (:mod:`xrdf_tools.spheres.visual_agreement`). ``urdf_path`` may be a loaded
    :class:`~xrdf_tools.robot.core.Robot`. Returns ``({link: spheres}, diagnostics)`` in URDF
    link order; :func:`~xrdf_tools.spheres.robot_fit.fit_robot` also gives times and solids.
    """
    from .count_policy import CountPolicy
    from .robot_fit import fit_robot

    result = fit_robot(
        urdf_path,
        links=links,
        counts=CountPolicy(per_link, count, density, target_coverage),
        seed=seed,
        package_paths=package_paths,
        max_protrusion=max_protrusion,
        clips=clips,
        progress=progress,
        source=source,
        method=method,
        visual_check=visual_check,
        reading=reading,
    )
    return result.spheres, result.diagnostics


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
            f"not measured (no geometry): {name_list(self.unmeasured)}" if self.unmeasured else ""
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
    """Per-link metrics for ``geoms`` and the pooled overall metrics; ``solid`` says what each
    link was measured against (``LinkGeometry.kind``), ``sheet_thickness`` whether it is a
    sheet (:mod:`.sheet`, under the default protrusion bound)."""
    from .fit import default_max_protrusion
    from .metrics import measure, pooled
    from .sheet import as_sheet

    per: dict[str, SphereMetrics] = {}
    pools = []
    for name, g in geoms.items():
        m, pool = measure(
            g.solid, spheres.get(name, ()), samples=samples, seed=link_seed(seed, name)
        )
        m = replace(m, solid=g.kind) if m.solid == "mesh" else m
        sheet = as_sheet(g.solid, default_max_protrusion(g.solid))
        per[name] = m if sheet is None else replace(m, sheet_thickness=sheet.thickness)
        pools.append(pool)
    return per, pooled(list(per.values()), pools)


def coverage_for_xrdf(
    urdf_path: str | os.PathLike[str] | Robot,
    xrdf: Xrdf,
    *,
    package_paths: PackagePaths | None = None,
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
    package_paths: PackagePaths | None = None,
    urdf: Any = None,
) -> tuple[Xrdf, list[Diagnostic]]:
    """Add each pair of *adjacent* sphere frames to the self-collision ignore mask.

    Two frames with spheres are adjacent when the tree path between them crosses only frames
    without spheres (such as fixed flange frames, or a bare palm between two fingers) and at
    most two joints that move (:mod:`xrdf_tools.robot.adjacency`). This is MoveIt's "adjacent
    links" rule: their spheres overlap at the joint by construction.
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
    edges = edges_of_joints(joints_of(urdf).values())
    ignore = {k: list(v) for k, v in xrdf.self_collision.ignore.items()}
    added = 0
    for key, frame in _adjacent_in_order(edges, [f for f in spheres if f in with_spheres]):
        if xrdf.self_collision.is_ignored(key, frame):
            continue
        ignore.setdefault(key, []).append(frame)
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


def _adjacent_in_order(edges: Edges, frames: list[str]) -> list[tuple[str, str]]:
    """The adjacent pairs of ``frames`` as (ignore key, listed frame): a frame under its
    adjacent ancestor, the later of two frames on separate branches under the earlier; in
    the order of ``frames``."""
    order = {f: i for i, f in enumerate(frames)}
    partners: dict[str, list[str]] = {f: [] for f in frames}
    for a, b in (sorted(p, key=order.__getitem__) for p in adjacent_pairs(edges, frames)):
        partners[a].append(b)
        partners[b].append(a)
    up = {f: _ancestors(edges, f) for f in frames}
    out: list[tuple[str, str]] = []
    for frame in frames:
        for other in sorted(partners[frame], key=order.__getitem__):
            below = other in up[frame]
            if below or (frame not in up[other] and order[other] < order[frame]):
                out.append((other, frame))
    return out


def _ancestors(edges: Edges, frame: str) -> set[str]:
    """The frames above ``frame`` in the tree ``edges``."""
    out: set[str] = set()
    while frame in edges and edges[frame][0] not in out:
        frame = edges[frame][0]
        out.add(frame)
    return out
