"""A total sphere count (``--sphere-budget`` of ``xrdf convert``, ``count`` of
:class:`~.count_policy.CountPolicy`) split over the links to fit.

The total holds every sphere of the result: the URDF's own ``<sphere>`` collisions, taken as
they are, come off it first, and a solid that several links share (fitted once) costs its
spheres once per link. One sphere each, then each further one where it adds the most covered
volume (:func:`allocate`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

__all__ = ["allocate"]


def allocate(
    curves: Mapping[str, Sequence[float]],
    volumes: Mapping[str, float],
    total: int,
    copies: Mapping[str, int] | None = None,
) -> dict[str, int]:
    """Split ``total`` spheres over solids: one each, then by largest covered-volume gain
    (``curves[s][k - 1]``: the share ``k`` spheres cover). A solid that ``copies[s]`` links
    share costs that many spheres for each of its own, and gains as much for each link."""
    cost = {s: (copies or {}).get(s, 1) for s in curves}
    alloc = dict.fromkeys(curves, 1)
    left = total - sum(cost.values())
    while left > 0:
        best, best_gain = None, -1.0
        for s, curve in curves.items():
            k = alloc[s]
            if k >= len(curve) or cost[s] > left:
                continue
            gain = (curve[k] - curve[k - 1]) * volumes[s]
            if gain > best_gain:
                best, best_gain = s, gain
        if best is None:
            break
        alloc[best] += 1
        left -= cost[best]
    return alloc
