"""Link geometry of a URDF as closed solids in each link's frame, ready for sphere fitting.

The parts come from the one loader of link geometry,
:func:`xrdf_tools.robot.link_geometry.link_geometry` (meshes that trimesh reads with ``scale``
honoured, ``box``, ``cylinder``, ``sphere`` and the non-standard ``capsule``, each with its
``<origin>``), read from the loaded robot. For every link the ``<collision>`` elements are used;
a link without any falls back to its ``<visual>`` elements (reported as
``spheres-visual-fallback``).

What is sphere-specific is here: a part that does not enclose a volume (open, non-manifold) is
replaced by its convex hull and a ``spheres-convex-hull`` warning says so; a part whose hull is
flat or degenerate by its oriented bounding box, at least ``MIN_THICKNESS`` thick
(``spheres-bounding-box``). Several parts of one link are merged into one solid by a boolean
union (manifold3d); if that fails, the convex hull of all parts is used, again with a warning.
A thin shell -- a closed solid whose volume is less than ``THIN_SHELL_RATIO`` of its convex
hull's and whose walls are thin beside its size (``THIN_WALL_RATIO``), like a moulded base
cover -- is fitted as its convex hull (``spheres-thin-shell``):
covering the shell itself needs spheres thinner than the wall, and the hollow inside is not
reachable free space for a planner. Nothing here touches ROS.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from ..diagnostics import Diagnostic, Severity
from ..robot.core import Robot
from ..robot.link_geometry import GeometryChoice, GeometryPart, GeometrySource, LinkParts
from ..robot.packages import package_folders
from ..util.errors import UrdfError
from ..util.fixed_order import quantized
from ..xrdf.model import Sphere
from .mesh_solids import (
    closed_parts,
    convex_hull,
    is_volume,
    overlapping_bodies,
    repaired,
    wall_thickness,
)

if TYPE_CHECKING:
    import trimesh

    from ..robot.packages import PackagePaths

__all__ = ["LinkGeometry", "link_solids", "load_link_geometry"]

SolidKind = Literal["mesh", "union", "convex_hull", "bounding_box"]

RULE_VISUAL_FALLBACK = "spheres-visual-fallback"
RULE_CONVEX_HULL = "spheres-convex-hull"
RULE_MESH_UNREADABLE = "spheres-mesh-unreadable"
RULE_UNSUPPORTED = "spheres-unsupported-geometry"
RULE_NO_GEOMETRY = "spheres-no-geometry"
RULE_THIN_SHELL = "spheres-thin-shell"
RULE_BOUNDING_BOX = "spheres-bounding-box"
RULE_MESH_SCALE = "spheres-mesh-scale"
#: A link's solid wider than this (m) is most likely a mesh in millimetres without its scale.
MAX_LINK_SPAN = 10.0


@dataclass(frozen=True)
class LinkGeometry:
    """The solid of one link, in the link frame.

    ``solid`` is a watertight ``trimesh.Trimesh``; ``kind`` says how it was made (the mesh
    itself, a boolean union of several parts, or a convex hull); ``source`` whether it came from
    collision or visual elements; ``parts`` is the number of URDF geometry elements used;
    ``exact`` the spheres the URDF itself gives, when its parts are all spheres.
    """

    link: str
    solid: trimesh.Trimesh
    kind: SolidKind
    source: GeometrySource
    parts: int
    line: int | None = None
    #: The link's own spheres when every part is a ``<sphere>`` (centre, radius), else ().
    exact: tuple[Sphere, ...] = ()


def _solidify(
    link: str,
    parts: list[trimesh.Trimesh],
    path: str,
    line: int | None,
    diags: list[Diagnostic],
) -> tuple[trimesh.Trimesh, SolidKind] | None:
    import trimesh

    bodies = [body for whole in parts for body in overlapping_bodies(repaired(whole))]
    with np.errstate(invalid="ignore", divide="ignore"):  # trimesh on flat parts
        pieces = [closed_parts(body) for body in bodies]  # (body, its solid, how) each
    made = [piece for of_body in pieces for piece in of_body]
    n_bodies = sum(max(len(of_body), 1) for of_body in pieces)  # unreadable ones too
    closed = [solid for _, solid, _ in made]
    how = [kind for _, _, kind in made]
    if not closed:
        diags.append(
            _warning(
                path,
                line,
                RULE_MESH_UNREADABLE,
                f"link '{link}': its geometry has no vertices; no spheres fitted",
            )
        )
        return None
    _report_parts(link, n_bodies, made, path, line, diags)
    if len(closed) == 1:
        return closed[0], _KIND[how[0]]
    try:
        union = trimesh.boolean.union(closed, engine="manifold")
        if is_volume(union):
            return union, "union"
    except Exception:  # the boolean engine may be missing or fail: fall back to the hull below
        pass
    combined: Any = trimesh.util.concatenate(closed)
    hull = convex_hull(combined)
    if hull is None:
        return None
    diags.append(
        _warning(
            path,
            line,
            RULE_CONVEX_HULL,
            f"link '{link}': the union of its {len(closed)} parts failed; spheres fitted to "
            "their convex hull",
        )
    )
    return hull, "convex_hull"


def _on_grid(
    made: tuple[trimesh.Trimesh, SolidKind] | None,
) -> tuple[trimesh.Trimesh, SolidKind] | None:
    """The solid with its vertices rounded to the grid its parts are on: a hull, a box or a
    union computed with a machine's BLAS (trimesh's oriented bounds and transforms) can differ
    from another machine's in the last bits, and the fit would carry that into its spheres."""
    if made is None:
        return None
    solid = made[0].copy()
    solid.vertices = quantized(solid.vertices)
    return solid, made[1]


