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
hull's, like a moulded base cover -- is fitted as its convex hull (``spheres-thin-shell``):
covering the shell itself needs spheres thinner than the wall, and the hollow inside is not
reachable free space for a planner. Nothing here touches ROS.
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from ..diagnostics import Diagnostic, Severity
from ..robot.core import Robot
from ..robot.link_geometry import GeometryChoice, GeometrySource, LinkParts
from ..util.errors import UrdfError
from ..util.fixed_order import quantized
from ..xrdf.model import Sphere
from .obb import oriented_box

if TYPE_CHECKING:
    import trimesh

__all__ = ["LinkGeometry", "is_volume", "link_solids", "load_link_geometry"]

SolidKind = Literal["mesh", "union", "convex_hull", "bounding_box"]

#: A closed solid with less than this share of its convex hull's volume is a thin shell.
THIN_SHELL_RATIO = 0.4
#: The thinnest bounding box a flat part becomes (metres).
MIN_THICKNESS = 0.002

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


def is_volume(mesh: trimesh.Trimesh) -> bool:
    """True when ``mesh`` encloses a positive volume (watertight, consistently wound). A flat
    closed mesh has a centre of mass of 0/0: trimesh's numpy warning is not printed."""
    try:
        with np.errstate(invalid="ignore", divide="ignore"):
            return bool(mesh.is_volume) and float(mesh.volume) > 0.0
    except Exception:  # trimesh's volume checks raise assorted errors on degenerate meshes
        return False


def convex_hull(mesh: trimesh.Trimesh) -> trimesh.Trimesh | None:
    """The convex hull of ``mesh`` as a closed solid, or None when it is flat or degenerate.

    Built from qhull's triangulated facets turned outward (trimesh's own hull, tried second,
    merges facets into a non-manifold surface on some dense CAD meshes)."""
    import trimesh

    try:
        from scipy.spatial import ConvexHull

        ch = ConvexHull(np.asarray(mesh.vertices, dtype=np.float64), qhull_options="Qt")
        rebuilt = trimesh.Trimesh(mesh.vertices, ch.simplices, process=True)
        rebuilt.remove_unreferenced_vertices()
        _turn_outward(rebuilt)
        if is_volume(rebuilt):
            return rebuilt
    except Exception:  # flat, collinear or too few points: try trimesh's hull below
        pass
    try:
        hull: trimesh.Trimesh = mesh.convex_hull
    except Exception:  # qhull fails on flat or degenerate parts: no hull
        return None
    return hull if is_volume(hull) else None


def _turn_outward(hull: trimesh.Trimesh) -> None:
    """Reverse the faces of a convex hull whose normal points inward (towards the mean of its
    vertices, inside a hull that is not flat): the faces trimesh's ``fix_normals`` gives, 20×
    faster (it walks the faces one by one: 0.2 s for a hull of 5,000)."""
    v = np.asarray(hull.vertices, dtype=np.float64)
    f = np.asarray(hull.faces)
    tri = v[f]
    normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    inward = np.einsum("ij,ij->i", normal, tri.mean(axis=1) - v.mean(axis=0)) < 0.0
    if inward.any():
        faces = f.copy()
        faces[inward] = faces[inward][:, ::-1]
        hull.faces = faces


def bounding_box(mesh: trimesh.Trimesh) -> trimesh.Trimesh | None:
    """The oriented bounding box of ``mesh``, at least ``MIN_THICKNESS`` along each axis."""
    import trimesh

    if len(mesh.vertices) == 0:
        return None
    try:
        to_link, extents = oriented_box(mesh.vertices)
    except Exception:  # a single point or a degenerate set: use the axis-aligned box
        # of the vertices (trimesh's bounds are None when no face uses a vertex: a
        # <cylinder length="0" radius="0"/> placeholder)
        points = np.asarray(mesh.vertices, dtype=np.float64)
        lo, hi = points.min(axis=0), points.max(axis=0)
        to_link, extents = np.eye(4), hi - lo
        to_link[:3, 3] = (lo + hi) / 2.0
    box = trimesh.creation.box(
        extents=np.maximum(np.asarray(extents, dtype=np.float64), MIN_THICKNESS),
        transform=to_link,
    )
    return box if is_volume(box) else None


