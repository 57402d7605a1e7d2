"""The engine's vectorised steps against plain loops, on real robots.

* per-sphere-pair minima of ``d² − R²`` and per-sphere-pair clearances (the minimum-clearance
  candidates) against a float64 loop over configurations and sphere pairs;
* culled body pairs tested as a group (one side against a sphere around the others) against
  the same pairs tested one by one: the same configurations within reach, bounds no higher;
* the exact minima found in earlier chunks (``known``) narrow the work, not the totals;
* the two-joint cell grids' fine cells when no sphere pair is left to look at.
"""

from __future__ import annotations

import numpy as np
import pytest

from tests.collision_reference import count_chunk
from tests.selfcollision.test_collision import fixed_configs, panda
from tests.selfcollision.test_engine import engine_for
from tests.selfcollision.test_engine_static import ARM, talos_left_arm
from xrdf_tools.robot.kinematics import KinematicModel
from xrdf_tools.selfcollision.collision import sphere_world_centers
from xrdf_tools.selfcollision.engine import EngineTotals, count_sampled
from xrdf_tools.selfcollision.engine import cullgroups as cullgroups_mod
from xrdf_tools.selfcollision.engine import culling as culling_mod
from xrdf_tools.selfcollision.engine.bodies import body_poses, joint_values
from xrdf_tools.selfcollision.engine.pairs import (
    ChunkPoses,
    pair_transform,
    sphere_pair_clearances,
    sphere_pair_minima,
)
from xrdf_tools.xrdf.model import Xrdf


def _panda_engine():  # type: ignore[no-untyped-def]
    kin, xrdf = panda()
    assert xrdf.cspace is not None
    cspace = [kin.actuated_index(j) for j in xrdf.cspace.joint_names]
    eng, spheres, q0 = engine_for(kin, xrdf, True, cspace, margin=0.01)
    return kin, eng, spheres, q0, cspace


def _world_pairs(kin, spheres, q0, cspace, qv, ia, ib):  # type: ignore[no-untyped-def]
    """float64 ``d²`` [n, len(ia), len(ib)] of sphere pairs by a loop over configurations."""
    out = np.empty((len(qv), len(ia), len(ib)))
    for n, row in enumerate(qv):
        q = q0.copy()
        q[cspace] = row
        c = sphere_world_centers(kin, spheres, q)
        for x, i in enumerate(ia.tolist()):
            for y, j in enumerate(ib.tolist()):
                out[n, x, y] = float(np.sum((c[i] - c[j]) ** 2))
    return out


def test_sphere_pair_minima_and_clearances_equal_a_loop() -> None:
    kin, eng, spheres, q0, cspace = _panda_engine()
    qv = fixed_configs(kin, 40, seed=21)[:, cspace]
    poses = ChunkPoses(eng.bodies, body_poses(eng.bodies, qv), joint_values(eng.bodies, qv))
    r = spheres.self_radii
    checked = 0
    for bp in eng.pairs:
        trel = pair_transform(bp, poses, None)
        d2 = _world_pairs(kin, spheres, q0, cspace, qv, bp.ia, bp.ib)
        rsum = r[bp.ia][:, None] + r[bp.ib][None, :]
        for _, rows, cols in bp.blocks:
            got = sphere_pair_minima(bp, trel, rows, cols)
            want = (d2[:, rows, cols] - rsum[rows, cols] ** 2).min(axis=0)
            near = want < (rsum[rows, cols] + 0.05) ** 2  # where the error bound holds
            assert np.all(np.abs(got - want)[near] <= bp.delta), (bp.a, bp.b)
            ii, jj = np.nonzero(np.ones_like(want, dtype=np.bool_))
            clr = sphere_pair_clearances(bp, trel, ii + rows.start, jj + cols.start)
            want_c = np.sqrt(d2[:, rows, cols][:, ii, jj]) - rsum[rows, cols][ii, jj]
            assert np.abs(clr - want_c.T).max() <= bp.tau, (bp.a, bp.b)
            checked += 1
    assert checked >= 10


