"""The report's counting engine: float32 fast path, float64-exact counts and clearances."""

from __future__ import annotations

import numpy as np
import pytest

from tests.selfcollision.test_collision import brute_force, fixed_configs, panda, three_link
from xrdf_tools.robot.kinematics import KinematicModel, default_configuration
from xrdf_tools.selfcollision.collision import (
    build_sphere_set,
    pair_clearance,
    sphere_world_centers,
)
from xrdf_tools.selfcollision.engine import CountEngine, EngineTotals, body_fk, count_sampled
from xrdf_tools.selfcollision.sampling import iter_samples
from xrdf_tools.xrdf.model import Xrdf

MARGIN = 0.05


def engine_for(  # type: ignore[no-untyped-def]
    kin: KinematicModel, xrdf: Xrdf, include_masked: bool, varying: list[int], margin=MARGIN
):
    spheres, _ = build_sphere_set(kin, xrdf, include_masked=include_masked)
    q0 = default_configuration(kin, xrdf.default_joint_positions)
    return CountEngine(kin, spheres, varying, q0, margin=margin), spheres, q0


def check_against_brute_force(
    kin: KinematicModel,
    xrdf: Xrdf,
    q_var: np.ndarray,
    include_masked: bool,
    varying: list[int],
    margin: float = MARGIN,
) -> EngineTotals:
    eng, spheres, q0 = engine_for(kin, xrdf, include_masked, varying, margin)
    q = np.repeat(q0[None, :], len(q_var), axis=0)
    q[:, varying] = q_var
    ref, ref_min, boundary = brute_force(kin, xrdf, q, include_masked=include_masked)
    totals = EngineTotals.empty(spheres.n_frame_pairs)
    hits = eng.count(q_var, totals)
    for k, (a, b) in enumerate(spheres.frame_pair_names()):
        key = frozenset((a, b))
        if key in boundary:  # two spheres exactly touching at a constant distance
            continue
        np.testing.assert_array_equal(hits[k], ref[key], err_msg=f"{a}/{b}")
        assert totals.hits[k] == ref[key].sum()
        true_min = ref_min[key]
        if totals.min_clearance[k] <= totals.clearance_bound[k]:
            assert totals.min_clearance[k] == pytest.approx(true_min, abs=1e-12), (a, b)
        else:
            assert totals.clearance_bound[k] <= true_min + 1e-12, (a, b)
        if true_min < margin:  # within the margin the minimum is exact
            assert totals.min_clearance[k] == pytest.approx(true_min, abs=1e-12), (a, b)
    return totals


@pytest.mark.parametrize("include_masked", [False, True])
def test_counts_equal_brute_force_three_link(include_masked: bool) -> None:
    kin, xrdf = three_link()
    q = fixed_configs(kin, 300, seed=1)
    totals = check_against_brute_force(kin, xrdf, q, include_masked, list(range(kin.n_actuated)))
    assert 0 < totals.hits.sum() < 300 * 10


@pytest.mark.parametrize("include_masked", [False, True])
def test_counts_equal_brute_force_panda(include_masked: bool) -> None:
    kin, xrdf = panda()
    q = fixed_configs(kin, 60, seed=7)
    totals = check_against_brute_force(kin, xrdf, q, include_masked, list(range(kin.n_actuated)))
    assert totals.hits.sum() > 0


def test_panda_cspace_only_folds_the_hand_and_decides_constant_pairs_once() -> None:
    kin, xrdf = panda()
    assert xrdf.cspace is not None
    cspace = [kin.actuated_index(j) for j in xrdf.cspace.joint_names]
    eng, _, _ = engine_for(kin, xrdf, True, cspace)
    # the fingers are not in the c-space: link7, hand and fingers form one body
    assert eng.bodies.n == 8
    names = list(eng.spheres.frame_pair_names())
    const = {frozenset(names[k]) for k in eng.const_k.tolist()}
    assert frozenset(("panda_leftfinger", "panda_rightfinger")) in const
    assert frozenset(("panda_link7", "panda_hand")) in const
    q = fixed_configs(kin, 200, seed=11)[:, cspace]
    check_against_brute_force(kin, xrdf, q, True, cspace)