_KIND: dict[str, SolidKind] = {
    "mesh": "mesh",
    "thin_shell": "convex_hull",
    "convex_hull": "convex_hull",
    "bounding_box": "bounding_box",
}


def _report_parts(
    link: str,
    n: int,
    made: list[tuple[trimesh.Trimesh, trimesh.Trimesh, str]],
    path: str,
    line: int | None,
    diags: list[Diagnostic],
) -> None:
    """One diagnostic per way a part (of ``n``) was replaced; ``made``: each part that got a
    solid, the solid and how it was made."""
    how = [kind for _, _, kind in made]
    for kind, rule, text in (
        ("convex_hull", RULE_CONVEX_HULL, "not watertight; spheres fitted to the convex hull"),
        (
            "bounding_box",
            RULE_BOUNDING_BOX,
            "enclose no volume, even as a convex hull; spheres fitted to the oriented bounding box",
        ),
    ):
        hit = [i for i, h in enumerate(how) if h == kind]
        if hit:
            diags.append(
                _warning(
                    path, line, rule, f"link '{link}': {len(hit)} of {n} mesh(es) {text} of those"
                )
            )
    shares = [
        float(part.volume) / float(solid.volume) for part, solid, h in made if h == "thin_shell"
    ]
    if not shares:
        return
    # of several bodies, say how many are shells: the note is about those, not the whole link
    whole = f"of its {n} bodies, " if n > 1 else ""
    if len(shares) == 1:
        walls = next(wall_thickness(part) for part, _, h in made if h == "thin_shell")
        what = f"{'one' if whole else 'a'} thin shell (its volume is {shares[0]:.0%} of its "
        what += f"convex hull's, its walls about {walls * 1000:.1f} mm thick); spheres fitted to "
        what += "its convex hull"
    else:
        what = f"{len(shares)} thin shells (each {min(shares):.0%}–{max(shares):.0%} of its "
        what += "hull's); spheres fitted to the convex hulls"
    what = whole + what
    diags.append(
        Diagnostic(path, line, None, RULE_THIN_SHELL, Severity.INFO, f"link '{link}': {what}")
    )


_WHAT = {"auto": "collision or visual", "collision": "collision", "visual": "visual"}


def load_link_geometry(
    urdf: str | os.PathLike[str] | Robot,
    *,
    links: Sequence[str] | None = None,
    package_paths: PackagePaths | None = None,
    source: GeometryChoice = "auto",
    progress: Callable[[str, int, int], None] | None = None,
) -> tuple[dict[str, LinkGeometry], list[Diagnostic]]:
    """Solids of the URDF's links (all links with geometry, or only ``links``).
    ``progress(link, i, n)`` is called before each link's geometry is read and made a solid
    (a CAD mesh of millions of triangles takes seconds).

    ``urdf`` is a loaded :class:`~xrdf_tools.robot.core.Robot` (its geometry is read from the
    yourdfpy object, the XML is not parsed again; ``package_paths`` replaces its own when
    given) or the path of a URDF or xacro file, which is loaded first.
    ``source``: ``collision`` uses only ``<collision>`` elements (a link without them gets no
    solid), ``visual`` only ``<visual>`` elements, ``auto`` collision with visual as the
    fallback (reported).

    Returns ``({link: LinkGeometry}, diagnostics)`` in URDF link order. Raises
    :class:`UrdfError` for an unreadable URDF or a requested link that does not exist.
    Missing or unreadable meshes are diagnostics (the part is skipped), not exceptions.
    """
    from ..robot.link_geometry import link_geometry

    robot = urdf if isinstance(urdf, Robot) else _load(urdf, package_paths)
    if links is not None:
        from ..util.errors import did_you_mean

        for name in links:
            if name not in robot.urdf.link_map:
                raise UrdfError(
                    f"no link '{name}' in the URDF{did_you_mean(name, robot.links)}",
                    path=robot.path,
                )
    names = list(dict.fromkeys(links)) if links is not None else list(robot.links)
    out: dict[str, LinkGeometry] = {}
    diags: list[Diagnostic] = []
    for i, name in enumerate(names):
        if progress is not None:
            progress(name, i, len(names))
        loaded = link_geometry(robot, source, links=[name], package_paths=package_paths)
        solids, more = link_solids(
            robot, loaded, source=source, requested=links is not None, package_paths=package_paths
        )
        out.update(solids)
        diags += more
    return out, diags


