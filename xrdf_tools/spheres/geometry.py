"""Link geometry of a URDF as closed solids in each link's frame, ready for sphere fitting.

For every link the ``<collision>`` elements are used; a link without any falls back to its
``<visual>`` elements (reported as ``spheres-visual-fallback``). Supported geometry: meshes that
trimesh reads (STL, OBJ, DAE, PLY, ...; ``scale`` honoured; ``package://``, ``file://`` and
relative URIs resolved with :class:`~xrdf_tools.packages.PackageResolver`) and the primitives
``box``, ``cylinder``, ``sphere`` and ``capsule`` (radius, length along z like the cylinder).

A part that does not enclose a volume (open, non-manifold) is replaced by its convex hull and a
``spheres-convex-hull`` warning says so. Several parts of one link are merged into one solid by
a boolean union (manifold3d); if that fails, the convex hull of all parts is used, again with
a warning. Meshes are read with trimesh; nothing here touches ROS.
"""

from __future__ import annotations

import os
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from ..diagnostics import Diagnostic, Severity
from ..errors import UrdfError, XrdfToolsError
from ..fileio import check_input_file, mesh_bytes_limit
from ..robot import Robot
from ..rotations import matrix_from_rpy

if TYPE_CHECKING:
    import trimesh

GeometrySource = Literal["collision", "visual"]
#: Which elements a solid is made of: only collision, only visual, or collision with visual as
#: the fallback for links without collision elements.
GeometryChoice = Literal["collision", "visual", "auto"]
SolidKind = Literal["mesh", "union", "convex_hull"]

RULE_VISUAL_FALLBACK = "spheres-visual-fallback"
RULE_CONVEX_HULL = "spheres-convex-hull"
RULE_MESH_UNREADABLE = "spheres-mesh-unreadable"
RULE_UNSUPPORTED = "spheres-unsupported-geometry"
RULE_NO_GEOMETRY = "spheres-no-geometry"

# Cylinders, capsules and spheres are tessellated finely enough that the facet error stays far
# below the sampling noise of the metrics (< 0.2 % of the radius).
_CYLINDER_SECTIONS = 96
_SPHERE_SUBDIVISIONS = 4


@dataclass(frozen=True)
class LinkGeometry:
    """The solid of one link, in the link frame.

    ``solid`` is a watertight ``trimesh.Trimesh``; ``kind`` says how it was made (the mesh
    itself, a boolean union of several parts, or a convex hull); ``source`` whether it came from
    collision or visual elements; ``parts`` is the number of URDF geometry elements used.
    """

    link: str
    solid: trimesh.Trimesh
    kind: SolidKind
    source: GeometrySource
    parts: int
    line: int | None = None


@dataclass(frozen=True)
class UrdfText:
    """A URDF as text (xacro already expanded), with the path used in messages."""

    path: str
    text: str


def read_urdf_text(
    path: str | os.PathLike[str], package_paths: Mapping[str, str] | None = None
) -> UrdfText:
    """Text of a URDF; a xacro file is expanded (``$(find pkg)`` via ``package_paths``)."""
    from ..sources.xacro_source import expand_xacro, is_xacro
    from ..urdf_source import read_urdf_bytes

    p = os.fspath(path)
    if Path(p).is_file() and is_xacro(p):
        return UrdfText(p, expand_xacro(p, None, package_paths))
    return UrdfText(p, read_urdf_bytes(p).decode("utf-8", errors="replace"))


def _floats(text: str | None, n: int, default: Sequence[float]) -> list[float]:
    if text is None:
        return list(default)
    vals = [float(v) for v in text.split()]
    if len(vals) == 1 and n == 3:
        vals = vals * 3
    if len(vals) != n:
        raise ValueError(f"expected {n} numbers, got '{text}'")
    return vals


def _origin_matrix(elem: Any) -> np.ndarray[Any, np.dtype[np.float64]]:
    origin = elem.find("origin")
    m = np.eye(4)
    if origin is None:
        return m
    x, y, z = _floats(origin.get("xyz"), 3, (0.0, 0.0, 0.0))
    r, p, w = _floats(origin.get("rpy"), 3, (0.0, 0.0, 0.0))
    m[:3, :3] = matrix_from_rpy(r, p, w)
    m[:3, 3] = (x, y, z)
    return m


def _capsule(radius: float, length: float) -> trimesh.Trimesh:
    import trimesh

    return trimesh.creation.capsule(height=length, radius=radius, count=[48, 48])


def _load_mesh_file(path: Path) -> trimesh.Trimesh:
    import trimesh

    loaded = trimesh.load(str(path), force="mesh", process=True)
    if not isinstance(loaded, trimesh.Trimesh) or len(loaded.faces) == 0:
        raise ValueError("no triangles in the file")
    return loaded


