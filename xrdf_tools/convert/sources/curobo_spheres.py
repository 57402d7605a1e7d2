"""cuRobo collision spheres: the file a config names, and sphere lists checked into the model.

Shared by the cuRobo (:mod:`.curobo`) and Lula (:mod:`.curobo_lula`) readers.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any, TypeGuard

from ...diagnostics import Severity
from ...util.errors import SourceError
from ...util.fileio import check_input_file, is_file
from ...util.text import name_list
from ...xrdf.model import Sphere
from ...yaml.io import is_finite
from . import Draft, Reporter, known_frame

__all__ = [
    "SLOT_RADIUS",
    "find_spheres_file",
    "is_num",
    "read_slots",
    "read_sphere_map",
    "spheres_of",
]


def is_num(v: Any) -> TypeGuard[float]:
    """A finite number of plain YAML data (booleans are not numbers)."""
    return isinstance(v, (int, float)) and not isinstance(v, bool) and is_finite(v)


def find_spheres_file(value: str, config_path: Path, rep: Reporter, where: str) -> Path:
    """The ``collision_spheres`` file ``value`` beside the config, one level up, or in its
    ``spheres/`` folder (cuRobo's layouts); raises :class:`SourceError` when none exists."""
    base = config_path.parent
    candidates = [base / value, base.parent / value, base / "spheres" / Path(value).name]
    for c in candidates:
        if is_file(c):
            return c
    for c in candidates:
        if os.path.exists(c):  # a directory, FIFO or device: say what it is, not "not found"
            try:
                check_input_file(c, what="cuRobo spheres file", error=SourceError)
            except SourceError as e:
                raise SourceError(
                    f"collision_spheres file '{value}' ({c}) {e.message}",
                    path=rep.path,
                    line=rep.position(where)[0],
                ) from None
    raise SourceError(
        f"collision_spheres file '{value}' not found (looked in "
        f"{', '.join(str(c.parent) for c in candidates)})",
        path=rep.path,
        line=rep.position(where)[0],
    )


def read_sphere_map(
    raw: Mapping[str, Any],
    frames: list[str],
    rep: Reporter,
    prefix: str,
    allowed: set[str] | None,
) -> dict[str, list[Sphere]]:
    """``{link: spheres}`` of a sphere file or inline map, for links of ``frames``; with
    ``allowed`` (``collision_link_names``), spheres on other links are reported and dropped."""
    out: dict[str, list[Sphere]] = {}
    # cuRobo looks spheres up only for collision_link_names, so a sphere file shared between
    # robots (cuRobo's iiwa.yml uses spheres/iiwa_allegro.yml) may name links of another robot:
    # those are neither unknown-link mistakes nor lost spheres; one info note covers them.
    foreign: list[str] = []
    for link, items in raw.items():
        link = str(link)
        w = f"{prefix}.{link}"
        if allowed is not None and link not in allowed and link not in frames:
            foreign.append(link)
            continue
        if not known_frame(link, frames, rep, w, "collision spheres"):
            continue
        if allowed is not None and link not in allowed:
            rep.report(
                "convert-unused-spheres",
                f"spheres on '{link}' are not used by cuRobo ('{link}' is not in "
                "collision_link_names); dropped",
                w,
            )
            continue
        spheres = spheres_of(items, rep, w)
        if spheres:
            out.setdefault(link, []).extend(spheres)
    if foreign:
        shown = name_list(foreign, 5)
        rep.report(
            "convert-unused-spheres",
            f"spheres on {len(foreign)} link(s) that are neither in the URDF nor in "
            f"collision_link_names ({shown}) are ignored: cuRobo never reads them (a sphere "
            "file shared with another robot?)",
            f"{prefix}.{foreign[0]}",
            severity=Severity.INFO,
        )
    return out


def spheres_of(items: Any, rep: Reporter, where: str) -> list[Sphere]:
    """The spheres of one link (null: none); raises :class:`SourceError` for a malformed one."""
    if items is None:
        return []
    if not isinstance(items, list):
        raise SourceError(
            "spheres of a link must be a list", path=rep.path, line=rep.position(where)[0]
        )
    out = []
    for i, s in enumerate(items):
        w = f"{where}[{i}]"
        c = s.get("center") if isinstance(s, Mapping) else None
        r = s.get("radius") if isinstance(s, Mapping) else None
        if not (isinstance(c, list) and len(c) == 3 and all(is_num(v) for v in c) and is_num(r)):
            raise SourceError(
                "a sphere needs center: [x, y, z] and a numeric radius",
                path=rep.path,
                line=rep.position(w)[0],
            )
        out.append(Sphere((float(c[0]), float(c[1]), float(c[2])), float(r)))
    return out


#: Radius cuRobo gives the spheres of ``extra_collision_spheres`` (attached-object slots).
SLOT_RADIUS = -10.0


def read_slots(value: Any, frames: list[str], d: Draft, rep: Reporter, where: str) -> None:
    """``extra_collision_spheres: {link: n}`` → n spheres of radius −10 at the link origin.

    This is how cuRobo builds them and how cuMotion's own ``franka_curobo.xrdf`` (1.0) keeps
    them; XRDF 2.0 cannot express them (the version converter reports that).
    """
    if value is None:
        return
    if not isinstance(value, Mapping):
        raise SourceError(
            "extra_collision_spheres must map links to a number of spheres",
            path=rep.path,
            line=rep.position(where)[0],
        )
    for link, n in value.items():
        w = f"{where}.{link}"
        if not (isinstance(n, int) and not isinstance(n, bool) and n >= 0):
            raise SourceError(
                f"extra_collision_spheres.{link} must be a whole number of spheres, not {n!r}",
                path=rep.path,
                line=rep.position(w)[0],
            )
        if n and known_frame(str(link), frames, rep, w, "extra_collision_spheres link"):
            slots = [Sphere((0.0, 0.0, 0.0), SLOT_RADIUS)] * n
            d.spheres = d.spheres if d.spheres is not None else {}
            d.spheres.setdefault(str(link), []).extend(slots)