def test_known_minima_narrow_the_work_not_the_totals() -> None:
    kin, eng, _, _, cspace = _panda_engine()
    lo, hi = kin.lower[cspace], kin.upper[cspace]
    fresh = EngineTotals.empty(eng.K)
    carried = EngineTotals.empty(eng.K)
    known = np.full(eng.K, np.inf)
    rows = fixed_configs(kin, 6000, seed=8)[:, cspace]
    rows = np.clip(rows, lo, hi)
    for q in np.array_split(rows, 6):
        alone = EngineTotals.empty(eng.K)
        eng.count(q, alone)
        fresh.merge(alone)
        part = EngineTotals.empty(eng.K)
        eng.count(q, part, known=known)
        np.minimum(known, part.min_clearance, out=known)
        carried.merge(part)
    np.testing.assert_array_equal(fresh.hits, carried.hits)
    for a, b in zip(fresh.clearance(), carried.clearance(), strict=True):
        np.testing.assert_array_equal(a, b)
    assert carried.rechecked < fresh.rechecked  # fewer float64 looks for the same answer
    # count_sampled carries them from chunk to chunk
    one = count_sampled(eng, lo, hi, 6000, method="uniform", seed=1, chunk=1000)
    big = count_sampled(eng, lo, hi, 6000, method="uniform", seed=1, chunk=6000)
    np.testing.assert_array_equal(one.hits, big.hits)
    exact_one, bound_one = one.clearance()
    exact_big, bound_big = big.clearance()
    np.testing.assert_array_equal(exact_one[~bound_one], exact_big[~bound_big])


@pytest.fixture(scope="module")
def talos_split() -> tuple[KinematicModel, Xrdf]:
    """Talos, left arm as the c-space, with enough spheres on the hand that it is cut into
    its frames: culled body pairs share a side (each frame of the static rest)."""
    return talos_left_arm(7)


def test_grouped_culling_equals_pair_by_pair(
    talos_split: tuple[KinematicModel, Xrdf], monkeypatch: pytest.MonkeyPatch
) -> None:
    kin, xrdf = talos_split
    arm = [kin.actuated_index(j) for j in ARM]
    monkeypatch.setattr(culling_mod, "_GROUP_MIN", 2)
    eng, spheres, q0 = engine_for(kin, xrdf, True, arm, margin=0.01)
    plan = eng.cull_plan
    assert plan.table is not None
    assert len(plan.sides) >= 5 and len(plan.table.row) >= 30
    monkeypatch.setattr(culling_mod, "_GROUP_MIN", 10**9)
    single = eng.culler.plan(list(plan.pairs))
    assert single.table is None
    qv = fixed_configs(kin, 3000, seed=12)[:, arm]
    T = body_poses(eng.bodies, qv)
    near_g, low_g = eng.culler.culled_near(plan, T[:, :, :3], T[:, :, 3])
    near_s, low_s = eng.culler.culled_near(single, T[:, :, :3], T[:, :, 3])
    assert 0 < near_s.sum() < near_s.size
    np.testing.assert_array_equal(near_g, near_s)
    # a group's bound is a lower bound of the one of testing every pair everywhere (up to the
    # float32 rounding of the placed centres), and still says "farther than the margin"
    assert np.all(low_g <= low_s + 1e-6)
    assert np.all(low_g > 0.01)
    assert np.mean(np.isclose(low_g, low_s, rtol=0, atol=1e-6)) > 0.5  # most: their own gaps
    # the members are tested in blocks of bounded memory: the same result block by block
    monkeypatch.setattr(cullgroups_mod, "_BLOCK", 64)
    near_b, low_b = eng.culler.culled_near(plan, T[:, :, :3], T[:, :, 3])
    np.testing.assert_array_equal(near_b, near_g)
    np.testing.assert_array_equal(low_b, low_g)
    # and the counts of the engine with groups equal the reference counter's
    q = np.repeat(q0[None, :], len(qv), axis=0)
    q[:, arm] = qv
    ref = count_chunk(kin, spheres, q, margin=0.01)
    np.testing.assert_array_equal(eng.count(qv), ref.hits)


