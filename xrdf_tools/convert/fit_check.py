"""Did every link that should get spheres get them? The check after sphere fitting.

Sphere fitting (:func:`xrdf_tools.spheres.fit_link_spheres`) skips what it cannot use and
says so in warnings: a mesh that cannot be read, a part that encloses no volume, a link whose
geometry yields no solid. A planner cannot see a link without spheres, so for the commands
that fit spheres (``xrdf convert --fit-spheres``, ``xrdf spheres``) such a skip fails the
command: :func:`unfitted_links` turns it into one error per link, naming the link and why.

Meshes the user allowed to be missing (``--allow-missing-meshes``) are the exception: their
parts are left out with a warning each, and a link whose only geometry is such a mesh gets no
spheres without an error.

A link with visual geometry only is not fitted by default (``--from collision``): cameras and
covers are usually not what a robot collides with. A link that a c-space joint moves directly
is a moving body, though (Doosan's M1013 URDF gives its elbow and flange no ``<collision>``):
:func:`moving_links_without_spheres` warns that the planner cannot see it.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

from ..diagnostics import Diagnostic, Severity
from ..robot.link_geometry import PartFailure
from ..util.text import name_list

__all__ = [
    "RULE_MOVING_UNFITTED",
    "RULE_UNFITTED",
    "moving_links_without_spheres",
    "unfitted_links",
]

RULE_UNFITTED = "spheres-link-not-covered"
RULE_MOVING_UNFITTED = "convert-moving-link-without-spheres"
#: Links said one by one in ``convert-moving-link-without-spheres``; the rest share a warning.
SAID_ONE_BY_ONE = 3

#: The fitting diagnostics that say a part or a link was dropped.
_DROPPED_RULES = frozenset({"spheres-mesh-unreadable", "spheres-unsupported-geometry"})
_PART_DROPPED = "; this part is ignored"


def unfitted_links(
    path: str,
    wanted: Sequence[str],
    fitted: Mapping[str, Sequence[object]],
    diagnostics: Sequence[Diagnostic],
    *,
    allowed_missing: Sequence[PartFailure] = (),
    lines: Mapping[str, int] | None = None,
) -> list[Diagnostic]:
    """One error per link of ``wanted`` that got no spheres in ``fitted``, or got them for
    only part of its geometry (a part was dropped), with the reasons the fitting
    ``diagnostics`` give; parts in ``allowed_missing`` do not count. ``path`` and ``lines``
    (link -> line) locate the errors in the URDF."""
    out: list[Diagnostic] = []
    for link in wanted:
        allowed = [f.reason for f in allowed_missing if f.link == link]
        about = [
            d
            for d in diagnostics
            if d.message.startswith(f"link '{link}'") and not any(r in d.message for r in allowed)
        ]
        said = [d.message for d in about]
        dropped = [
            d.message
            for d in about
            if d.rule in _DROPPED_RULES and d.message.endswith(_PART_DROPPED)
        ]
        if fitted.get(link):
            if not dropped:
                continue
            message = (
                f"link '{link}' got spheres for only part of its geometry: "
                f"{_reasons(link, dropped)}"
            )
        elif allowed and not said:
            continue  # its only geometry is a mesh the user allowed to be missing
        else:
            why = _reasons(link, said) if said else "its geometry yields no solid to fit"
            message = f"link '{link}' has geometry but got no spheres: {why}"
        where = None if lines is None else lines.get(link)
        out.append(Diagnostic(path, where, None, RULE_UNFITTED, Severity.ERROR, message))
    return out


def _reasons(link: str, messages: Sequence[str]) -> str:
    """The messages about ``link`` without the repeated link name, joined."""
    prefix = f"link '{link}'"
    parts = [m.removeprefix(prefix).lstrip(" :").removesuffix(_PART_DROPPED) for m in messages]
    return "; ".join(dict.fromkeys(parts))


def moving_links_without_spheres(
    path: str,
    visual_only: Sequence[str],
    moved_by: Mapping[str, str],
    lines: Mapping[str, int] | None = None,
) -> list[Diagnostic]:
    """One warning per link of ``visual_only`` (left without spheres) that a c-space joint
    moves directly (``moved_by``: child link -> c-space joint), located at the link; past
    :data:`SAID_ONE_BY_ONE` links, one more warning names the rest (a snake's 64 modules each
    with a visual-only marker made 64 lines that said the same)."""
    moving = [link for link in visual_only if link in moved_by]

    def at(link: str) -> int | None:
        return None if lines is None else lines.get(link)

    out = [
        Diagnostic(
            path,
            at(link),
            None,
            RULE_MOVING_UNFITTED,
            Severity.WARNING,
            f"link '{link}', moved by c-space joint '{moved_by[link]}', has visual geometry "
            "only, so it gets no spheres and the planner sees it neither against obstacles nor "
            "against the rest of the robot; --from auto fits spheres to its visual geometry "
            "(or give it <collision> in the URDF)",
        )
        for link in moving[:SAID_ONE_BY_ONE]
    ]
    rest = moving[SAID_ONE_BY_ONE:]
    if rest:
        out.append(
            Diagnostic(
                path,
                at(rest[0]),
                None,
                RULE_MOVING_UNFITTED,
                Severity.WARNING,
                f"{len(rest)} more link(s) moved by c-space joints have visual geometry only "
                f"and get no spheres, as above: {name_list(rest, 8)}",
            )
        )
    return out