def _geometry_part(
    geom: Any, resolver: Any, urdf_dir: Path
) -> tuple[trimesh.Trimesh | None, str | None]:
    """A mesh for one ``<geometry>`` element, or ``(None, reason)``."""
    import trimesh

    for child in geom:
        tag = child.tag if isinstance(child.tag, str) else ""
        if tag == "box":
            size = _floats(child.get("size"), 3, (0.0, 0.0, 0.0))
            return trimesh.creation.box(extents=size), None
        if tag == "cylinder":
            r, length = float(child.get("radius", "0")), float(child.get("length", "0"))
            return trimesh.creation.cylinder(
                radius=r, height=length, sections=_CYLINDER_SECTIONS
            ), None
        if tag == "sphere":
            r = float(child.get("radius", "0"))
            return trimesh.creation.icosphere(subdivisions=_SPHERE_SUBDIVISIONS, radius=r), None
        if tag == "capsule":
            r, length = float(child.get("radius", "0")), float(child.get("length", "0"))
            return _capsule(r, length), None
        if tag == "mesh":
            uri = child.get("filename") or ""
            if not uri:
                return None, "<mesh> without a filename"
            try:
                path = resolver.resolve_uri(uri, urdf_dir)
            except XrdfToolsError as e:
                return None, f"{uri}: {e.message}"
            if not path.is_file():
                return None, f"{uri}: mesh file not found ({path})"
            try:
                check_input_file(path, what="mesh file", max_bytes=mesh_bytes_limit())
                mesh = _load_mesh_file(path)
            except XrdfToolsError as e:
                return None, f"{uri}: {e.message}"
            except Exception as e:  # trimesh raises many exception types for bad files
                detail = str(e).splitlines()[0] if str(e) else type(e).__name__
                return None, f"{uri}: cannot read mesh ({detail})"
            scale = _floats(child.get("scale"), 3, (1.0, 1.0, 1.0))
            if scale != [1.0, 1.0, 1.0]:
                mesh = mesh.copy()
                mesh.apply_transform(np.diag([*scale, 1.0]))
            return mesh, None
        if tag:
            return None, f"unsupported geometry <{tag}>"
    return None, "empty <geometry>"


def is_volume(mesh: trimesh.Trimesh) -> bool:
    """True when ``mesh`` encloses a positive volume (watertight, consistently wound)."""
    try:
        return bool(mesh.is_volume) and float(mesh.volume) > 0.0
    except Exception:  # trimesh's volume checks raise assorted errors on degenerate meshes
        return False


def _solidify(
    link: str,
    parts: list[trimesh.Trimesh],
    path: str,
    line: int | None,
    diags: list[Diagnostic],
) -> tuple[trimesh.Trimesh, SolidKind] | None:
    import trimesh

    closed: list[trimesh.Trimesh] = []
    hulled = 0
    for part in parts:
        if is_volume(part):
            closed.append(part)
            continue
        try:
            hull = part.convex_hull
        except Exception:  # qhull fails on flat or degenerate parts: they enclose nothing
            continue
        if is_volume(hull):
            closed.append(hull)
            hulled += 1
    if not closed:
        diags.append(
            Diagnostic(
                path,
                line,
                None,
                RULE_MESH_UNREADABLE,
                Severity.WARNING,
                f"link '{link}': its geometry encloses no volume (even as a convex hull); "
                "no spheres fitted",
            )
        )
        return None
    if hulled:
        diags.append(
            Diagnostic(
                path,
                line,
                None,
                RULE_CONVEX_HULL,
                Severity.WARNING,
                f"link '{link}': {hulled} of {len(parts)} mesh(es) not watertight; spheres "
                "fitted to the convex hull of those",
            )
        )
    if len(closed) == 1:
        return closed[0], ("convex_hull" if hulled else "mesh")
    try:
        union = trimesh.boolean.union(closed, engine="manifold")
        if is_volume(union):
            return union, "union"
    except Exception:  # the boolean engine may be missing or fail: fall back to the hull below
        pass
    combined: Any = trimesh.util.concatenate(closed)
    hull = combined.convex_hull
    diags.append(
        Diagnostic(
            path,
            line,
            None,
            RULE_CONVEX_HULL,
            Severity.WARNING,
            f"link '{link}': the union of its {len(closed)} parts failed; spheres fitted to "
            "their convex hull",
        )
    )
    return hull, "convex_hull"


_WHAT = {"auto": "collision or visual", "collision": "collision", "visual": "visual"}


def _elements(elem: Any, choice: GeometryChoice) -> tuple[GeometrySource, list[Any]]:
    """The geometry elements of one ``<link>`` for ``choice``, and which kind they are."""
    if choice == "visual":
        return "visual", list(elem.findall("visual"))
    elements = list(elem.findall("collision"))
    if elements or choice == "collision":
        return "collision", elements
    return "visual", list(elem.findall("visual"))