def repaired(part: trimesh.Trimesh) -> trimesh.Trimesh:
    """``part`` itself when it encloses a volume, else the first of these mended copies that
    does: its vertices merged across texture and normal seams (an OBJ or COLLADA file
    repeats a vertex for each texture coordinate it has, and trimesh keeps those copies
    apart: the surface is cut open along every seam); then also its zero-area faces dropped
    (a CAD export's slivers, each leaving an edge shared by four faces). Either is turned
    outward when all its faces point inward (closed, of negative volume). Else ``part``
    unchanged: nothing else is mended, a mesh open after that is open."""
    if is_volume(part):
        return part
    mesh = part.copy()
    with np.errstate(invalid="ignore", divide="ignore"):
        mesh.merge_vertices(merge_tex=True, merge_norm=True)
        if _outward(mesh):
            return mesh
        mesh.update_faces(mesh.nondegenerate_faces())
        mesh.remove_unreferenced_vertices()
        mesh.merge_vertices(merge_tex=True, merge_norm=True)
        return mesh if _outward(mesh) else part


def _outward(mesh: trimesh.Trimesh) -> bool:
    """Whether ``mesh`` encloses a volume, once turned outward if it is closed and all its
    faces point inward (``mesh`` is inverted in place then)."""
    closed = len(mesh.faces) and mesh.is_watertight and mesh.is_winding_consistent
    if closed and float(mesh.volume) < 0.0:
        mesh.invert()
    return is_volume(mesh)


def _closed_part(part: trimesh.Trimesh) -> tuple[trimesh.Trimesh, str] | None:
    """The part as a closed solid: itself, else its hull, else its bounding box."""
    if is_volume(part):
        hull = convex_hull(part)
        if hull is not None and float(part.volume) < THIN_SHELL_RATIO * float(hull.volume):
            return hull, "thin_shell"
        return part, "mesh"
    hull = convex_hull(part)
    if hull is not None:
        return hull, "convex_hull"
    box = bounding_box(part)
    return (box, "bounding_box") if box is not None else None


def _overlapping_bodies(part: trimesh.Trimesh) -> list[trimesh.Trimesh]:
    """The closed bodies of one mesh when some of them overlap (a CAD export of a link as
    intersecting shells in one file), else the mesh itself. A point inside two shells crosses
    an even number of faces, so an inside test of the whole file calls it outside: the bodies
    are unioned instead, like the parts of a link."""
    if not is_volume(part):
        return [part]
    bodies = connected_bodies(part)
    if len(bodies) < 2 or not all(is_volume(b) for b in bodies):
        return [part]
    lo = np.array([b.bounds[0] for b in bodies])
    hi = np.array([b.bounds[1] for b in bodies])
    touch = np.all(lo[:, None, :] < hi[None, :, :], axis=2) & np.all(
        lo[None, :, :] < hi[:, None, :], axis=2
    )
    np.fill_diagonal(touch, False)
    return list(bodies) if touch.any() else [part]


def connected_bodies(mesh: trimesh.Trimesh) -> list[trimesh.Trimesh]:
    """The bodies of ``mesh`` (faces joined by shared edges) in the order of their first
    faces, each keeping the faces in the mesh's own order (``mesh.split(only_watertight=
    False)``, made machine-independent: trimesh groups the faces by an unstable sort, whose
    ties numpy's SIMD sort (AVX-512) and its portable one break differently, and a fit
    follows the order of the faces)."""
    import trimesh

    found = trimesh.graph.connected_components(
        mesh.face_adjacency, nodes=np.arange(len(mesh.faces)), min_len=1
    )
    bodies = sorted((np.sort(np.asarray(c, dtype=np.intp)) for c in found), key=lambda c: c[0])
    out: Any = mesh.submesh(bodies, only_watertight=False, repair=True)  # a list for a list
    return list(out)


