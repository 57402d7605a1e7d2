"""With ``--urdf``: a collision sphere lies far outside its link's collision geometry.

A sphere stands in for part of its link, so it should touch the link's collision geometry. A
sphere far away from it is usually written in the wrong frame, has a sign or unit error in its
``center``, or was left over from another robot; the planner then avoids empty space and does
not see the link itself.

Every sphere of every group a collision section uses (``collision``/``world_collision`` and
``self_collision``, clones resolved) is checked when its frame is a URDF link with
``<collision>`` elements. The link's collision geometry (meshes with ``scale``, boxes,
cylinders, spheres, capsules, each with its ``<origin>``; ``package://`` URIs found by
searching the URDF's directory and its ancestors) is loaded once per link and reduced to its
axis-aligned bounding box in the link frame. The sphere is reported when

    gap = distance(center, box) - radius  >  max(20 mm, 0.25 x the box's largest extent)

where ``distance(center, box)`` is the distance from the sphere's center to the nearest point
of the box (0 inside it), i.e. when the sphere does not even come near the box: spheres that
overlap the box, poke out of it, or leave a gap of up to a quarter of the link's size (at
least 20 mm) pass. The box is a generous envelope, so the rule finds misplaced spheres, not
loose fits (the hand-tuned Franka spheres all overlap their boxes). The message names the link,
the sphere index and group, and the gap in mm, and points at the sphere's ``center``.

Spheres whose ``center`` is not 3 finite numbers or whose ``radius`` is not positive are left
to ``sphere-center`` and ``sphere-radius``; frames that are not links (``add_frame`` frames) or
links without collision geometry are not checked.

When a link's collision geometry cannot be loaded in full, that link's spheres are skipped and
one finding per file and cause lists the skipped links with the first reason, so a clean
result is never mistaken for a check that did not run: a **warning** when a mesh file was
found but cannot be read (truncated, not a mesh, no triangles), a **warning** when a mesh file
cannot be found (pass ``--package-path NAME=DIR``), or an **info** for those with
``--allow-missing-meshes`` (the meshes are knowingly not at hand), and an info when the
geometry cannot be loaded at all (trimesh not installed). (A level configured for this rule
also applies to these findings.)
"""

from __future__ import annotations

import math
import os
import threading
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

from ...diagnostics import Severity
from ...util.errors import MissingDependencyError
from ...util.text import name_list
from ...yaml.io import YSeq
from ..context import LintContext, Problem, Rule, SphereRef, length_number

if TYPE_CHECKING:
    from ...robot.core import Robot
    from ...robot.link_geometry import LinkParts

RULE_ID = "sphere-outside-geometry"

#: A sphere may leave this much room to its link's box (metres) before it is reported ...
MIN_GAP = 0.02
#: ... or this fraction of the box's largest extent, whichever is larger.
RELATIVE_GAP = 0.25


@dataclass(frozen=True)
class Box:
    """Axis-aligned bounds of a link's collision geometry in the link frame (metres)."""

    lo: tuple[float, float, float]
    hi: tuple[float, float, float]

    @property
    def largest_extent(self) -> float:
        return max(h - lo for lo, h in zip(self.lo, self.hi, strict=True))

    def distance(self, p: Sequence[float]) -> float:
        """Euclidean distance from ``p`` to the box (0 inside)."""
        return math.sqrt(
            sum(max(lo - x, 0.0, x - h) ** 2 for x, lo, h in zip(p, self.lo, self.hi, strict=True))
        )

    @property
    def threshold(self) -> float:
        return max(MIN_GAP, RELATIVE_GAP * self.largest_extent)


@dataclass(frozen=True)
class Skipped:
    """Why a link's geometry could not be loaded, and whether a mesh file was not found
    (``missing``), found but unreadable (``unreadable``), or neither (no loader at all)."""

    reason: str
    missing: bool = False
    unreadable: bool = False


#: Per URDF file (path, mtime, size): link -> its box, or why its geometry could not be loaded.
_CACHE: dict[tuple[str, int, int, int], dict[str, Box | Skipped]] = {}
_CACHE_SIZE = 8
_CACHE_LOCK = threading.Lock()


