"""The engine's float64 second look and the sphere pairs it decides once.

* Forward kinematics and sphere placement give a configuration the same bits whichever
  configurations are computed with it (the exact values of a report must not depend on the
  batch around them).
* The sharpener's float64 values, composed along the tree path, agree with the reference pair
  test within its stated error, on real configurations.
* Sphere pairs that no joint moves (a centre on the axis of the joint between two bodies) are
  really constant, and the engine's totals still equal the brute force.
"""

from __future__ import annotations

import numpy as np
import pytest

from tests.selfcollision.test_collision import brute_force, fixed_configs, panda, three_link
from xrdf_tools.robot.kinematics import default_configuration, fk_batch_last
from xrdf_tools.selfcollision.collision import (
    build_sphere_set,
    frame_pair_verdicts,
    sphere_world_centers,
)
from xrdf_tools.selfcollision.engine import CountEngine, EngineTotals
from xrdf_tools.selfcollision.engine.layout import body_pairs
from xrdf_tools.selfcollision.engine.reach import Reach

EPS32 = float(np.finfo(np.float32).eps)


@pytest.mark.parametrize("width", [1, 2, 7, 64, 999])
def test_fk_bits_do_not_depend_on_the_batch(width: int) -> None:
    kin, xrdf = panda()
    q = fixed_configs(kin, 1000, seed=11)
    R, t = fk_batch_last(kin, q)
    spheres, _ = build_sphere_set(kin, xrdf, include_masked=True)
    centres = sphere_world_centers(kin, spheres, q)
    for start in (0, 1, 1000 - width):
        Rw, tw = fk_batch_last(kin, q[start : start + width])
        assert np.array_equal(Rw, R[..., start : start + width])
        assert np.array_equal(tw, t[..., start : start + width])
        cw = sphere_world_centers(kin, spheres, q[start : start + width])
        assert np.array_equal(cw, centres[start : start + width])


def _engine(kin, xrdf, margin=0.01):  # type: ignore[no-untyped-def]
    assert xrdf.cspace is not None
    varying = [kin.actuated_index(j) for j in xrdf.cspace.joint_names]
    spheres, _ = build_sphere_set(kin, xrdf, include_masked=True)
    q0 = default_configuration(kin, xrdf.default_joint_positions)
    return CountEngine(kin, spheres, varying, q0, margin=margin), spheres, q0, varying


@pytest.mark.parametrize("robot", [panda, three_link])
def test_sharpened_values_agree_with_the_reference(robot) -> None:  # type: ignore[no-untyped-def]
    kin, xrdf = robot()
    eng, spheres, q0, varying = _engine(kin, xrdf)
    q = fixed_configs(kin, 300, seed=5)
    rng = np.random.default_rng(0)
    ks = np.sort(rng.integers(0, spheres.n_frame_pairs, 3000))
    rows = rng.integers(0, len(q), len(ks))
    e_min, clear = eng.sharpener.evaluate(ks, q[rows][:, varying])
    q_full = np.repeat(q0[None, :], len(q), axis=0)
    q_full[:, varying] = q[:, varying]
    hit, ref = frame_pair_verdicts(kin, spheres, q_full, ks, rows)
    assert np.abs(clear - ref).max() <= eng.sharpener.tau
    sure = np.abs(e_min) > eng.sharpener.delta
    assert sure.mean() > 0.99
    np.testing.assert_array_equal(e_min[sure] < 0, hit[sure])
    # a loop over the sphere pairs of each entry gives the same values
    c = sphere_world_centers(kin, spheres, q_full)
    for e in range(0, len(ks), 97):
        i, j, rs = spheres.frame_pair_sphere_pairs(int(ks[e]))
        d = np.linalg.norm(c[rows[e], i] - c[rows[e], j], axis=1)
        assert abs(float((d - rs).min()) - clear[e]) <= eng.sharpener.tau


def test_sphere_pairs_on_a_joint_axis_are_constant_and_decided_once() -> None:
    kin, xrdf = panda()
    eng, spheres, q0, varying = _engine(kin, xrdf)
    layout = body_pairs(
        spheres,
        eng.frame_body,
        eng.local,
        eng.err,
        set(eng.const_k.tolist()),
        Reach.of(kin, eng.varying, eng.bodies),
        0.01,
    )
    assert len(layout.fixed_k) > 0  # the Panda has spheres centred on its joint axes
    q = np.repeat(q0[None, :], 60, axis=0)
    q[:, varying] = fixed_configs(kin, 60, seed=8)[:, varying]
    c = sphere_world_centers(kin, spheres, q)
    i, j = np.array(layout.fixed_i), np.array(layout.fixed_j)
    d = np.linalg.norm(c[:, i] - c[:, j], axis=-1)
    assert (d.max(axis=0) - d.min(axis=0)).max() < 1e-12
    # no fixed sphere pair is also sampled by a body pair
    sampled = set()
    for bp in eng.pairs:
        a, b = np.nonzero(bp.relevant())
        sampled |= {frozenset(p) for p in zip(bp.ia[a].tolist(), bp.ib[b].tolist(), strict=True)}
    fixed = {frozenset(p) for p in zip(i.tolist(), j.tolist(), strict=True)}
    assert not sampled & fixed
    # and the totals still equal the brute force
    totals = EngineTotals.empty(spheres.n_frame_pairs)
    hits = eng.count(q[:, varying], totals)
    _equal_to_brute_force(kin, xrdf, q, spheres, hits, totals)