def test_fine_cells_with_no_sphere_pair_left_are_far() -> None:
    """A coarse cell whose every sphere pair is farther than the smallest far gap seen: its
    fine cells are all far without computing a distance."""
    from xrdf_tools.selfcollision.engine.grid import _CellTest

    consts = [np.eye(4), np.eye(4)]
    consts[1][:3, 3] = [0.3, 0.0, 0.0]
    ev = _CellTest(
        consts,
        np.array([-1.0, -1.0]),
        np.array([[0.1, 0.0, 0.0]]),
        np.array([[5.0, 0.0, 0.0]]),
        np.array([[0.05]]),
        np.ones((1, 1), dtype=np.bool_),
        [np.array([0.4]), np.array([0.1])],
        [-np.inf],  # nothing can be nearer than the smallest far gap
    )
    far = ev.split_far([np.array([0, 1]), np.array([0, 0])], np.array([0.01, 0.01]), (8, 8))
    assert far.shape == (2, 16) and far.all()


@pytest.mark.parametrize("block", [1 << 16, 7])
def test_reference_verdicts_equal_a_loop_to_the_last_bit(
    block: int, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The float64 reference verdicts (every sphere pair of every entry in one flat pass;
    with blocks of 7 sphere pairs, entries spread over several blocks) against a loop over
    entries and sphere pairs on the centres of ``sphere_world_centers``: the same bits (the
    report's exact minima are these values)."""
    from xrdf_tools.selfcollision.collision import distances, frame_pair_verdicts, touching

    monkeypatch.setattr(distances, "_PAIR_BLOCK", block)
    kin, _, spheres, q0, cspace = _panda_engine()
    q = np.repeat(q0[None, :], 30, axis=0)
    q[:, cspace] = fixed_configs(kin, 30, seed=31)[:, cspace]
    rng = np.random.default_rng(4)
    ks = rng.integers(0, spheres.n_frame_pairs, 400)
    rows = rng.integers(0, len(q), 400)
    hit, clr = frame_pair_verdicts(kin, spheres, q, ks, rows)
    centres = sphere_world_centers(kin, spheres, q)
    for e, (k, row) in enumerate(zip(ks.tolist(), rows.tolist(), strict=True)):
        i, j, rs = spheres.frame_pair_sphere_pairs(k)
        diff = centres[row, i] - centres[row, j]
        d2 = np.einsum("...k,...k->...", diff, diff)
        assert hit[e] == touching(d2, rs).any()
        assert clr[e] == (np.sqrt(d2) - rs).min()
    assert 0 < hit.sum() < len(hit)


def test_second_look_few_entries_together_equals_one_by_one(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    from xrdf_tools.selfcollision.engine import sharpen as sharpen_mod

    kin, eng, spheres, q0, cspace = _panda_engine()
    rng = np.random.default_rng(6)
    ks = np.sort(rng.integers(0, spheres.n_frame_pairs, 300))
    qv = fixed_configs(kin, 300, seed=33)[:, cspace]
    monkeypatch.setattr(sharpen_mod, "_MANY", 1)  # every frame pair on its own
    e_one, c_one = eng.sharpener.evaluate(ks, qv)
    monkeypatch.setattr(sharpen_mod, "_MANY", 10**9)  # all in the flat pass
    e_flat, c_flat = eng.sharpener.evaluate(ks, qv)
    np.testing.assert_allclose(e_flat, e_one, rtol=0, atol=1e-12)
    np.testing.assert_allclose(c_flat, c_one, rtol=0, atol=1e-12)
    # and both within the sharpener's error of the reference
    from xrdf_tools.selfcollision.collision import frame_pair_verdicts

    q = np.repeat(q0[None, :], len(qv), axis=0)
    q[:, cspace] = qv
    _, ref = frame_pair_verdicts(kin, spheres, q, ks, np.arange(len(ks)))
    assert np.abs(c_flat - ref).max() <= eng.sharpener.tau