def _cache_for(robot: Robot) -> dict[str, Box | Skipped]:
    path, text = robot.path, robot.text
    try:
        st = os.stat(path)
        key = (os.path.realpath(path), st.st_mtime_ns, st.st_size, hash(text))
    except OSError:
        key = (os.path.realpath(path), -1, -1, hash(text))
    with _CACHE_LOCK:  # lint may run in several threads at once
        boxes = _CACHE.get(key)
        if boxes is None:
            while len(_CACHE) >= _CACHE_SIZE:
                del _CACHE[next(iter(_CACHE))]
            boxes = _CACHE[key] = {}
    return boxes


def _first_line(text: str, limit: int = 160) -> str:
    line = text.strip().splitlines()[0] if text.strip() else text
    return line if len(line) <= limit else line[: limit - 3] + "..."


def _reason(link: str, messages: list[str]) -> str:
    """Why ``link`` was not loaded, from the geometry loader's messages about it."""
    prefix = f"link '{link}' collision: "
    for m in messages:
        if m.startswith(prefix):
            return _first_line(m[len(prefix) :].removesuffix("; this part is ignored"))
        if m.startswith(f"link '{link}'"):
            return _first_line(m)
    return f"link '{link}': collision geometry not loaded"


def _load_boxes(robot: Robot, expected: dict[str, int]) -> dict[str, Box | Skipped]:
    """Boxes of the links in ``expected`` (link -> number of its ``<collision>`` elements).

    The geometry is read once from the loaded robot (an expanded xacro keeps its arguments)
    with its package paths, and not parsed as a URDF again. A link whose geometry
    is not loaded in full gets the reason instead; nothing raises.
    """
    try:
        from ...robot.link_geometry import link_geometry, missing_meshes
        from ...spheres.geometry import link_solids

        gone = {f.link for f in missing_meshes(robot, "collision", links=list(expected))}
        loaded = link_geometry(robot, "auto", links=list(expected))
        made = "link_solids" in robot.derived  # the fitter made the solids: their bounds
        boxes = {} if made else _closed_part_boxes(loaded, expected)
        rest = {name: parts for name, parts in loaded.items() if name not in boxes}
        geoms, diags = link_solids(robot, rest)
    except MissingDependencyError as exc:  # one line ending in how to install: kept whole
        return dict.fromkeys(expected, Skipped(str(exc)))
    except Exception as exc:  # an unreadable URDF, a failing loader: skip, do not crash
        why = _first_line(str(exc) or type(exc).__name__)
        return dict.fromkeys(expected, Skipped(why))
    out: dict[str, Box | Skipped] = {}
    for link, count in expected.items():
        if link in boxes:
            out[link] = boxes[link]
            continue
        g = geoms.get(link)
        if g is None or g.source != "collision" or g.parts < count:
            why = _reason(link, [d.message for d in diags])
            out[link] = Skipped(why, missing=link in gone, unreadable=link not in gone)
            continue
        try:
            b = [[float(v) for v in row] for row in g.solid.bounds]
        except Exception as exc:  # trimesh computes bounds lazily; degenerate meshes raise
            out[link] = Skipped(f"link '{link}': no bounds ({type(exc).__name__})", unreadable=True)
            continue
        if not all(math.isfinite(v) for row in b for v in row):
            out[link] = Skipped(
                f"link '{link}': collision geometry has no finite bounds", unreadable=True
            )
            continue
        out[link] = Box((b[0][0], b[0][1], b[0][2]), (b[1][0], b[1][1], b[1][2]))
    return out


def _closed_part_boxes(loaded: Mapping[str, LinkParts], expected: dict[str, int]) -> dict[str, Box]:
    """Boxes of the links in ``expected`` whose collision parts all load and each enclose a
    volume. The solid the sphere fitter makes of such parts (each part, its convex hull when
    it is a thin shell, or the union of the parts and of overlapping bodies) has the bounds of
    the parts themselves, so they are taken without making it: the hulls and the union of a
    mesh of a million triangles take seconds and gigabytes. Other links are left to the
    fitter's solids (which say why a link cannot be loaded)."""
    import numpy as np

    from ...spheres.mesh_solids import is_volume

    out: dict[str, Box] = {}
    for name, link in loaded.items():
        if link.source != "collision" or link.failures or len(link.parts) < expected[name]:
            continue
        parts = [part.in_link_frame() for part in link.parts]
        if not parts or not all(is_volume(part) for part in parts):
            continue
        lo = np.min([part.bounds[0] for part in parts], axis=0)
        hi = np.max([part.bounds[1] for part in parts], axis=0)
        if np.all(np.isfinite(lo)) and np.all(np.isfinite(hi)):
            out[name] = Box(
                (float(lo[0]), float(lo[1]), float(lo[2])),
                (float(hi[0]), float(hi[1]), float(hi[2])),
            )
    return out


