"""Error bounds of the float32 path: when a float32 verdict is sure, what a value implies.

The engine evaluates ``e = d² − R²`` (squared centre distance minus squared radius sum) in
float32. :func:`energy_error` bounds its error near ``e = 0``: a float32 verdict is trusted only
outside ``± delta``, everything inside is re-decided in float64. The clearance functions turn
a bound on ``e`` into a bound on the clearance ``d − R`` for a frame pair whose radius sums lie
in ``[rlo, rhi]`` (and back), which is how the engine knows which configurations can hold a
frame pair's minimum clearance without computing every clearance.
"""

from __future__ import annotations

import numpy as np

from ...util.arrays import FloatArray
from .bodies import EPS32


def energy_error(pmax: float, r_max: float, err: float) -> float:
    """Bound on |float32 − exact| of ``d² − R²`` wherever that value is near zero, for sphere
    centres of side ``a`` at most ``pmax`` from its body origin and radius sums up to
    ``r_max``.

    Near zero ``d ≤ R + err``: a position error ``err`` moves ``d²`` by at most
    ``2 (R + err) err``; the GEMM's own rounding is bounded by a few float32 ulps of the
    largest term, ``(2|p| + R)²``. Doubled for safety.
    """
    return 2.0 * (2.0 * (r_max + err) * err + 16.0 * EPS32 * (2.0 * pmax + r_max + err) ** 2)


def energy_at(c: FloatArray, rlo: FloatArray, rhi: FloatArray) -> FloatArray:
    """Largest ``e`` with ``clearance_lo(e) <= c`` (the inverse of that monotone bound)."""
    with np.errstate(invalid="ignore"):
        neg = np.where(c >= -rlo, (c + rlo) ** 2 - rlo**2, -(c**2))
        e = np.where(c >= 0, (c + rhi) ** 2 - rhi**2, np.where(c < -rhi, -np.inf, neg))
    return np.where(np.isfinite(c), e, np.inf)


def clearance_lo(e: FloatArray, rlo: FloatArray, rhi: FloatArray) -> FloatArray:
    """Lower bound of ``d − R`` given ``d² − R² >= e`` and ``R`` in [rlo, rhi]."""
    with np.errstate(invalid="ignore"):
        pos = np.sqrt(np.maximum(e + rhi**2, 0.0)) - rhi
        neg = np.where(e <= -(rlo**2), -np.sqrt(np.maximum(-e, 0.0)), np.sqrt(e + rlo**2) - rlo)
    out = np.where(e >= 0, pos, np.maximum(neg, -rhi))
    return np.where(np.isfinite(e), out, np.inf)


def clearance_hi(e: FloatArray, rlo: FloatArray, rhi: FloatArray) -> FloatArray:
    """Upper bound of ``d − R`` given ``d² − R² <= e`` for one pair, ``R`` in [rlo, rhi]."""
    with np.errstate(invalid="ignore"):
        pos = np.sqrt(np.maximum(e + rlo**2, 0.0)) - rlo
        neg = np.sqrt(np.maximum(e + rhi**2, 0.0)) - rhi
    out = np.where(e >= 0, pos, neg)
    return np.where(np.isfinite(e), out, np.inf)