def link_solids(
    robot: Robot,
    loaded: Mapping[str, LinkParts],
    *,
    source: GeometryChoice = "auto",
    requested: bool = True,
    package_paths: PackagePaths | None = None,
) -> tuple[dict[str, LinkGeometry], list[Diagnostic]]:
    """:func:`load_link_geometry` of links already read by
    :func:`~xrdf_tools.robot.link_geometry.link_geometry` (with the same ``source`` and
    ``package_paths``); ``requested``: the links were named (a link without geometry is
    reported)."""
    # a link's solid is made once per loaded robot: convert fits the links, then lints them
    same = package_paths is None or (
        package_folders(package_paths) == package_folders(robot.package_paths)
    )
    made = robot.derived.setdefault("link_solids", {}) if same else {}
    out: dict[str, LinkGeometry] = {}
    diags: list[Diagnostic] = []
    for name, link in loaded.items():
        if not link.elements:
            if requested:
                diags.append(
                    _warning(
                        robot.path,
                        link.line,
                        RULE_NO_GEOMETRY,
                        f"link '{name}' has no {_WHAT[source]} geometry; no spheres fitted",
                    )
                )
            continue
        solid = _link_solid(robot.path, link, source, diags, made)
        if solid is not None:
            out[name] = solid
    return out, diags


def _load(path: str | os.PathLike[str], package_paths: PackagePaths | None) -> Robot:
    from ..robot.xacro_source import load_robot

    return load_robot(path, package_paths=package_paths)


def _warning(path: str, line: int | None, rule: str, message: str) -> Diagnostic:
    return Diagnostic(path, line, None, rule, Severity.WARNING, message)


def _link_solid(
    path: str,
    link: LinkParts,
    choice: GeometryChoice,
    diags: list[Diagnostic],
    made: dict[tuple[str, str], tuple[tuple[Any, SolidKind] | None, list[Diagnostic]]],
) -> LinkGeometry | None:
    """The solid of one link's parts (None when nothing encloses a volume), and its warnings.
    ``made``: solids already made from the same parts, by link and source."""
    name = link.link
    for failure in link.failures:
        rule = RULE_UNSUPPORTED if failure.unsupported else RULE_MESH_UNREADABLE
        diags.append(
            _warning(
                path,
                link.line,
                rule,
                f"link '{name}' {link.source}: {failure.reason}; this part is ignored",
            )
        )
    if not link.parts:
        return None
    if link.source == "visual" and choice == "auto":
        diags.append(
            _warning(
                path,
                link.line,
                RULE_VISUAL_FALLBACK,
                f"link '{name}' has no collision geometry; spheres fitted to its visual geometry",
            )
        )
    sized = [part for part in link.parts if not _is_point(part)]
    parts = [part.in_link_frame() for part in (sized or link.parts)]
    key = (name, link.source)
    if key not in made:
        said: list[Diagnostic] = []
        made[key] = (_on_grid(_solidify(name, parts, path, link.line, said)), said)
        if not sized:  # points alone: a placeholder, which its own note says
            said[:] = [d for d in said if d.rule != RULE_BOUNDING_BOX]
    solid, said = made[key]
    diags.extend(said)
    if solid is None:
        return None
    span = float(np.max(solid[0].extents))
    if span > MAX_LINK_SPAN:
        diags.append(
            _warning(
                path,
                link.line,
                RULE_MESH_SCALE,
                f"link '{name}' {link.source} geometry spans {span:.4g} m: {_scale_hint(link)} "
                "(spheres fitted as it is)",
            )
        )
    exact = _sphere_parts(link)
    return LinkGeometry(name, solid[0], solid[1], link.source, len(parts), link.line, exact)


def _is_point(part: GeometryPart) -> bool:
    """A primitive of zero size (Drake's ``<sphere radius="0">`` point contacts and frames
    without geometry): it encloses nothing, so a link's other parts are its solid."""
    return part.shape != "mesh" and not np.any(np.ptp(part.mesh.vertices, axis=0))


def _scale_hint(link: LinkParts) -> str:
    """What most likely makes a link too large: a mesh file in millimetres without its scale,
    or (no mesh file among its parts) primitive sizes written in millimetres."""
    if any(part.file for part in link.parts):
        return 'a mesh exported in millimetres needs <mesh scale="0.001 0.001 0.001">'
    return "its <box>/<cylinder>/<sphere> sizes look like millimetres; URDF lengths are metres"


def _sphere_parts(link: LinkParts) -> tuple[Sphere, ...]:
    """The link's ``<sphere>`` elements as spheres in the link frame, when every part read is
    one of positive radius (points beside them left out) and none failed; else () (points
    alone are a placeholder)."""
    out = []
    for part in [part for part in link.parts if not _is_point(part)] or link.parts:
        if part.radius is None or part.radius <= 0.0:
            return ()
        x, y, z = (float(v) for v in part.origin[:3, 3])
        out.append(Sphere(center=(x, y, z), radius=part.radius))
    return () if link.failures else tuple(out)
