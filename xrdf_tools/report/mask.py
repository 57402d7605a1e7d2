"""The recommended ``self_collision.ignore`` mask and how it differs from the current one.

Pairs whose recommendation is not "check" (adjacent, default, always, never; with
``--mask-policy proven`` only proven never-pairs) are ignored; existing entries between
known frames that involve a frame without spheres are kept (the report cannot judge them) and
entries naming unknown frames are dropped. :func:`recommended_xrdf` writes the mask into an
:class:`~xrdf_tools.xrdf.model.Xrdf` (``xrdf report --write-mask``).
"""

from __future__ import annotations

from collections.abc import Sequence

from ..robot.kinematics import KinematicModel
from ..selfcollision.collision import SphereSet
from ..util.errors import XrdfToolsError
from ..util.frozen import FrozenMap
from ..xrdf.model import SelfCollisionSection, Xrdf
from .results import MaskChange, PairStat, Report

__all__ = ["recommended_xrdf"]


def recommend_ignore(
    xrdf: Xrdf, kin: KinematicModel, spheres: SphereSet, stats: Sequence[PairStat]
) -> tuple[FrozenMap[str, tuple[str, ...]], MaskChange]:
    """Ignore map: pairs classified adjacent/default/always/never, plus existing entries
    between known frames that involve a frame without spheres (the report cannot judge
    them); entries naming unknown frames are dropped."""
    sc = xrdf.self_collision
    current = sc.ignore_pairs() if sc is not None else frozenset()
    sphere_frames = set(spheres.frame_names)
    want: set[frozenset[str]] = {
        frozenset((p.frame_a, p.frame_b)) for p in stats if p.recommendation != "check"
    }
    unknown: set[str] = set()
    for pair in current:
        names = tuple(pair)
        if not all(kin.has_frame(n) for n in names):
            unknown.update(n for n in names if not kin.has_frame(n))
            continue
        if not all(n in sphere_frames for n in names):
            want.add(pair)
    if sc is not None:  # self-entries and names in lone keys
        unknown.update(n for a, o in sc.ignore.items() for n in (a, *o) if not kin.has_frame(n))
    order = {f: i for i, f in enumerate(kin.frame_names)}

    def ordered(pair: frozenset[str]) -> tuple[str, str]:
        a, b = sorted(pair, key=lambda f: order[f])
        return a, b

    mapping: dict[str, list[str]] = {}
    for a, b in sorted((ordered(p) for p in want), key=lambda ab: (order[ab[0]], order[ab[1]])):
        mapping.setdefault(a, []).append(b)
    known_current = {p for p in current if all(kin.has_frame(n) for n in p)}
    added = sorted((ordered(p) for p in want - known_current), key=lambda ab: ab)
    removed = sorted((ordered(p) for p in known_current - want), key=lambda ab: ab)
    change = MaskChange(tuple(added), tuple(removed), tuple(sorted(unknown)))
    return FrozenMap((a, tuple(bs)) for a, bs in mapping.items()), change


def recommended_xrdf(xrdf: Xrdf, report: Report) -> Xrdf:
    """``xrdf`` with ``self_collision.ignore`` replaced by the report's recommendation."""
    sc = xrdf.self_collision
    if sc is None:
        raise XrdfToolsError(
            "the XRDF has no self_collision section to write a mask into",
            **xrdf.source.locate(""),
        )
    return xrdf.replace(
        self_collision=SelfCollisionSection(
            geometry=sc.geometry,
            buffer_distance=sc.buffer_distance,
            ignore=FrozenMap(report.recommended_ignore),
        )
    )