def _bisect_touching(
    eng: CountEngine, spheres, q0: np.ndarray, p: int, joint: int, lo: float, hi: float
) -> float:  # type: ignore[no-untyped-def]
    """Joint value in [lo, hi] where sphere pair ``p`` touches (its clearance changes sign)."""

    def clr(v: float) -> float:
        q = q0.copy()
        q[joint] = v
        c = sphere_world_centers(eng.kin, spheres, q)
        return float(pair_clearance(spheres, c)[p])

    f_lo = clr(lo)
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        if (clr(mid) < 0) == (f_lo < 0):
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def _slope(kin: KinematicModel, spheres, q: np.ndarray, p: int, j: int, v: float) -> float:  # type: ignore[no-untyped-def]
    """d(clearance of pair p)/d(q[j]) at q[j] = v, by central differences."""
    qq = np.repeat(q[None, :], 2, axis=0)
    qq[:, j] = (v - 1e-5, v + 1e-5)
    c = pair_clearance(spheres, sphere_world_centers(kin, spheres, qq))[:, p]
    return float(c[1] - c[0]) / 2e-5


def near_boundary_configs(n_want: int, seed: int) -> tuple[np.ndarray, list[int], list[int]]:
    """Panda configurations where some sphere pair is within ±1e-6 m of touching."""
    kin, xrdf = panda()
    eng, spheres, _ = engine_for(kin, xrdf, True, list(range(kin.n_actuated)))
    rng = np.random.default_rng(seed)
    out: list[np.ndarray] = []
    target: list[int] = []
    lo = hi = 0.0
    qs = fixed_configs(kin, 400, seed=seed)
    for q in qs:
        c = sphere_world_centers(kin, spheres, q)
        clr = pair_clearance(spheres, c)
        clr[np.abs(clr) < 1e-12] = np.inf  # pairs touching exactly at a constant distance
        p = int(np.argmin(np.abs(clr)))
        if abs(clr[p]) > 0.05:
            continue
        for j in rng.permutation(7).tolist():  # an arm joint that moves the pair through 0
            lo, hi = q[j] - 0.2, q[j] + 0.2
            ends = []
            for v in (lo, hi):
                qq = q.copy()
                qq[j] = v
                ends.append(pair_clearance(spheres, sphere_world_centers(kin, spheres, qq))[p])
            if (ends[0] < 0) != (ends[1] < 0):
                break
        else:
            continue
        v = _bisect_touching(eng, spheres, q, p, j, lo, hi)
        slope = _slope(kin, spheres, q, p, j, v)
        if abs(slope) < 1e-3:
            continue
        for offset in (-1e-6, -1e-7, -2e-8, 2e-8, 1e-7, 1e-6):  # metres of clearance
            qq = q.copy()
            qq[j] = v + offset / slope
            out.append(qq)
            target.append(p)
        if len(out) >= n_want:
            break
    return np.array(out), target, list(range(kin.n_actuated))


def test_near_boundary_configurations_float32_counts_equal_float64() -> None:
    kin, xrdf = panda()
    q, target, varying = near_boundary_configs(120, seed=5)
    assert len(q) >= 60
    spheres, _ = build_sphere_set(kin, xrdf, include_masked=True)
    clr = pair_clearance(spheres, sphere_world_centers(kin, spheres, q))
    close = np.abs(clr[np.arange(len(q)), target])
    assert np.all(close < 1.5e-6)  # every configuration is on the edge of a verdict
    assert np.all(close > 1e-8)  # but not so close that float64 rounding decides
    # margin 0: no configuration is re-evaluated for its clearance, only for its verdict
    totals = check_against_brute_force(kin, xrdf, q, True, varying, margin=0.0)
    assert totals.rechecked >= len(q) // 2  # the guard band sent them to float64


def test_float32_error_stays_far_below_the_guard() -> None:
    kin, xrdf = panda()
    assert xrdf.cspace is not None
    cspace = [kin.actuated_index(j) for j in xrdf.cspace.joint_names]
    eng, spheres, q0 = engine_for(kin, xrdf, False, cspace)
    qv = fixed_configs(kin, 3000, seed=2)[:, cspace]
    R, t = body_fk(eng.bodies, qv)
    q = np.repeat(q0[None, :], len(qv), axis=0)
    q[:, cspace] = qv
    exact = sphere_world_centers(kin, spheres, q)
    body = eng.sphere_body
    fast = np.einsum("sikb,sk->bsi", R[body], eng.local.astype(np.float32))
    fast += t[body].transpose(2, 0, 1)
    assert np.abs(fast - exact).max() < eng.err / 10


