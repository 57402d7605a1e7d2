"""Chunks: memory bounded per chunk, progress from within a chunk, the same totals either way.

The report cuts a sample into chunks of :meth:`CountEngine.chunk_limit` configurations (from
the robot's frame pairs, culled pairs and bodies, so that a chunk's arrays stay within about
64 MB), counts them with :meth:`CountEngine.count_totals` (no [K, B] flags of the frame pairs
no body pair samples) and reports progress from within a chunk. On Talos (left arm as the
c-space, seeded spheres on every link) the totals equal :meth:`CountEngine.count`'s, a chunk's
peak memory stays within its budget, and progress steps come about every tenth of a chunk.
"""

from __future__ import annotations

import tracemalloc

import numpy as np
import pytest

from tests.selfcollision.test_collision import fixed_configs
from tests.selfcollision.test_engine import engine_for
from tests.selfcollision.test_engine_static import ARM, talos_left_arm
from xrdf_tools.robot.kinematics import KinematicModel
from xrdf_tools.selfcollision.engine import CountEngine, EngineTotals
from xrdf_tools.selfcollision.engine import core as core_mod
from xrdf_tools.xrdf.model import Xrdf


@pytest.fixture(scope="module")
def talos() -> tuple[KinematicModel, Xrdf, CountEngine, list[int]]:
    kin, xrdf = talos_left_arm(3)
    arm = [kin.actuated_index(j) for j in ARM]
    eng, _, _ = engine_for(kin, xrdf, True, arm, margin=0.01)
    return kin, xrdf, eng, arm


def test_totals_without_flags_equal_the_flags_counted(talos) -> None:  # type: ignore[no-untyped-def]
    kin, _, eng, arm = talos
    q = fixed_configs(kin, 3000, seed=12)[:, arm]
    with_flags, without = EngineTotals.empty(eng.K), EngineTotals.empty(eng.K)
    hits = eng.count(q, with_flags)
    eng.count_totals(q, without)
    np.testing.assert_array_equal(hits.sum(axis=1), with_flags.hits)
    np.testing.assert_array_equal(with_flags.hits, without.hits)
    np.testing.assert_array_equal(with_flags.min_clearance, without.min_clearance)
    np.testing.assert_array_equal(with_flags.clearance_bound, without.clearance_bound)
    assert with_flags.rechecked == without.rechecked
    # only the frame pairs some body pair samples are held per configuration
    assert 0 < len(eng.sampled_k) < eng.K // 2
    assert without.hits.sum() > 0


def test_a_chunk_stays_within_its_memory_budget(talos) -> None:  # type: ignore[no-untyped-def]
    kin, _, eng, arm = talos
    n = eng.chunk_limit()
    assert 4096 <= eng.chunk_limit(flags=True) < n <= 65536
    rng = np.random.default_rng(2)
    q = rng.uniform(kin.lower[arm], kin.upper[arm], (n, len(arm)))
    tracemalloc.start()
    eng.count_totals(q, EngineTotals.empty(eng.K))
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    held = 4 * core_mod._HELD_MINIMA
    assert peak < 1.15 * (core_mod.CHUNK_BYTES + held)
    assert peak > 0.5 * core_mod.CHUNK_BYTES  # the budget is used, not far undershot


def test_progress_steps_come_from_within_a_chunk(talos) -> None:  # type: ignore[no-untyped-def]
    kin, _, eng, arm = talos
    q = fixed_configs(kin, 2000, seed=13)[:, arm]
    steps: list[float] = []
    eng.count_totals(q, EngineTotals.empty(eng.K), on_step=steps.append)
    assert eng.steps_per_chunk == 10 and len(steps) == 10
    assert steps == sorted(steps) and steps[-1] == 1.0
    assert np.all(np.diff([0.0, *steps]) < 0.2)  # about every tenth of the body pairs


def test_minima_classified_in_batches_give_the_same_totals(
    talos, monkeypatch: pytest.MonkeyPatch
) -> None:  # type: ignore[no-untyped-def]
    """A chunk's evaluated minima classified body pair by body pair (the smallest batches)
    give the totals of classifying them all at once."""
    kin, _, eng, arm = talos
    q = fixed_configs(kin, 3000, seed=14)[:, arm]
    at_once = EngineTotals.empty(eng.K)
    eng.count_totals(q, at_once)
    monkeypatch.setattr(core_mod, "_HELD_MINIMA", 1)
    batched = EngineTotals.empty(eng.K)
    eng.count_totals(q, batched)
    np.testing.assert_array_equal(at_once.hits, batched.hits)
    np.testing.assert_array_equal(at_once.min_clearance, batched.min_clearance)
    np.testing.assert_array_equal(at_once.clearance_bound, batched.clearance_bound)
    assert at_once.hits.sum() > 0


def test_culled_gaps_block_by_block_equal_the_whole_chunk(talos) -> None:  # type: ignore[no-untyped-def]
    """The culled pairs' verdicts and bounds reduced column block by column block equal those
    of the chunk's gaps computed at once."""
    from xrdf_tools.selfcollision.engine.bodies import body_poses

    kin, _, eng, arm = talos
    q = fixed_configs(kin, 5000, seed=15)[:, arm]
    T = body_poses(eng.bodies, q)
    pairs = list(eng.cull_plan.pairs)
    assert len(pairs) > 100
    R, t = T[:, :, :3], T[:, :, 3]
    near_b, low_b = eng.culler._near_blocks(pairs, R, t)
    gaps = eng.culler.gaps2(R, t, pairs)  # the whole chunk at once
    reach = np.array([eng.culler.reach(bp) for bp in pairs])
    near_w = gaps <= (reach**2).astype(np.float32)[:, None]
    far = np.min(gaps, axis=1, where=~near_w, initial=np.inf).astype(np.float64)
    low_w = np.sqrt(far) - reach + eng.culler.margin
    np.testing.assert_array_equal(near_b, near_w)
    np.testing.assert_array_equal(low_b, low_w)
    assert near_w.any() and not near_w.all()