def _solidify(
    link: str,
    parts: list[trimesh.Trimesh],
    path: str,
    line: int | None,
    diags: list[Diagnostic],
) -> tuple[trimesh.Trimesh, SolidKind] | None:
    import trimesh

    bodies = [body for whole in parts for body in _overlapping_bodies(repaired(whole))]
    made: list[tuple[trimesh.Trimesh, trimesh.Trimesh, str]] = []  # (body, its solid, how)
    for body in bodies:
        with np.errstate(invalid="ignore", divide="ignore"):  # trimesh on flat parts
            got = _closed_part(body)
        if got is not None:
            made.append((body, *got))
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
    _report_parts(link, len(bodies), made, path, line, diags)
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
    if len(shares) == 1:
        what = f"a thin shell (its volume is {shares[0]:.0%} of its convex hull's); spheres "
        what += "fitted to the convex hull"
    else:
        what = f"{len(shares)} thin shells (each {min(shares):.0%}–{max(shares):.0%} of its "
        what += "hull's); spheres fitted to the convex hulls"
    diags.append(
        Diagnostic(path, line, None, RULE_THIN_SHELL, Severity.INFO, f"link '{link}': {what}")
    )


_WHAT = {"auto": "collision or visual", "collision": "collision", "visual": "visual"}


def load_link_geometry(
    urdf: str | os.PathLike[str] | Robot,
    *,
    links: Sequence[str] | None = None,
    package_paths: Mapping[str, str] | None = None,
    source: GeometryChoice = "auto",
) -> tuple[dict[str, LinkGeometry], list[Diagnostic]]:
    """Solids of the URDF's links (all links with geometry, or only ``links``).

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
    loaded = link_geometry(robot, source, links=links, package_paths=package_paths)
    return link_solids(
        robot, loaded, source=source, requested=links is not None, package_paths=package_paths
    )


def link_solids(
    robot: Robot,
    loaded: Mapping[str, LinkParts],
    *,
    source: GeometryChoice = "auto",
    requested: bool = True,
    package_paths: Mapping[str, str] | None = None,
) -> tuple[dict[str, LinkGeometry], list[Diagnostic]]:
    """:func:`load_link_geometry` of links already read by
    :func:`~xrdf_tools.robot.link_geometry.link_geometry` (with the same ``source`` and
    ``package_paths``); ``requested``: the links were named (a link without geometry is
    reported)."""
    # a link's solid is made once per loaded robot: convert fits the links, then lints them
    same = package_paths is None or dict(package_paths) == dict(robot.package_paths)
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


def _load(path: str | os.PathLike[str], package_paths: Mapping[str, str] | None) -> Robot:
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
    parts = [part.in_link_frame() for part in link.parts]
    key = (name, link.source)
    if key not in made:
        said: list[Diagnostic] = []
        made[key] = (_on_grid(_solidify(name, parts, path, link.line, said)), said)
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


def _scale_hint(link: LinkParts) -> str:
    """What most likely makes a link too large: a mesh file in millimetres without its scale,
    or (no mesh file among its parts) primitive sizes written in millimetres."""
    if any(part.file for part in link.parts):
        return 'a mesh exported in millimetres needs <mesh scale="0.001 0.001 0.001">'
    return "its <box>/<cylinder>/<sphere> sizes look like millimetres; URDF lengths are metres"


def _sphere_parts(link: LinkParts) -> tuple[Sphere, ...]:
    """The link's ``<sphere>`` elements as spheres in the link frame, when every part read is
    one of positive radius and none failed; else () (a zero-size one is a placeholder)."""
    out = []
    for part in link.parts:
        if part.radius is None or part.radius <= 0.0:
            return ()
        x, y, z = (float(v) for v in part.origin[:3, 3])
        out.append(Sphere(center=(x, y, z), radius=part.radius))
    return () if link.failures else tuple(out)
