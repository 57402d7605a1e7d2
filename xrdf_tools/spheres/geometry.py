"""Link geometry of a URDF as closed solids in each link's frame, ready for sphere fitting.

The parts come from the one loader of link geometry,
:func:`xrdf_tools.robot.link_geometry.link_geometry` (meshes that trimesh reads with ``scale``
honoured, ``box``, ``cylinder``, ``sphere`` and the non-standard ``capsule``, each with its
``<origin>``), read from the loaded robot. For every link the ``<collision>`` elements are used;
a link without any falls back to its ``<visual>`` elements (reported as
``spheres-visual-fallback``).

What is sphere-specific is here: a part that does not enclose a volume (open, non-manifold) is
replaced by its convex hull and a ``spheres-convex-hull`` warning says so. Several parts of one
link are merged into one solid by a boolean union (manifold3d); if that fails, the convex hull
of all parts is used, again with a warning. Nothing here touches ROS.
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Literal

from ..diagnostics import Diagnostic, Severity
from ..robot.core import Robot
from ..robot.link_geometry import GeometryChoice, GeometrySource, LinkParts
from ..util.errors import UrdfError

if TYPE_CHECKING:
    import trimesh

__all__ = ["LinkGeometry", "is_volume", "load_link_geometry"]

SolidKind = Literal["mesh", "union", "convex_hull"]

RULE_VISUAL_FALLBACK = "spheres-visual-fallback"
RULE_CONVEX_HULL = "spheres-convex-hull"
RULE_MESH_UNREADABLE = "spheres-mesh-unreadable"
RULE_UNSUPPORTED = "spheres-unsupported-geometry"
RULE_NO_GEOMETRY = "spheres-no-geometry"


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
    out: dict[str, LinkGeometry] = {}
    diags: list[Diagnostic] = []
    for name, link in loaded.items():
        if not link.elements:
            if links is not None:
                diags.append(
                    _warning(
                        robot.path,
                        link.line,
                        RULE_NO_GEOMETRY,
                        f"link '{name}' has no {_WHAT[source]} geometry; no spheres fitted",
                    )
                )
            continue
        solid = _link_solid(robot.path, link, source, diags)
        if solid is not None:
            out[name] = solid
    return out, diags


def _load(path: str | os.PathLike[str], package_paths: Mapping[str, str] | None) -> Robot:
    from ..robot.xacro_source import load_robot

    return load_robot(path, package_paths=package_paths)


def _warning(path: str, line: int | None, rule: str, message: str) -> Diagnostic:
    return Diagnostic(path, line, None, rule, Severity.WARNING, message)


def _link_solid(
    path: str, link: LinkParts, choice: GeometryChoice, diags: list[Diagnostic]
) -> LinkGeometry | None:
    """The solid of one link's parts (None when nothing encloses a volume), and its warnings."""
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
    solid = _solidify(name, parts, path, link.line, diags)
    if solid is None:
        return None
    return LinkGeometry(name, solid[0], solid[1], link.source, len(parts), link.line)