def load_link_geometry(
    urdf_path: str | os.PathLike[str] | Robot,
    *,
    links: Sequence[str] | None = None,
    package_paths: Mapping[str, str] | None = None,
    source: GeometryChoice = "auto",
    urdf_text: str | None = None,
) -> tuple[dict[str, LinkGeometry], list[Diagnostic]]:
    """Solids of the URDF's links (all links with geometry, or only ``links``).

    ``source``: ``collision`` uses only ``<collision>`` elements (a link without them gets no
    solid), ``visual`` only ``<visual>`` elements, ``auto`` collision with visual as the
    fallback (reported). ``urdf_text`` is the URDF already read (an expanded xacro, with its
    ``--xacro-arg``); ``urdf_path`` then only locates relative meshes and names messages.
    ``urdf_path`` may be a loaded :class:`~xrdf_tools.robot.Robot`: its path, text and
    ``package_paths`` are used (unless given).

    Returns ``({link: LinkGeometry}, diagnostics)`` in URDF link order. Raises
    :class:`UrdfError` for an unreadable URDF or a requested link that does not exist.
    Missing or unreadable meshes are diagnostics (the link is skipped), not exceptions.
    """
    from lxml import etree

    from ..packages import PackageResolver
    from ..urdf_source import parse_urdf_string

    checked_already = False
    if isinstance(urdf_path, Robot):
        robot = urdf_path
        checked_already = urdf_text is None and robot.text is not None
        package_paths = robot.package_paths if package_paths is None else package_paths
        urdf_text = robot.text if urdf_text is None else urdf_text
        urdf_path = robot.path
    if urdf_text is not None:
        src = UrdfText(os.fspath(urdf_path), urdf_text)
    else:
        src = read_urdf_text(urdf_path, package_paths)
    # validate (errors with lines); yourdfpy knows no <capsule>, which reads like a cylinder
    checked = re.sub(r"<capsule\b", "<cylinder", src.text)
    if not (checked_already and checked == src.text):  # a loaded Robot's text was checked
        parse_urdf_string(checked, src.path, package_paths=package_paths)
    parser = etree.XMLParser(resolve_entities=False, no_network=True, huge_tree=True)
    root = etree.fromstring(src.text.encode("utf-8"), parser)
    link_elems = {e.get("name"): e for e in root.iter("link") if e.get("name")}
    if links is not None:
        from ..errors import did_you_mean

        for name in links:
            if name not in link_elems:
                raise UrdfError(
                    f"no link '{name}' in the URDF{did_you_mean(name, link_elems)}",
                    path=src.path,
                )
    wanted = list(link_elems) if links is None else list(dict.fromkeys(links))
    resolver = PackageResolver(Path(src.path), dict(package_paths or {}))
    urdf_dir = Path(src.path).resolve().parent
    out: dict[str, LinkGeometry] = {}
    diags: list[Diagnostic] = []
    source_choice = source
    for name in wanted:
        elem = link_elems[name]
        line = elem.sourceline
        source, elements = _elements(elem, source_choice)
        if not elements:
            if links is not None:
                diags.append(
                    Diagnostic(
                        src.path,
                        line,
                        None,
                        RULE_NO_GEOMETRY,
                        Severity.WARNING,
                        f"link '{name}' has no {_WHAT[source_choice]} geometry; no spheres fitted",
                    )
                )
            continue
        parts: list[trimesh.Trimesh] = []
        for e in elements:
            geom = e.find("geometry")
            if geom is None:
                continue
            try:
                mesh, why = _geometry_part(geom, resolver, urdf_dir)
                transform = _origin_matrix(e)
            except ValueError as err:
                mesh, why = None, str(err)
            if mesh is None:
                rule = RULE_UNSUPPORTED if why and "unsupported" in why else RULE_MESH_UNREADABLE
                diags.append(
                    Diagnostic(
                        src.path,
                        e.sourceline,
                        None,
                        rule,
                        Severity.WARNING,
                        f"link '{name}' {source}: {why}; this part is ignored",
                    )
                )
                continue
            mesh = mesh.copy()
            mesh.apply_transform(transform)
            parts.append(mesh)
        if not parts:
            continue
        if source == "visual" and source_choice == "auto":
            diags.append(
                Diagnostic(
                    src.path,
                    line,
                    None,
                    RULE_VISUAL_FALLBACK,
                    Severity.WARNING,
                    f"link '{name}' has no collision geometry; spheres fitted to its visual "
                    "geometry",
                )
            )
        solid = _solidify(name, parts, src.path, line, diags)
        if solid is None:
            continue
        out[name] = LinkGeometry(name, solid[0], solid[1], source, len(parts), line)
    return out, diags
