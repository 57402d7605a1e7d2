"""The programs that read an XRDF ("targets") and which XRDF versions each one loads.

A target names the reader the user will load the file with. ``xrdf convert --target`` picks
the version every named reader loads, ``xrdf lint --target`` turns that reader's silent
failures into errors, and ``xrdf export --target`` checks the output against it.

=============  =============================================  ==========  =================
target         reader                                          versions    on another version
=============  =============================================  ==========  =================
``curobo``     cuRobo 0.7.x / main, Isaac ROS cuMotion 4.x     1.0         2.0 loads with
               (alias ``isaac-ros``)                                       **no** collision
``cumotion``   cuMotion library 1.0 / 1.1                      1.0, 2.0    —
``isaac-sim``  Isaac Sim Robot Description Editor 6.0          1.0, 2.0    —
=============  =============================================  ==========  =================
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..util.errors import ConversionError, XrdfToolsError, did_you_mean

if TYPE_CHECKING:
    from .model import Xrdf

__all__ = [
    "TARGETS",
    "TARGET_ALIASES",
    "Target",
    "choose_version",
    "dropping_readers",
    "parse_target",
]


@dataclass(frozen=True)
class Target:
    """One reader of XRDF files."""

    id: str
    #: Human name used in messages.
    label: str
    #: XRDF versions it loads as written (the first is the one it prefers).
    versions: tuple[str, ...]


TARGETS: dict[str, Target] = {
    t.id: t
    for t in (
        Target("curobo", "cuRobo and Isaac ROS cuMotion", ("1.0",)),
        Target("cumotion", "the cuMotion library", ("1.0", "2.0")),
        Target("isaac-sim", "Isaac Sim's Robot Description Editor", ("1.0", "2.0")),
    )
}


#: Other names of the programs above: Isaac ROS cuMotion loads an XRDF through cuRobo's reader.
TARGET_ALIASES: dict[str, str] = {"isaac-ros": "curobo", "isaac-ros-cumotion": "curobo"}


def parse_target(value: str | None) -> Target | None:
    """The target named ``value`` (None stays None); an unknown name raises one clear line.

    Case, ``_`` and spaces do not matter (``isaac_sim`` is ``isaac-sim``), and an alias names
    the reader its program loads through (``isaac-ros`` is ``curobo``)."""
    if value is None:
        return None
    key = "-".join(value.strip().lower().replace("_", " ").split())
    key = TARGET_ALIASES.get(key, key)
    if key not in TARGETS:
        raise XrdfToolsError(
            f"unknown target '{value}'; choose one of {', '.join(TARGETS)} (isaac-ros: curobo)"
            + did_you_mean(key, [*TARGETS, *TARGET_ALIASES])
        )
    return TARGETS[key]


def dropping_readers(version: str) -> list[Target]:
    """Readers that do not load a file of ``version`` as written."""
    return [t for t in TARGETS.values() if version not in t.versions]


def choose_version(x: Xrdf, requested: str | None, target: Target | None) -> tuple[str, str]:
    """The XRDF version to write and, when it is 2.0, which readers will not load it.

    1.0 is what every reader loads. 2.0 is written when asked for, or when the robot needs
    what only 2.0 expresses; a target that cannot load that version is an error.
    """
    from .versions import needs_version_2

    needs = needs_version_2(x)
    if requested is None:
        requested = "2.0" if needs else (target.versions[0] if target else "1.0")
    if requested == "1.0" and needs:
        raise ConversionError(f"XRDF 1.0 cannot express this robot: {needs[0]}; write 2.0")
    if target is not None and requested not in target.versions:
        reason = f" (the robot needs it: {needs[0]})" if needs else ""
        raise ConversionError(
            f"XRDF {requested}{reason} is not loaded as written by {target.label} "
            f"(target '{target.id}' reads {', '.join(target.versions)})"
        )
    dropping = [] if target is not None else dropping_readers(requested)
    if not dropping:
        return requested, ""
    reason = f" because {needs[0]}" if needs else ""
    return requested, (
        f"writing XRDF {requested}{reason}: {' and '.join(t.label for t in dropping)} read only "
        "1.0: cuRobo's robot loader stops on this file (no 'collision' section), and its XRDF "
        "converter alone loads it with NO collision spheres (pass --target to say who reads it)"
    )
