"""The counting engine behind ``xrdf report``: exact per-frame-pair collision counts, fast.

:class:`CountEngine` answers, for a chunk of configurations, which frame pairs of a
:class:`~xrdf_tools.selfcollision.collision.SphereSet` collide (exactly, as the float64 brute force
``‖c_a − c_b‖ < r_a + r_b`` does) and keeps exact minimum clearances. It is built once per
report; only the c-space joints (``varying``) change between configurations, every other joint
stays at the base configuration. How it gets its speed (see ``docs/report.md``), module by
module:

1. **Moving bodies** (:mod:`.bodies`). Frames joined by joints that do not vary (fixed joints,
   joints outside the c-space held at their defaults) are folded into one rigid *body*; sphere
   centres are stored in their body's frame. Forward kinematics runs over bodies only, in
   float32.
2. **Constant pairs** (:mod:`.core`). Two frames on the same body never move relative to each
   other: the pair is decided once, exactly, at the base configuration.
3. **Body pairs** (:mod:`.pairs`). Frame pairs between the same two bodies share one relative
   transform. The spheres of body B are moved into the frame of body A with one GEMM, and
   every sphere pair's ``d² − (r_a + r_b)²`` comes out of one more GEMM (the expanded distance
   ``|p|² + |q|² − 2 p·q − r_a² − 2 r_a r_b − r_b²`` with the rank-one radius term folded in),
   in blocks small enough for the CPU cache.
4. **Culling** (:mod:`.culling`). Body pairs that are usually far apart first test one
   bounding sphere per body (many pairs sharing a side: as a group first), or a cell grid
   over the one or two joints between them; only configurations within reach (plus the
   exact-clearance margin) are evaluated.
5. **Exactness** (:mod:`.bounds`, :mod:`.classify`, :mod:`.sharpen`, :mod:`.core`). float32
   values carry an error bounded by ``delta`` (derived from float32 precision and the lever
   arm: the robot's, or for bodies a joint or two apart, the pair's own along those joints);
   a frame pair whose smallest ``d² − (r_a + r_b)²`` lies within ``± delta`` of zero is
   looked at again in float64 along the tree path between its bodies, and only what is still
   within that error goes to the reference pair test of
   :mod:`xrdf_tools.selfcollision.collision`; so do the few configurations that may hold a
   frame pair's minimum clearance (when it is below the margin), found sphere pair by sphere
   pair. Sphere pairs that no joint moves (a centre on the joint axis between the two
   bodies) are decided once. Counts therefore equal the float64 brute force, clearances are
   float64-exact.
6. **Workers** (:mod:`.jobs`). :func:`count_sampled` spreads chunks over ``--jobs`` processes
   with identical totals.

Every name is importable from ``xrdf_tools.selfcollision.engine``. To change the worker threshold at
run time, set :data:`xrdf_tools.selfcollision.engine.jobs.MIN_SAMPLES_PER_JOB` (the value
re-exported here is a copy).
"""

from __future__ import annotations

from .bodies import body_fk as body_fk  # compared with float64 kinematics in the tests
from .core import CountEngine, EngineTotals
from .jobs import MIN_SAMPLES_PER_JOB, ProgressFn, count_sampled, default_jobs

__all__ = [
    "MIN_SAMPLES_PER_JOB",
    "CountEngine",
    "EngineTotals",
    "ProgressFn",
    "count_sampled",
    "default_jobs",
]