def _equal_to_brute_force(kin, xrdf, q, spheres, hits, totals):  # type: ignore[no-untyped-def]
    """The engine's flags and exact clearances (below 1 cm) equal the brute force at ``q``
    (full configurations); returns the brute force's minimum clearances."""
    ref, ref_min, boundary = brute_force(kin, xrdf, q, include_masked=True)
    for k, (a, b) in enumerate(spheres.frame_pair_names()):
        key = frozenset((a, b))
        if key in boundary:
            continue
        np.testing.assert_array_equal(hits[k], ref[key], err_msg=f"{a}/{b}")
        if ref_min[key] < 0.01:
            assert totals.min_clearance[k] == pytest.approx(ref_min[key], abs=1e-12)
    return ref_min


@pytest.mark.parametrize("robot", [panda, three_link])
def test_path_local_float32_poses_stay_within_their_bound(robot) -> None:  # type: ignore[no-untyped-def]
    """Body pairs a joint or two apart compose their relative pose from those joints in
    float32; the centres of ``b`` in ``a``'s frame stay far within the pair's bound."""
    from xrdf_tools.selfcollision.engine.bodies import body_poses, joint_values
    from xrdf_tools.selfcollision.engine.pairs import ChunkPoses, pair_transform

    kin, xrdf = robot()
    eng, _, _, varying = _engine(kin, xrdf)
    q = fixed_configs(kin, 2000, seed=9)[:, varying]
    poses = ChunkPoses(eng.bodies, body_poses(eng.bodies, q), joint_values(eng.bodies, q))
    local = [bp for bp in eng.pairs if bp.path is not None]
    assert local
    for bp in local:
        T32 = pair_transform(bp, poses, None).astype(np.float64)  # [3, 4, n]
        R, t = eng.sharpener.relative(bp.a, bp.b, q)  # float64 [n, 3, 3], [n, 3]
        pb = eng.local[bp.ib]
        fast = np.einsum("ikn,mk->nmi", T32[:, :3], pb) + T32[:, 3].T[:, None, :]
        exact = np.einsum("nik,mk->nmi", R, pb) + t[:, None, :]
        assert np.abs(fast - exact).max() < bp.tau / 10
        assert bp.tau < 2 * eng.err + 8 * EPS32 * eng.bodies.lever  # tighter than the world


def test_a_sphere_just_off_a_joint_axis_ties_in_float32_and_is_narrowed_in_float64(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A sphere 0.2 µm off joint 1's axis, deep inside a base sphere off that axis: its clearance
    changes by far less than the float32 error as the joint turns, so every configuration
    ties for the minimum in float32. They are narrowed in float64 before the second look
    (which then sees a few entries, not every configuration), and the totals still equal
    the brute force."""
    from tests.paths import FIXTURES
    from tests.robots import robot_urdf
    from xrdf_tools.robot.kinematics import build_kinematic_model
    from xrdf_tools.robot.urdf_source import load_urdf
    from xrdf_tools.selfcollision.engine.sharpen import Sharpener
    from xrdf_tools.xrdf.io import parse_xrdf

    text = (FIXTURES / "panda" / "panda.xrdf").read_text()
    on_axis = "      panda_link0:\n        - center: [0.0, 0.0, 0.085]\n          radius: 0.03\n"
    off_axis = "      panda_link1:\n        - center: [2.0e-7, 0.0, -0.2]\n          radius: 0.15\n"
    assert on_axis in text and "      panda_link1:\n" in text
    text = text.replace(on_axis, "      panda_link0:\n", 1)  # keep the base's off-axis sphere
    xrdf = parse_xrdf(text.replace("      panda_link1:\n", off_axis, 1), "off_axis.xrdf")
    kin, _ = build_kinematic_model(load_urdf(robot_urdf("panda")), xrdf)
    eng, spheres, q0, varying = _engine(kin, xrdf)
    seen: list[int] = []
    evaluate = Sharpener.evaluate

    def counting(self: Sharpener, ks: np.ndarray, q: np.ndarray):  # type: ignore[no-untyped-def]
        seen.append(len(ks))
        return evaluate(self, ks, q)

    monkeypatch.setattr(Sharpener, "evaluate", counting)
    n = 1500
    q = np.repeat(q0[None, :], n, axis=0)
    q[:, varying] = fixed_configs(kin, n, seed=21)[:, varying]
    totals = EngineTotals.empty(spheres.n_frame_pairs)
    hits = eng.count(q[:, varying], totals)
    assert sum(seen) < n // 4  # without the float64 narrowing: every configuration
    ref_min = _equal_to_brute_force(kin, xrdf, q, spheres, hits, totals)
    k01 = list(spheres.frame_pair_names()).index(("panda_link0", "panda_link1"))
    assert ref_min[frozenset(("panda_link0", "panda_link1"))] < -0.05  # deep inside
    assert totals.min_clearance[k01] <= totals.clearance_bound[k01]  # exact, not a bound
