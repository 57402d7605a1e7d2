"""Readers for conversion inputs: xacro, MoveIt SRDF + joint limits, cuRobo robot YAML.

Each reader fills a :class:`Draft` — what its source says, nothing guessed — and reports every
dropped or unusable value as a :class:`~xrdf_tools.diagnostics.Diagnostic` with the source
position. :mod:`xrdf_tools.convert.core` completes the draft against the URDF (defaults, checks) and
builds the XRDF model. Names of links and joints are checked against a :class:`RobotTree`, a
plain view of the URDF.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field

from ...diagnostics import Diagnostic, Severity
from ...robot.tree import RobotTree
from ...util.errors import did_you_mean
from ...xrdf.model import AddFrame, Modifier, Sphere

__all__ = ["Draft", "Reporter", "RobotTree", "not_a_joint"]


@dataclass(frozen=True)
class OfferedFrame:
    """A frame of another reader's (a Drake ``<frame>``) that ``--tool-frame`` can make an
    XRDF frame: ``added`` (its joint named when taken), else ``why`` it cannot be one."""

    added: AddFrame | None
    what: str
    at: tuple[str, int | None]
    why: str = ""


@dataclass
class Draft:
    """What one or more sources say about the XRDF to write. Empty/None = not said."""

    cspace: list[str] | None = None
    acceleration: dict[str, float] = field(default_factory=dict)
    jerk: dict[str, float] = field(default_factory=dict)
    defaults: dict[str, float] = field(default_factory=dict)
    #: Joint → where its default position was read (file, line), when a source knows.
    default_at: dict[str, tuple[str, int | None]] = field(default_factory=dict)
    tool_frames: list[str] = field(default_factory=list)
    spheres: dict[str, list[Sphere]] | None = None
    world_buffer: dict[str, float] = field(default_factory=dict)
    self_buffer: dict[str, float] = field(default_factory=dict)
    ignore: dict[str, list[str]] = field(default_factory=dict)
    modifiers: list[Modifier] = field(default_factory=list)
    geometry_name: str | None = None
    group: str | None = None
    passive_joints: set[str] = field(default_factory=set)
    #: Joint → a finding (``convert-limit-not-carried``) for MoveIt velocity or position limits
    #: tighter than the URDF's, which no XRDF reader sees; reported for c-space joints only.
    uncarried_limits: dict[str, Diagnostic] = field(default_factory=dict)
    #: ``(kind, joint)`` → where a joint_limits.yaml turns that limit off
    #: (``has_acceleration_limits: false``, as MoveIt Setup Assistant writes): ``(file, line)``.
    limits_off: dict[tuple[str, str], tuple[str, int | None]] = field(default_factory=dict)
    #: Frame names the inputs define for a reader other than XRDF's (a Drake ``<frame>``) →
    #: the ``add_frame`` that ``--tool-frame`` naming one writes (or why none can be), what the
    #: frame is, and where it is written.
    offered_frames: dict[str, OfferedFrame] = field(default_factory=dict)
    diagnostics: list[Diagnostic] = field(default_factory=list)

    def limits(self, kind: str) -> dict[str, float]:
        """The ``acceleration`` or ``jerk`` limits, by joint."""
        return self.acceleration if kind == "acceleration" else self.jerk

    def add_ignore(self, a: str, b: str) -> None:
        """Add the pair once (in either direction), folded under ``a``."""
        if a == b or b in self.ignore.get(a, ()) or a in self.ignore.get(b, ()):
            return
        self.ignore.setdefault(a, []).append(b)


@dataclass
class Reporter:
    """Makes diagnostics for one source file; positions come from ``positions[key_path]``."""

    path: str
    positions: Mapping[str, tuple[int, int]] = field(default_factory=dict)
    diagnostics: list[Diagnostic] = field(default_factory=list)

    def position(self, key_path: str) -> tuple[int | None, int | None]:
        for kp in (key_path + "#key", key_path):
            if kp in self.positions:
                return self.positions[kp]
        kp = key_path
        while kp:
            cut = max(kp.rfind("."), kp.rfind("["))
            kp = kp[:cut] if cut > 0 else ""
            if kp in self.positions:
                return self.positions[kp]
        return (None, None)

    def report(
        self,
        rule: str,
        message: str,
        key_path: str = "",
        *,
        severity: Severity = Severity.WARNING,
        line: int | None = None,
        at: tuple[str, int | None] | None = None,
    ) -> Diagnostic:
        """A diagnostic at ``line`` of the file, else at ``at`` (a file and line: an SRDF
        element a macro of an included file writes), else at ``key_path``."""
        key_path = str(key_path)  # a YAML key may be a number (``1: ...``)
        path = self.path
        if at is not None and line is None:
            path, line = at
        if line is not None:
            pos: tuple[int | None, int | None] = (line, None)
        else:
            pos = self.position(key_path)
        d = Diagnostic(path, pos[0], pos[1], rule, severity, message, key_path)
        self.diagnostics.append(d)
        return d


def known_frame(
    name: str,
    frames: Iterable[str],
    rep: Reporter,
    key_path: str,
    what: str,
    *,
    line: int | None = None,
    at: tuple[str, int | None] | None = None,
) -> bool:
    """True when ``name`` is a frame; otherwise report ``convert-unknown-link`` (did-you-mean)
    at ``line`` or ``at`` (see :meth:`Reporter.report`)."""
    frames = list(frames)
    if name in frames:
        return True
    rep.report(
        "convert-unknown-link",
        f"'{name}' ({what}) is not a link of the URDF; dropped{did_you_mean(name, frames)}",
        key_path,
        line=line,
        at=at,
    )
    return False


def not_a_joint(name: str, tree: RobotTree) -> str:
    """Why ``name``, given where a joint belongs, is not one: a link of the URDF (with the
    joint that moves it), else not in the URDF (with a did-you-mean)."""
    if name in tree.links:
        mover = tree.parent_joint.get(name)
        moved = f"the joint that moves it is '{mover}'" if mover else "no joint moves it"
        return f"is a link of the URDF, not a joint ({moved})"
    return f"is not in the URDF{did_you_mean(name, tree.joints)}"
