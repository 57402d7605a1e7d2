"""Semantic difference between two XRDF documents.

:func:`diff_xrdf` compares what the documents *mean*, not how they are written:

* mapping order is ignored everywhere (frames, joints, buffers, groups);
* ``collision`` (1.0) and ``world_collision`` (2.0) are the same section; a version change is
  reported once, in the ``format`` section;
* geometry is compared as the *effective* sphere sets of the world and self collision sections,
  with ``clone`` resolved first; a group that is only renamed is a minor (naming) change;
* spheres are compared per frame as multisets within ``tolerance`` (maximum matching), and what
  is left over is reported as radius changes (same centre), moves (same radius, centre moved by
  at most that radius) or additions and removals;
* attached-object slots (radius ≤ −1, cuRobo's ``extra_collision_spheres``) are *not geometry*
  until an object is attached, so they are left out of the sphere comparison and mentioned in
  ``notes`` when the two files carry a different number; a small negative radius (the seed
  UR10e's ``tool0``: −0.01) is a real sphere once buffered and is compared like any other;
* ignore pairs are a symmetric set (``a: [b]`` is the same pair as ``b: [a]``);
* buffers are compared per frame, a missing buffer being 0.0;
* c-space joint order and tool-frame order matter (the first tool frame is the end effector);
  a reorder is reported apart from additions and removals; limits are compared per joint;
* ``add_frame`` transforms are compared within ``tolerance``, orientations as rotations
  (any written form; ``q`` and ``-q`` are the same rotation).

Numbers are equal when ``|x - y| ≤ tolerance`` (per component for vectors and quaternions).

The package is pure: it returns an :class:`XrdfDiff`; :mod:`xrdf_tools.diff.render` turns it into
text or JSON. See ``docs/diff.md``.

Layout: :mod:`.result` (the values returned), :mod:`.mapping` (the generic comparison every
section is written with: keys added / removed / changed, fields, order), one rule module per
group of sections (:mod:`.sections`, :mod:`.modifiers`, :mod:`.geometry`), :mod:`.spheres`
(multiset matching) and :mod:`.values` (tolerance and number formatting). A new section is a
function in a rule module, called from :func:`diff_xrdf` in its place in the list below.
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping

from ..xrdf.io import load_xrdf
from ..xrdf.model import Xrdf
from .geometry import diff_geometry
from .modifiers import diff_modifiers
from .result import (
    JSON_SCHEMA_VERSION,
    SECTION_ORDER,
    Change,
    Detail,
    DocumentInfo,
    Level,
    XrdfDiff,
    jsonable,
)
from .sections import (
    diff_collision_sections,
    diff_cspace,
    diff_defaults,
    diff_extra,
    diff_format,
    diff_tool_frames,
)
from .spheres import FrameSpheres, compare_spheres

__all__ = [
    "DEFAULT_TOLERANCE",
    "JSON_SCHEMA_VERSION",
    "SECTION_ORDER",
    "Change",
    "Detail",
    "DocumentInfo",
    "FrameSpheres",
    "Level",
    "XrdfDiff",
    "compare_spheres",
    "diff_files",
    "diff_xrdf",
    "jsonable",
]

DEFAULT_TOLERANCE = 1e-9


def diff_files(
    path_a: str | os.PathLike[str],
    path_b: str | os.PathLike[str],
    tolerance: float = DEFAULT_TOLERANCE,
    *,
    root_frame: str | None = None,
) -> XrdfDiff:
    """Load two XRDF files and diff them. Load errors raise :class:`XrdfToolsError`."""
    return diff_xrdf(load_xrdf(path_a), load_xrdf(path_b), tolerance, root_frame=root_frame)


def diff_xrdf(
    a: Xrdf,
    b: Xrdf,
    tolerance: float = DEFAULT_TOLERANCE,
    *,
    root_frame: str | None = None,
    unset_defaults: Mapping[str, float] | None = None,
) -> XrdfDiff:
    """Semantic difference from ``a`` to ``b`` (see the module docstring for the rules).

    ``root_frame`` is the URDF's root link when known: ``set_base_frame`` on it is a no-op, so
    a file that has it and one that does not are equal (a note says so). ``unset_defaults``
    (:func:`~xrdf_tools.robot.kinematics.unset_defaults` of the URDF) is the value each
    joint's default has when it is not written: a default added or removed at that value is
    no change either (a note says so).

    Raises :class:`ValueError` for a negative or non-finite ``tolerance`` and
    :class:`~xrdf_tools.util.errors.GeometryGroupError` when a collision section's group (or a
    clone) is undefined or cyclic, because its effective spheres cannot be known.
    """
    if not (math.isfinite(tolerance) and tolerance >= 0):
        raise ValueError(f"tolerance must be a finite number ≥ 0, not {tolerance!r}")
    tol = tolerance
    # Section by section, in this order (it decides which error is raised first).
    found = [
        *diff_format(a, b, tol),
        *diff_modifiers(a, b, tol, root_frame),
        *diff_defaults(a, b, tol, unset_defaults),
        *diff_cspace(a, b, tol),
        *diff_tool_frames(a, b, tol),
        *diff_collision_sections(a, b, tol),
        *diff_geometry(a, b, tol),
        *diff_extra(a, b, tol),
    ]
    order = {s: i for i, s in enumerate(SECTION_ORDER)}
    # Stable sorts: within a section, changes and notes stay in document order.
    changes = sorted(
        (c for c in found if c.level is not Level.INFO), key=lambda c: order[c.section]
    )
    notes = sorted((c for c in found if c.level is Level.INFO), key=lambda c: order[c.section])
    return XrdfDiff(
        DocumentInfo(a.source.path, a.format_version),
        DocumentInfo(b.source.path, b.format_version),
        tolerance,
        tuple(changes),
        tuple(notes),
    )
