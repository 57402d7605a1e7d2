"""What cuRobo's loader would raise on in an exported robot YAML, found before it is written.

The ``curobo-*`` lint rules (``xrdf lint --target curobo``, which ``xrdf convert --target
curobo`` runs too) say where cuRobo's loader raises on an XRDF. ``xrdf export curobo`` writes
its own YAML from the XRDF, so some of those findings never reach cuRobo through it (the export
writes every number as a float, ``FIXED``, lists by joint name, ...: :data:`WRITTEN_AWAY`);
the others -- a URDF's empty limit range (velocity, effort, or position:
``cspace-joint-held``, :data:`RAISES_IN_CUROBO`) or tilted axis (with ``--keep-axes``: the
export otherwise writes a URDF with the axis rewritten), a floating joint below the base, a
c-space joint on no chain cuRobo builds, no sphere pair left to check -- would make cuRobo's
loader raise on the export as on the XRDF: :func:`loader_errors` returns them, located in the
XRDF (the messages name the URDF or xacro line of each joint), and the export writes nothing.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..diagnostics import Diagnostic, Severity

if TYPE_CHECKING:
    from ..robot.core import Robot

__all__ = ["AXES_WRITTEN", "RAISES_IN_CUROBO", "WRITTEN_AWAY", "loader_errors"]

#: The cuRobo reader's rules (``curobo-*``, ``reader-number``) whose finding about the XRDF the
#: exported YAML does not carry, and why. A rule of that reader not listed here stops the export.
WRITTEN_AWAY: dict[str, str] = {
    "curobo-default-order": "the lists are written by joint name, not in URDF order",
    "curobo-different-groups": "the world group is written (export-different-groups says so)",
    "curobo-dropped": "clones are written flattened; remove_mimic_attributes stops the export",
    "curobo-format-version": "the YAML is cuRobo's own config, read from either version",
    "curobo-integer": "every number is written as a float",
    "curobo-joint-type": "every added frame is written with joint_type FIXED",
    "curobo-missing-key": (
        "the export writes the keys itself (0.0 for a missing default position, an ignore map "
        "of the pairs; export-no-pair when none is left) and stops without tool_frames"
    ),
    "curobo-no-pair": "export-no-pair checks the pairs as written, also those it masks itself",
    "curobo-quoted-version": "format_version is written as a number",
    "curobo-self-buffer": "the self-collision buffer is written per frame",
    "reader-number": "the numbers are written as both YAML readings read them (as xrdf reads them)",
}


#: Rules of no one reader whose finding is an error for ``--target curobo`` because cuRobo's
#: loader raises on it: they stop the export as the reader's own rules do.
RAISES_IN_CUROBO = frozenset({"cspace-joint-held"})


#: The rule whose findings the URDF the export writes carries away: it rewrites every joint
#: axis cuRobo cannot take (:mod:`xrdf_tools.export.curobo_axes`), unless ``--keep-axes``.
AXES_WRITTEN = "curobo-joint-axis"


def loader_errors(
    text: str, label: str, robot: Robot, *, axes_written: bool = False
) -> list[Diagnostic]:
    """The ``curobo-*`` lint errors of the XRDF ``text`` (the file ``label``) for ``robot``
    that the exported YAML would carry to cuRobo's loader, which raises on each
    (``axes_written``: the URDF written has every joint axis rewritten, so
    :data:`AXES_WRITTEN` is not among them)."""
    from ..lint import RULES, lint_text

    skip = {*WRITTEN_AWAY, *([AXES_WRITTEN] if axes_written else [])}
    rules = [
        r for r in RULES if (r.reader == "curobo" and r.id not in skip) or r.id in RAISES_IN_CUROBO
    ]
    found = lint_text(text, label, urdf_model=robot, target="curobo", rules=rules)
    return [d for d in found if d.severity is Severity.ERROR]
