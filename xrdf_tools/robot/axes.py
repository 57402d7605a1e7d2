"""Joint axes against the coordinate axes: which axis a reader that knows ±x, ±y and ±z only
(cuRobo) reads as written, which is one but for rounding, and how far a tilted one is off.

Plain :mod:`math`: the linter imports this without numpy.
"""

from __future__ import annotations

import math

__all__ = ["ROUNDING", "Axis", "coordinate_axis_near", "degrees_off", "is_coordinate_axis"]

Axis = tuple[float, float, float]

#: How far each component of an axis may be off a coordinate axis for the axis to be that one
#: "but for rounding" (a CAD export's ``1.0000000000000004`` and ``2.2e-14``).
ROUNDING = 1e-6


def is_coordinate_axis(axis: Axis) -> bool:
    """Exactly ±x, ±y or ±z: one component exactly 1 or -1, the others exactly 0. (cuRobo's
    URDF parser takes a component of exactly ±1 for that axis whatever the others are.)"""
    units = [i for i, a in enumerate(axis) if abs(a) == 1.0]
    return len(units) == 1 and all(a == 0.0 for i, a in enumerate(axis) if i != units[0])


def coordinate_axis_near(axis: Axis) -> Axis | None:
    """The coordinate axis (``(0.0, 0.0, -1.0)``) that ``axis`` is but for rounding: one
    component within :data:`ROUNDING` of ±1, the others within it of 0; None for any other
    axis (a tilted one)."""
    near = [i for i, a in enumerate(axis) if abs(abs(a) - 1.0) < ROUNDING]
    if len(near) != 1 or any(abs(a) >= ROUNDING for i, a in enumerate(axis) if i != near[0]):
        return None
    k = near[0]
    sign = -1.0 if axis[k] < 0 else 1.0
    return (sign if k == 0 else 0.0, sign if k == 1 else 0.0, sign if k == 2 else 0.0)


def degrees_off(axis: Axis) -> float:
    """The angle in degrees between the direction of ``axis`` (not zero) and the nearest
    of ±x, ±y, ±z."""
    length = math.sqrt(sum(a * a for a in axis))
    return math.degrees(math.acos(min(1.0, max(abs(a) for a in axis) / length)))
