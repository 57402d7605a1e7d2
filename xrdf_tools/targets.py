"""The programs that read an XRDF ("targets") and which XRDF versions each one loads.

A target names the reader the user will load the file with. ``xrdf convert --target`` picks
the version every named reader loads, ``xrdf lint --target`` turns that reader's silent
failures into errors, and ``xrdf export --target`` checks the output against it.

=============  =============================================  ==========  =================
target         reader                                          versions    on another version
=============  =============================================  ==========  =================
``curobo``     cuRobo 0.7.x / main, Isaac ROS cuMotion 4.x     1.0         2.0 loads with
                                                                           **no** collision
``cumotion``   cuMotion library 1.0 / 1.1                      1.0, 2.0    —
``isaac-sim``  Isaac Sim Robot Description Editor 6.0          1.0, 2.0    —
=============  =============================================  ==========  =================
"""

from __future__ import annotations

from dataclasses import dataclass

from .errors import XrdfToolsError, did_you_mean

__all__ = [
    "TARGETS",
    "Target",
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


def parse_target(value: str | None) -> Target | None:
    """The target named ``value`` (None stays None); an unknown name raises one clear line."""
    if value is None:
        return None
    key = value.strip().lower()
    if key not in TARGETS:
        raise XrdfToolsError(
            f"unknown target '{value}'; choose one of {', '.join(TARGETS)}"
            + did_you_mean(key, TARGETS)
        )
    return TARGETS[key]


def dropping_readers(version: str) -> list[Target]:
    """Readers that do not load a file of ``version`` as written."""
    return [t for t in TARGETS.values() if version not in t.versions]
