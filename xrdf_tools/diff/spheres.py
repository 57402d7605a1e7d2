"""Sphere sets compared as multisets within a tolerance (one frame's spheres at a time).

:func:`compare_spheres` pairs the spheres of A and B that are equal (maximum matching), then
reads what is left over as radius changes, moves, additions and removals; :func:`effective`
leaves out attached-object slots, which are not geometry.
"""

from __future__ import annotations

import bisect
import math
from collections import deque
from collections.abc import Callable, Sequence
from dataclasses import dataclass

from ..xrdf.model import Sphere
from .values import close, close_all


def _max_matching(adj: Sequence[Sequence[int]], nb: int) -> list[tuple[int, int]]:
    """Maximum bipartite matching (greedy start, then BFS augmenting paths); ``(i, j)`` pairs."""
    match_a = [-1] * len(adj)
    match_b = [-1] * nb
    for i, js in enumerate(adj):
        for j in js:
            if match_b[j] < 0:
                match_a[i], match_b[j] = j, i
                break
    for i in range(len(adj)):
        if match_a[i] >= 0 or not adj[i]:
            continue
        parent: dict[int, int] = {}
        seen = {i}
        queue = deque([i])
        free = -1
        while queue and free < 0:
            u = queue.popleft()
            for j in adj[u]:
                if j in parent:
                    continue
                parent[j] = u
                if match_b[j] < 0:
                    free = j
                    break
                w = match_b[j]
                if w not in seen:
                    seen.add(w)
                    queue.append(w)
        j = free
        while j >= 0:
            u = parent[j]
            previous = match_a[u]
            match_a[u], match_b[j] = j, u
            j = previous if u != i else -1
    return [(i, j) for i, j in enumerate(match_a) if j >= 0]


@dataclass(frozen=True)
class FrameSpheres:
    """How the effective spheres of one frame differ (what :func:`compare_spheres` returns)."""

    added: tuple[Sphere, ...] = ()
    removed: tuple[Sphere, ...] = ()
    radius_changed: tuple[tuple[Sphere, Sphere], ...] = ()
    moved: tuple[tuple[Sphere, Sphere], ...] = ()

    def __bool__(self) -> bool:
        return bool(self.added or self.removed or self.radius_changed or self.moved)


def compare_spheres(a: Sequence[Sphere], b: Sequence[Sphere], tol: float) -> FrameSpheres:
    """Multiset comparison of two sphere lists within ``tol``.

    1. equal spheres (centre and radius within ``tol``) are paired by a maximum matching;
    2. leftovers with the same centre are *radius changes* (maximum matching);
    3. leftovers with the same radius whose centres are at most one radius apart (the new
       centre lies inside the old sphere) are *moves*, nearest first;
    4. anything else is added or removed.
    """
    ia = list(range(len(a)))
    ib = list(range(len(b)))

    def same_center(x: Sphere, y: Sphere) -> bool:
        return close_all(x.center, y.center, tol)

    def stage(ok: Callable[[Sphere, Sphere], bool]) -> list[tuple[int, int]]:
        # Both stages need equal centres, so candidates are found in a window on x.
        nonlocal ia, ib
        adj = _candidates([a[i] for i in ia], [b[j] for j in ib], ok, tol)
        pairs = [(ia[p], ib[q]) for p, q in _max_matching(adj, len(ib))]
        used_a = {i for i, _ in pairs}
        used_b = {j for _, j in pairs}
        ia = [i for i in ia if i not in used_a]
        ib = [j for j in ib if j not in used_b]
        return sorted(pairs)

    stage(lambda x, y: same_center(x, y) and close(x.radius, y.radius, tol))
    radius = stage(same_center)
    # Moves: equal radius, centres within one radius, nearest first (ties by index).
    candidates = sorted(
        (math.dist(a[i].center, b[j].center), i, j)
        for i in ia
        for j in ib
        if close(a[i].radius, b[j].radius, tol)
        and math.dist(a[i].center, b[j].center) <= max(a[i].radius, tol)
    )
    moved: list[tuple[int, int]] = []
    used_a: set[int] = set()
    used_b: set[int] = set()
    for _, i, j in candidates:
        if i not in used_a and j not in used_b:
            used_a.add(i)
            used_b.add(j)
            moved.append((i, j))
    moved.sort()
    return FrameSpheres(
        added=tuple(b[j] for j in ib if j not in used_b),
        removed=tuple(a[i] for i in ia if i not in used_a),
        radius_changed=tuple((a[i], b[j]) for i, j in radius),
        moved=tuple((a[i], b[j]) for i, j in moved),
    )


def _candidates(
    a: Sequence[Sphere], b: Sequence[Sphere], ok: Callable[[Sphere, Sphere], bool], tol: float
) -> list[list[int]]:
    """For each sphere of ``a``, the indices of ``b`` with ``ok``; only spheres whose centre x
    lies within ``tol`` are tried (all of them when a coordinate is not finite)."""
    if not all(math.isfinite(s.center[0]) for s in (*a, *b)):
        return [[j for j, y in enumerate(b) if ok(x, y)] for x in a]
    order = sorted(range(len(b)), key=lambda j: b[j].center[0])
    xs = [b[j].center[0] for j in order]
    out = []
    for x in a:
        lo = bisect.bisect_left(xs, x.center[0] - tol)
        hi = bisect.bisect_right(xs, x.center[0] + tol)
        out.append(sorted(order[k] for k in range(lo, hi) if ok(x, b[order[k]])))
    return out


def effective(spheres: Sequence[Sphere]) -> tuple[tuple[Sphere, ...], int]:
    """Spheres that are geometry, and how many attached-object slots (radius ≤ −1) were left
    out."""
    kept = tuple(s for s in spheres if s.radius > -1)
    return kept, len(spheres) - len(kept)
