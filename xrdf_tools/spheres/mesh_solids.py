"""One mesh as a closed solid: does it enclose a volume, its convex hull or oriented bounding
box when it does not, a repair of its winding, and its bodies (the shells a CAD export may put
in one file). :mod:`xrdf_tools.spheres.geometry` builds a link's solid from these.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from ..util.arrays import ragged_index
from .bodies import BodyTable, body_table
from .obb import oriented_box

if TYPE_CHECKING:
    import trimesh

__all__ = [
    "MIN_THICKNESS",
    "SHELL_AREA_RATIO",
    "THIN_SHELL_RATIO",
    "THIN_WALL_RATIO",
    "bounding_box",
    "closed_part",
    "closed_parts",
    "connected_bodies",
    "convex_hull",
    "is_thin_shell",
    "is_volume",
    "overlapping_bodies",
    "repaired",
    "wall_thickness",
]

#: A closed solid with less than this share of its convex hull's volume, walls thinner than
#: ``THIN_WALL_RATIO`` of the hull's size and a surface at least ``SHELL_AREA_RATIO`` of its
#: hull's is a thin shell (:func:`is_thin_shell`).
THIN_SHELL_RATIO = 0.4
THIN_WALL_RATIO = 0.08
SHELL_AREA_RATIO = 0.25
#: The thinnest bounding box a flat part becomes (metres).
MIN_THICKNESS = 0.002


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
    apart: the surface is cut open along every seam); then also its zero-area and repeated
    faces dropped (a CAD export's slivers, each leaving an edge shared by four faces; a
    double-sided export's second copy of each face, in either winding: the first is kept).
    Either is turned
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
        mesh.update_faces(mesh.unique_faces())
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


def wall_thickness(mesh: trimesh.Trimesh) -> float:
    """The mean wall thickness of a closed mesh, 2 · volume / area: ``w`` for a plate of
    thickness ``w`` (each side is half the area), two thirds of the radius for a ball."""
    area = float(mesh.area)
    return 2.0 * float(mesh.volume) / area if area > 0 else 0.0


def is_thin_shell(part: trimesh.Trimesh, hull: trimesh.Trimesh) -> bool:
    """A closed part that is a thin shell: less than ``THIN_SHELL_RATIO`` of its hull's volume,
    walls thinner than ``THIN_WALL_RATIO`` of its hull's size (the cube root of its volume)
    *and* a surface that wraps its hull (at least ``SHELL_AREA_RATIO`` of the hull's area). A
    moulded cover (TIAGo's base: walls 2 % of its size, 1.6 times its hull's area) is one; a
    fork or clevis (a wrist link whose prongs hold the next joint: walls 10-15 %) is a concave
    solid, and its hull would fill the slot where the next link turns; a coiled cable or a
    frame of thin tubes (1-13 % of its hull's area) is a solid wire, and its hull would fill the
    free space inside the coil or between the tubes."""
    return _thin_walled(part, hull) and float(part.area) >= SHELL_AREA_RATIO * float(hull.area)


def _thin_walled(part: trimesh.Trimesh, hull: trimesh.Trimesh) -> bool:
    """Less than ``THIN_SHELL_RATIO`` of its hull's volume, walls thinner than
    ``THIN_WALL_RATIO`` of the hull's size: a thin shell, or thin bodies far apart, or a
    wire (:func:`is_thin_shell` tells them apart)."""
    hull_volume = float(hull.volume)
    if not float(part.volume) < THIN_SHELL_RATIO * hull_volume:
        return False
    return wall_thickness(part) < THIN_WALL_RATIO * float(np.cbrt(hull_volume))


def closed_part(part: trimesh.Trimesh) -> tuple[trimesh.Trimesh, str] | None:
    """The part as a closed solid: itself, else its hull, else its bounding box."""
    if is_volume(part):
        hull = convex_hull(part)
        if hull is not None and is_thin_shell(part, hull):
            return hull, "thin_shell"
        return part, "mesh"
    hull = convex_hull(part)
    if hull is not None:
        return hull, "convex_hull"
    box = bounding_box(part)
    return (box, "bounding_box") if box is not None else None


def closed_parts(part: trimesh.Trimesh) -> list[tuple[trimesh.Trimesh, trimesh.Trimesh, str]]:
    """``(body, its closed solid, how)`` for one part (:func:`closed_part`, its hull computed
    once), or for each of its bodies when it is thin-walled only as a whole: closed bodies far
    apart in one file (two jaw plates, a robot's masts) have a small share of their common
    hull's volume, and that hull would fill the space between them (the whole is then
    thin-walled beside its hull, its surface not necessarily wrapping it). When even the
    bodies' own hulls fill less than ``THIN_SHELL_RATIO`` of the common hull, each body is
    judged alone; bodies that close up to most of it (the two halves of a cover) stay one
    shell. The bodies are measured at once (:func:`.bodies.body_table`): a hull is built
    only for a body whose box does not settle the answer."""
    if not is_volume(part):
        got = closed_part(part)
        return [] if got is None else [(part, *got)]
    hull = convex_hull(part)
    if hull is None or not _thin_walled(part, hull):
        return [(part, part, "mesh")]
    table = body_table(part)
    if table.count > 1 and _all_volumes(table) and _apart(table, float(hull.volume)):
        return [(b, *_closed_body(b, table, i)) for i, b in enumerate(table.bodies())]
    return [(part, hull, "thin_shell")] if is_thin_shell(part, hull) else [(part, part, "mesh")]


def _all_volumes(table: BodyTable) -> bool:
    """Whether every body of a closed mesh encloses a volume: each edge of a closed mesh has
    its two faces in one body, so each body is closed too, and encloses a volume when its
    signed volume is positive (:func:`is_volume` of each body, without the body)."""
    return bool((table.volume > 0.0).all())


def _apart(table: BodyTable, hull_volume: float) -> bool:
    """Whether the bodies' own hulls fill less than ``THIN_SHELL_RATIO`` of their common
    hull's volume: at once when their boxes (each holding its body's hull) do, else from the
    hulls."""
    bound = THIN_SHELL_RATIO * hull_volume
    if float(table.box_volume.sum()) < bound:
        return True
    hulls = (convex_hull(b) for b in table.bodies())
    return sum(float(h.volume) for h in hulls if h is not None) < bound


def _closed_body(body: trimesh.Trimesh, table: BodyTable, i: int) -> tuple[trimesh.Trimesh, str]:
    """:func:`closed_part` of body ``i`` (closed, of positive volume): the body itself when
    its box settles that it is no thin shell (it fills ``THIN_SHELL_RATIO`` of its box, or
    its walls are ``THIN_WALL_RATIO`` of the box's size: its hull is smaller), else as its
    hull says."""
    box = float(table.box_volume[i])
    volume, area = float(table.volume[i]), float(table.area[i])
    walls = 2.0 * volume / area if area > 0 else 0.0
    if volume >= THIN_SHELL_RATIO * box or walls >= THIN_WALL_RATIO * float(np.cbrt(box)):
        return body, "mesh"
    hull = convex_hull(body)
    return (
        (hull, "thin_shell") if hull is not None and is_thin_shell(body, hull) else (body, "mesh")
    )


def overlapping_bodies(part: trimesh.Trimesh) -> list[trimesh.Trimesh]:
    """The closed bodies of one mesh when some of them overlap (a CAD export of a link as
    intersecting shells in one file), else the mesh itself. A point inside two shells crosses
    an even number of faces, so an inside test of the whole file calls it outside: the bodies
    are unioned instead, like the parts of a link. The bodies' boxes come from
    :func:`.bodies.body_table`: a mesh is made of each body only when some overlap."""
    if not is_volume(part):
        return [part]
    table = body_table(part)
    if table.count < 2 or not _all_volumes(table):
        return [part]
    return table.bodies() if _boxes_overlap(table.lo, table.hi) else [part]


#: Pairs of boxes compared at once (:func:`_boxes_overlap`).
_OVERLAP_PAIRS = 1 << 18


def _boxes_overlap(lo: Any, hi: Any) -> bool:
    """Whether any two of the boxes ``lo[i]..hi[i]`` overlap. In the order of their lower x,
    a box can overlap only the boxes after it that start along x before it ends: those pairs
    are compared, at most ``_OVERLAP_PAIRS`` at a time (10,000 bodies of a screw bag: 3.6 s
    as a block of rows against all boxes at a time, 0.1 s so)."""
    order = np.argsort(lo[:, 0], kind="stable")
    lo, hi = lo[order], hi[order]
    n = len(lo)
    ends = np.searchsorted(lo[:, 0], hi[:, 0], side="left")
    counts = np.maximum(ends - np.arange(n) - 1, 0)
    done = np.cumsum(counts)
    start = 0
    while start < n:
        before = int(done[start - 1]) if start else 0
        stop = max(int(np.searchsorted(done, before + _OVERLAP_PAIRS, side="right")), start + 1)
        group, rank = ragged_index(counts[start:stop])
        i = start + group
        j = i + 1 + rank
        touch = np.ones(len(i), dtype=np.bool_)
        for axis in range(3):  # one axis at a time: no (pairs, 3) temporaries
            touch &= (lo[j, axis] < hi[i, axis]) & (lo[i, axis] < hi[j, axis])
        if touch.any():
            return True
        start = stop
    return False


def connected_bodies(mesh: trimesh.Trimesh) -> list[trimesh.Trimesh]:
    """The bodies of ``mesh`` (faces joined by shared edges) in the order of their first
    faces, each keeping the faces in the mesh's own order (:func:`.bodies.body_table`: the
    same on every machine, where trimesh's ``split`` groups the faces by an unstable sort).
    A mesh of one body is returned as it is: copying it cost 5 s on a CAD mesh of 1.2 M
    triangles, to learn that it is one body."""
    table = body_table(mesh)
    return [mesh] if table.count == 1 else table.bodies()
