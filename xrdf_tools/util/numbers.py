"""The bounds on every number xrdf-tools reads, the same for every command.

A number read from an input (an XRDF, cuRobo or Lula YAML, ``joint_limits.yaml``, a lint
configuration, a URDF attribute, a table of configurations) is usable when it is finite and
within ±:data:`MAX_NUMBER`; a length or coordinate in metres (sphere centres and radii, buffer
distances, frame and joint origins, geometry sizes, prismatic limits, mesh vertices) within
±:data:`MAX_LENGTH`. Past those bounds, products and squares in the self-collision engine,
the sampler and the renderers overflow (``1e308`` limits make ``uniform(lo, hi)`` raise, a
``1e308`` origin turns into ``inf - inf`` in forward kinematics), so a number outside them is
refused where it is read, with its location, and never reaches numpy.

Both bounds are far beyond any robot: joint ranges, limits in rad/s³ and masses stay well below
``1e12``; a robot spans metres, not ``1e6`` m.
"""

from __future__ import annotations

import math
from typing import Any

__all__ = [
    "CERTIFY_BOXES",
    "LIMIT_TOLERANCE",
    "MAX_LENGTH",
    "MAX_NUMBER",
    "MAX_SAMPLES",
    "PLACEHOLDER_SIZE",
    "REPORT_SAMPLES",
    "bound_problem",
    "bound_reason",
    "vertices_problem",
    "within",
]

#: How far past a joint limit a default position may be and still be within it (radians or
#: metres): the last bits of a value written in another unit or rounded by a tool.
LIMIT_TOLERANCE = 1e-9
#: A link whose collision geometry spans less than this across (metres) is a placeholder, not
#: a part: the fitter gives it one sphere, lint does not require one
#: (:mod:`xrdf_tools.robot.placeholders`).
PLACEHOLDER_SIZE = 0.02
#: Largest magnitude of any number read (limits, positions, multipliers, weights, ...).
MAX_NUMBER = 1e12
#: Largest magnitude of a length or coordinate, in metres.
MAX_LENGTH = 1e6
#: The most configurations one run samples (``--samples`` of ``report`` and ``convert
#: --fit-spheres``): ten billion, hours of work on any machine.
MAX_SAMPLES = 10_000_000_000
#: The work ``report --certify`` does by default, in joint boxes: about a minute on one core
#: for pairs of Panda-size links.
CERTIFY_BOXES = 4_000_000
#: Configurations a self-collision report samples by default: ``xrdf report``, the mask
#: ``convert --fit-spheres`` computes and the report of ``xrdf edit``. A recommended mask
#: ignores pairs never seen colliding, so fewer samples miss more of the rare collisions.
REPORT_SAMPLES = 100_000


def within(v: int | float, bound: float = MAX_NUMBER) -> bool:
    """Whether ``v`` is finite and within ±``bound`` (exact for integers of any size: YAML
    integers have no size limit, and ``float()`` of a 400-digit one raises)."""
    if isinstance(v, int):
        return -bound <= v <= bound
    return math.isfinite(v) and -bound <= v <= bound


def bound_reason(v: int | float, *, metres: bool = False) -> str | None:
    """The rule ``v`` breaks (``"lengths must be finite and within ±1e+06 m"``), or None.
    ``metres``: a length or coordinate (:data:`MAX_LENGTH`), else any number
    (:data:`MAX_NUMBER`)."""
    if within(v, MAX_LENGTH if metres else MAX_NUMBER):
        return None
    if metres:
        return f"lengths must be finite and within ±{MAX_LENGTH:g} m"
    return f"numbers must be finite and within ±{MAX_NUMBER:g}"


def bound_problem(v: int | float, *, metres: bool = False) -> str | None:
    """Why ``v`` cannot be used (``"is 1e+308; lengths must be finite and within ±1e+06 m"``),
    or None (see :func:`bound_reason`)."""
    reason = bound_reason(v, metres=metres)
    if reason is None:
        return None
    if isinstance(v, float) or within(v, 1e300):
        shown = f"{float(v):g}"
    else:  # an integer beyond float range
        shown = f"{'-' if v < 0 else ''}about 1e{int(abs(v).bit_length() * math.log10(2))}"
    return f"is {shown}; {reason}"


def vertices_problem(vertices: Any, factors: Any = 1.0) -> str | None:
    """Why mesh ``vertices`` (in the file's units) times the mesh's ``scale`` ``factors``
    cannot be used, or None: every coordinate must be finite and within ±:data:`MAX_LENGTH`
    metres *once scaled* (a part modelled in millimetres 1 km from its origin,
    ``scale="0.001 0.001 0.001"``, is 1e6 in the file and 1,000 m in the link frame)."""
    import numpy as np

    with np.errstate(all="ignore"):
        scaled = np.abs(np.asarray(vertices, dtype=np.float64) * np.asarray(factors, float))
    if not len(scaled):
        return None
    if not np.all(np.isfinite(scaled)):
        return "a vertex is not finite"
    farthest = float(scaled.max())
    if farthest <= MAX_LENGTH:
        return None
    shown = f"{farthest:,.0f}" if farthest < MAX_NUMBER else f"{farthest:.3g}"
    return (
        f"a vertex is {shown} m from the link frame, beyond ±{MAX_LENGTH:g} m (a CAD "
        f"part exported in world coordinates, or a wrong scale?); re-export it about its own "
        f"origin, or check the mesh's scale"
    )