def _used_spheres(ctx: LintContext) -> list[SphereRef]:
    """Spheres of every group a collision section uses (clones resolved), each once."""
    seen: set[tuple[str, str, int]] = set()
    out: list[SphereRef] = []
    for _, section in ctx.collision_sections():
        g = ctx.group_name(section)
        if g is None or g not in ctx.groups:
            continue
        spheres = ctx.resolved_spheres(g)
        if spheres is None:  # broken clones (other rules say so): the group's own spheres
            spheres = list(ctx.iter_spheres(g))
        for s in spheres:
            k = (s.group, s.frame, s.index)
            if k not in seen:
                seen.add(k)
                out.append(s)
    return out


def _center(s: SphereRef) -> tuple[float, float, float] | None:
    c = s.field("center")
    if not isinstance(c, YSeq) or len(c) != 3:
        return None
    xyz = [length_number(v) for v in c.items]
    if any(v is None for v in xyz):
        return None
    x, y, z = (float(v) for v in xyz if v is not None)
    return x, y, z


def check(ctx: LintContext) -> Iterator[Problem]:
    robot = ctx.robot
    if robot is None:
        return
    todo: list[tuple[SphereRef, tuple[float, float, float], float]] = []
    expected: dict[str, int] = {}
    for s in _used_spheres(ctx):
        collisions = robot.collision_counts.get(s.frame)
        if not collisions:
            continue
        center, radius = _center(s), length_number(s.field("radius"))
        if center is None or radius is None or radius <= 0.0:
            continue
        todo.append((s, center, radius))
        expected[s.frame] = collisions
    if not todo:
        return
    cache = _cache_for(robot)
    missing = {k: v for k, v in expected.items() if k not in cache}
    if missing:
        cache.update(_load_boxes(robot, missing))
    urdf_name = robot.file_name
    skipped: dict[str, SphereRef] = {}
    for s, center, radius in todo:
        box = cache.get(s.frame)
        if not isinstance(box, Box):
            skipped.setdefault(s.frame, s)
            continue
        gap = box.distance(center) - radius
        if gap > box.threshold:
            yield ctx.problem(
                s.field("center"),
                f"sphere {s.index} of link '{s.frame}' (group '{s.group}') is {gap * 1000:.0f} "
                f"mm outside the bounds of the link's collision geometry in {urdf_name} "
                f"(allowed: {box.threshold * 1000:.0f} mm); check its center and frame",
                s.key_path + ".center",
            )
    yield from _skipped(ctx, skipped, cache, urdf_name)


def _skipped(
    ctx: LintContext,
    skipped: dict[str, SphereRef],
    cache: dict[str, Box | Skipped],
    urdf_name: str,
) -> Iterator[Problem]:
    """One finding per cause for the links whose spheres were not checked."""
    causes: dict[tuple[str, str, Severity], dict[str, SphereRef]] = {}
    for frame, ref in skipped.items():
        why = cache.get(frame)
        if not isinstance(why, Skipped):
            continue
        if why.unreadable:
            cause = ("a collision mesh of theirs cannot be read", "", Severity.WARNING)
        elif why.missing and not ctx.allow_missing_meshes:
            cause = (
                "a collision mesh of theirs cannot be found",
                "; pass --package-path NAME=DIR, or --allow-missing-meshes when the meshes are "
                "not at hand",
                Severity.WARNING,
            )
        else:
            cause = ("their collision geometry could not be loaded", "", Severity.INFO)
        causes.setdefault(cause, {})[frame] = ref
    for (what, hint, severity), refs in causes.items():
        first = next(iter(refs.values()))
        why = cache.get(first.frame)
        reason = why.reason if isinstance(why, Skipped) else ""
        names = name_list(refs, 3)
        yield ctx.problem(
            first.frame_key,
            f"spheres of {len(refs)} link(s) not checked: {what} in {urdf_name} ({names}; "
            f"first: {reason}){hint}",
            f"geometry.{first.group}.spheres.{first.frame}",
            severity,
        )


RULE = Rule(RULE_ID, Severity.WARNING, check, __doc__ or "", needs_urdf=True)
