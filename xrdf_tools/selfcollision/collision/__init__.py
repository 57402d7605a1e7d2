"""Self-collision of sphere models: active pairs as index arrays, batched distances, counting.

Semantics (docs/report.md): spheres ``a`` and ``b`` on *different* frames are in
self-collision when ``‖c_a − c_b‖ < (r_a + s_a) + (r_b + s_b)``, where ``s`` is the frame's
``self_collision.buffer_distance`` (default 0). Pairs on the same frame are never checked; a
pair whose frames are in ``self_collision.ignore`` (either direction) is masked. A sphere with a
raw radius ≤ −1 is an attached-object slot and takes part in no check; a small negative raw
radius becomes a real sphere once buffered (at least 1 mm, as cuRobo builds it). Mimic,
continuous and prismatic joints are handled by :mod:`xrdf_tools.robot.kinematics`.

Modules, bottom up:

* :mod:`.spheres`: :func:`build_sphere_set` turns an :class:`~xrdf_tools.xrdf.model.Xrdf` plus a
  :class:`~xrdf_tools.robot.kinematics.KinematicModel` into a :class:`SphereSet` of flat arrays
  (and :func:`~.spheres.bounding_sphere`, the culling bound shared with the engine).
* :mod:`.distances`: the pair test (:func:`~.distances.touching`), :func:`sphere_world_centers`
  and :func:`pair_clearance` (every pair, float64, no culling), the float64 verdicts of chosen
  (frame pair, configuration) entries, and :func:`contacts` / :func:`colliding_frame_pairs`
  ("what collides at this q": lint's default-pose rule, viz).
* ``tests/collision_reference.py``: ``count_chunk``, the reference counter (float64 with
  bounding-sphere culling) that the report's :mod:`xrdf_tools.selfcollision.engine` is measured and
  tested against.

All arithmetic here is float64. Counting compares squared distances with squared radius sums,
so a pair's verdict can only differ from an exact real-number evaluation when it is within a
few ulp (~1e-15 m) of touching. Every name is importable from
``xrdf_tools.selfcollision.collision``.
"""

from __future__ import annotations

from .distances import (
    Contact,
    colliding_frame_pairs,
    colliding_sphere_pairs,
    contacts,
    contacts_of_pairs,
    frame_pair_clearances,
    frame_pair_verdicts,
    pair_clearance,
    pair_hits,
    sphere_world_centers,
    squared_distances,
    touching,
)
from .spheres import (
    CULL_SLACK,
    MAX_SPHERE_FRAMES,
    MAX_SPHERES,
    MIN_BUFFERED_RADIUS,
    SphereLimitError,
    SphereSet,
    bounding_sphere,
    build_sphere_set,
    is_slot,
    self_radius,
)

__all__ = [
    "CULL_SLACK",
    "MAX_SPHERES",
    "MAX_SPHERE_FRAMES",
    "MIN_BUFFERED_RADIUS",
    "Contact",
    "SphereLimitError",
    "SphereSet",
    "bounding_sphere",
    "build_sphere_set",
    "colliding_frame_pairs",
    "colliding_sphere_pairs",
    "contacts",
    "contacts_of_pairs",
    "frame_pair_clearances",
    "frame_pair_verdicts",
    "is_slot",
    "pair_clearance",
    "pair_hits",
    "self_radius",
    "sphere_world_centers",
    "squared_distances",
    "touching",
]