def test_chunks_and_jobs_give_identical_totals() -> None:
    kin, xrdf = three_link()
    eng, _, _ = engine_for(kin, xrdf, True, list(range(kin.n_actuated)))
    lo, hi = kin.lower, kin.upper
    n = 5000
    one = count_sampled(eng, lo, hi, n, method="uniform", seed=3, chunk=700)
    # the same chunks counted one by one from the streaming sampler
    ref = EngineTotals.empty(eng.K)
    for q in iter_samples(lo, hi, n, method="uniform", seed=3, chunk=700):
        eng.count(q, ref)
    np.testing.assert_array_equal(one.hits, ref.hits)
    for a, b in zip(one.clearance(), ref.clearance(), strict=True):
        np.testing.assert_array_equal(a, b)
    # where count_sampled reads the threshold
    import xrdf_tools.selfcollision.engine.jobs as engine_mod

    old = engine_mod.MIN_SAMPLES_PER_JOB
    engine_mod.MIN_SAMPLES_PER_JOB = 1000  # force two worker processes on a small sample
    try:
        two = count_sampled(eng, lo, hi, n, method="uniform", seed=3, chunk=700, jobs=2)
    finally:
        engine_mod.MIN_SAMPLES_PER_JOB = old
    np.testing.assert_array_equal(one.hits, two.hits)
    for a, b in zip(one.clearance(), two.clearance(), strict=True):
        np.testing.assert_array_equal(a, b)
    assert two.configurations == n


def test_workers_count_every_chunk_when_all_queued_chunks_finish_together(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """On a loaded machine every queued chunk can be done by the time the parent looks: the
    parent then stopped with chunks never submitted (the last 500 of 3,000 samples lost, a
    sixth of the hits). Here each wait returns only when every queued chunk is done."""
    import concurrent.futures

    import xrdf_tools.selfcollision.engine.jobs as jobs_mod

    kin, xrdf = three_link()
    eng, _, _ = engine_for(kin, xrdf, True, list(range(kin.n_actuated)))
    lo, hi = kin.lower, kin.upper
    n = 5000
    one = count_sampled(eng, lo, hi, n, method="uniform", seed=3, chunk=700)
    real_wait = concurrent.futures.wait

    def wait_all(fs, timeout=None, return_when=None):  # type: ignore[no-untyped-def]
        return real_wait(fs, return_when=concurrent.futures.ALL_COMPLETED)

    monkeypatch.setattr(concurrent.futures, "wait", wait_all)
    monkeypatch.setattr(jobs_mod, "MIN_SAMPLES_PER_JOB", 1000)  # two workers, small sample
    two = count_sampled(eng, lo, hi, n, method="uniform", seed=3, chunk=700, jobs=2)
    assert two.configurations == n
    np.testing.assert_array_equal(one.hits, two.hits)
    for a, b in zip(one.clearance(), two.clearance(), strict=True):
        np.testing.assert_array_equal(a, b)


def test_grid_far_cells_are_really_beyond_the_margin() -> None:
    """Dense check of the cell grids: no configuration in a far cell comes within the margin."""
    kin, xrdf = panda()
    assert xrdf.cspace is not None
    cspace = [kin.actuated_index(j) for j in xrdf.cspace.joint_names]
    eng, spheres, q0 = engine_for(kin, xrdf, True, cspace, margin=0.01)
    grids = [bp for bp in eng.pairs if bp.grid is not None]
    assert len(grids) >= 4
    hand = next(bp for bp in grids if bp.n_sphere_pairs == 351)  # link5 / hand body
    assert hand.grid is not None and 0.5 < hand.grid.far_fraction < 1.0
    qv = fixed_configs(kin, 20000, seed=4)[:, cspace]
    q = np.repeat(q0[None, :], len(qv), axis=0)
    q[:, cspace] = qv
    for bp in grids:
        assert bp.grid is not None
        far = ~bp.grid.near(qv)
        assert far.mean() > 0.2
        # the sphere pairs the body pair samples (pairs that no joint moves are decided once)
        c = sphere_world_centers(kin, spheres, q[far])
        i, j = np.nonzero(bp.relevant())
        d = np.linalg.norm(c[:, bp.ia[i]] - c[:, bp.ib[j]], axis=-1)
        clr = d - spheres.self_radii[bp.ia[i]] - spheres.self_radii[bp.ib[j]]
        assert clr.min() > 0.01


def test_coarse_cells_least_gap_first_give_the_same_grids(monkeypatch: pytest.MonkeyPatch) -> None:
    """Splitting the coarse cells with the least gap first (the smallest far gap then skips
    most of the others' sphere pairs) gives the far cells and the clearance bound, to the
    last bit, of splitting them all at once."""
    import xrdf_tools.selfcollision.engine.grid as grid_mod

    kin, xrdf = panda()
    assert xrdf.cspace is not None
    cspace = [kin.actuated_index(j) for j in xrdf.cspace.joint_names]
    first, _, _ = engine_for(kin, xrdf, True, cspace, margin=0.01)
    monkeypatch.setattr(grid_mod, "_FIRST_BATCH", 1)  # one batch: every coarse cell at once
    at_once, _, _ = engine_for(kin, xrdf, True, cspace, margin=0.01)
    grids = [(a.grid, b.grid) for a, b in zip(first.pairs, at_once.pairs, strict=True) if a.grid]
    assert sum(len(a.shape) == 2 for a, _ in grids) >= 3
    for a, b in grids:
        assert b is not None
        np.testing.assert_array_equal(a.far, b.far)
        assert a.far_bound == b.far_bound


def _every_cell_far_2d(ev, shape, h):  # type: ignore[no-untyped-def]
    """The plain two-level decision: every coarse cell, then every fine cell of the coarse
    cells that are not far, each on all sphere pairs."""
    split = 4
    n0, n1 = shape
    c0, c1 = -(-n0 // split), -(-n1 // split)
    i0, i1 = np.divmod(np.arange(c0 * c1), c1)
    coarse = ev.far([i0, i1], h * split)
    far = np.zeros((c0 * split, c1 * split), dtype=np.bool_)
    far.reshape(c0, split, c1, split)[:] = coarse.reshape(c0, 1, c1, 1)
    todo = np.flatnonzero(~coarse)
    sub0, sub1 = np.divmod(np.arange(split * split), split)
    f0 = ((todo // c1)[:, None] * split + sub0[None, :]).ravel()
    f1 = ((todo % c1)[:, None] * split + sub1[None, :]).ravel()
    if len(todo):
        far[f0, f1] = ev.far([f0, f1], h)
    return np.ascontiguousarray(far[:n0, :n1]).ravel()


def test_grid_levels_decided_on_the_pairs_that_matter_equal_every_pair_everywhere(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Deciding a level only on the sphere pairs whose parent-cell gap is small gives the same
    far cells and the same clearance bound as deciding every cell on every pair."""
    import xrdf_tools.selfcollision.engine.grid as grid_mod

    kin, xrdf = panda()
    assert xrdf.cspace is not None
    cspace = [kin.actuated_index(j) for j in xrdf.cspace.joint_names]
    fast, _, _ = engine_for(kin, xrdf, True, cspace, margin=0.01)
    monkeypatch.setattr(grid_mod, "_far_2d", _every_cell_far_2d)
    plain, _, _ = engine_for(kin, xrdf, True, cspace, margin=0.01)
    grids = [(a.grid, b.grid) for a, b in zip(fast.pairs, plain.pairs, strict=True) if a.grid]
    two_joint = [(a, b) for a, b in grids if b is not None and len(b.shape) == 2]
    assert len(two_joint) >= 4
    assert any(not b.all_far for _, b in two_joint)  # the hand/link5 grid has near cells
    for a, b in grids:
        assert b is not None
        np.testing.assert_array_equal(a.far, b.far)
        assert a.far_bound == pytest.approx(b.far_bound, rel=1e-12, abs=1e-15)
