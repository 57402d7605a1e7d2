"""Collision semantics: vectorized counts equal a brute-force double loop over spheres."""

from __future__ import annotations

import math

import numpy as np
import pytest

from tests.collision_reference import count_chunk
from tests.paths import FIXTURES
from tests.robots import robot_urdf
from xrdf_tools.robot.kinematics import KinematicModel, build_kinematic_model, fk
from xrdf_tools.robot.urdf_source import load_urdf
from xrdf_tools.selfcollision.collision import (
    build_sphere_set,
    colliding_frame_pairs,
    pair_clearance,
    sphere_world_centers,
)
from xrdf_tools.xrdf.io import load_xrdf, parse_xrdf
from xrdf_tools.xrdf.model import Xrdf

THREE_LINK = FIXTURES / "urdf" / "three_link_mimic.urdf"

# Spheres on every frame of the three-link fixture (revolute, continuous, prismatic, mimic,
# fixed), buffers on two frames, a placeholder, a mask with an unknown name.
THREE_LINK_XRDF = """\
format: xrdf
format_version: 1.0
cspace:
  joint_names: [joint1, joint2, joint3]
  acceleration_limits: [10.0, 10.0, 10.0]
  jerk_limits: [100.0, 100.0, 100.0]
default_joint_positions: {joint1: 0.0, joint2: 0.0, joint3: 0.1}
collision:
  geometry: arm
self_collision:
  geometry: arm
  buffer_distance: {link1: 0.01, tool: 0.02}
  ignore:
    base_link: [link1]
    link3: [finger, no_such_frame]
geometry:
  arm:
    spheres:
      base_link:
        - {center: [0.0, 0.0, 0.05], radius: 0.08}
      link1:
        - {center: [0.15, 0.0, 0.05], radius: 0.05}
        - {center: [0.3, 0.0, 0.05], radius: 0.05}
      link2:
        - {center: [0.06, 0.0, 0.0], radius: 0.05}
        - {center: [0.2, 0.0, 0.0], radius: 0.05}
      link3:
        - {center: [0.05, 0.0, 0.0], radius: 0.04}
      finger:
        - {center: [0.03, 0.0, 0.0], radius: 0.03}
        - {center: [0.0, 0.0, 0.0], radius: -0.01}
        - {center: [0.0, 0.0, 0.0], radius: -10.0}
      tool:
        - {center: [0.0, 0.0, 0.0], radius: 0.045}
      ghost_link:
        - {center: [0.0, 0.0, 0.0], radius: 0.04}
"""


def three_link() -> tuple[KinematicModel, Xrdf]:
    xrdf = parse_xrdf(THREE_LINK_XRDF, "three_link.xrdf")
    kin, _ = build_kinematic_model(load_urdf(THREE_LINK), xrdf)
    return kin, xrdf


def panda() -> tuple[KinematicModel, Xrdf]:
    xrdf = load_xrdf(FIXTURES / "panda" / "panda.xrdf")
    kin, _ = build_kinematic_model(load_urdf(robot_urdf("panda")), xrdf)
    return kin, xrdf


def brute_force(
    kin: KinematicModel, xrdf: Xrdf, q: np.ndarray, *, include_masked: bool
) -> tuple[dict[frozenset[str], np.ndarray], dict[frozenset[str], float], set[frozenset[str]]]:
    """Per frame pair: colliding flags [B] and min clearance, by a plain double loop.

    Also returns the frame pairs with a sphere pair within 1e-9 m of the collision boundary
    in some configuration (there the verdict is decided by float rounding).
    """
    sc = xrdf.self_collision
    assert sc is not None
    poses = fk(kin, q)  # [B, F, 4, 4]
    spheres = []
    for frame, sph in xrdf.self_collision_spheres().items():
        if not kin.has_frame(frame):
            continue
        f = kin.frame_index(frame)
        for s in sph:
            if s.radius < 0:
                continue
            spheres.append((frame, f, s.center, s.radius + sc.buffer_distance.get(frame, 0.0)))
    hits: dict[frozenset[str], np.ndarray] = {}
    min_clear: dict[frozenset[str], float] = {}
    boundary: set[frozenset[str]] = set()
    for b in range(q.shape[0]):
        world = [
            tuple(poses[b, f, :3, :3] @ np.array(c) + poses[b, f, :3, 3]) for _, f, c, _ in spheres
        ]
        for i in range(len(spheres)):
            for j in range(i + 1, len(spheres)):
                fa, fb = spheres[i][0], spheres[j][0]
                if fa == fb or (sc.is_ignored(fa, fb) and not include_masked):
                    continue
                key = frozenset((fa, fb))
                d = math.dist(world[i], world[j])
                reach = spheres[i][3] + spheres[j][3]
                if abs(d - reach) < 1e-9:
                    boundary.add(key)
                flags = hits.setdefault(key, np.zeros(q.shape[0], dtype=bool))
                flags[b] |= d < reach
                min_clear[key] = min(min_clear.get(key, math.inf), d - reach)
    return hits, min_clear, boundary


def fixed_configs(kin: KinematicModel, n: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    lo, hi = kin.lower.copy(), kin.upper.copy()
    q = rng.uniform(lo, hi, size=(n, kin.n_actuated))
    # continuous joints also well outside [-pi, pi]
    q[:, kin.continuous] *= 3.0
    return q


def check_counts(kin: KinematicModel, xrdf: Xrdf, q: np.ndarray, include_masked: bool) -> int:
    spheres, _ = build_sphere_set(kin, xrdf, include_masked=include_masked)
    ref, ref_min, boundary = brute_force(kin, xrdf, q, include_masked=include_masked)
    # only panda's masked link1/link2 has two spheres exactly touching (constant distance)
    assert len(boundary) <= int(include_masked)
    res = count_chunk(kin, spheres, q, margin=0.05)
    names = list(spheres.frame_pair_names())
    assert {frozenset(p) for p in names} == set(ref)
    total = 0
    for k, (a, b) in enumerate(names):
        if frozenset((a, b)) in boundary:
            continue
        np.testing.assert_array_equal(res.hits[k], ref[frozenset((a, b))], err_msg=f"{a}/{b}")
        total += int(res.hits[k].sum())
        true_min = ref_min[frozenset((a, b))]
        if res.min_clearance[k] <= res.clearance_bound[k]:
            assert res.min_clearance[k] == pytest.approx(true_min, abs=1e-12)
        else:
            assert res.clearance_bound[k] <= true_min + 1e-12
        if true_min < 0.05:  # within the margin the minimum is always exact
            assert res.min_clearance[k] == pytest.approx(true_min, abs=1e-12)
    return total


@pytest.mark.parametrize("include_masked", [False, True])
def test_counts_equal_brute_force_three_link(include_masked: bool) -> None:
    kin, xrdf = three_link()
    q = fixed_configs(kin, 300, seed=1)
    total = check_counts(kin, xrdf, q, include_masked)
    assert 0 < total < 300 * 10  # some collisions, not everything


@pytest.mark.parametrize("include_masked", [False, True])
def test_counts_equal_brute_force_panda(include_masked: bool) -> None:
    kin, xrdf = panda()
    q = fixed_configs(kin, 60, seed=7)
    assert check_counts(kin, xrdf, q, include_masked) > 0


def test_chunking_does_not_change_counts() -> None:
    kin, xrdf = three_link()
    spheres, _ = build_sphere_set(kin, xrdf)
    q = fixed_configs(kin, 500, seed=3)
    whole = count_chunk(kin, spheres, q).hits
    parts = np.concatenate(
        [count_chunk(kin, spheres, q[i : i + 97]).hits for i in range(0, 500, 97)], axis=1
    )
    np.testing.assert_array_equal(whole, parts)


def test_sphere_set_structure() -> None:
    kin, xrdf = three_link()
    spheres, diags = build_sphere_set(kin, xrdf)
    # the attached-object slot (-10) dropped, the small negative radius kept as a 1 mm sphere
    # (cuRobo clamps a buffered radius in (-1, 0] to 1 mm), ghost_link reported
    assert spheres.n_placeholders == 1
    assert spheres.sphere_counts() == {
        "base_link": 1,
        "link1": 2,
        "link2": 2,
        "link3": 1,
        "finger": 2,
        "tool": 1,
    }
    finger = spheres.spheres_of(spheres.frame_names.index("finger"))
    np.testing.assert_allclose(spheres.self_radii[finger], [0.03, 0.001])
    assert [d.rule for d in diags] == ["sphere-frame-unknown"]
    assert "ghost_link" in diags[0].message and diags[0].line is not None
    # buffers go into the self-collision radii only
    link1 = spheres.spheres_of(spheres.frame_names.index("link1"))
    np.testing.assert_allclose(spheres.radii[link1], [0.05, 0.05])
    np.testing.assert_allclose(spheres.self_radii[link1], [0.06, 0.06])
    # masked frame pairs are absent (either direction), and no pair is on one frame
    pairs = {frozenset(p) for p in spheres.frame_pair_names()}
    assert frozenset(("base_link", "link1")) not in pairs
    assert frozenset(("link3", "finger")) not in pairs
    assert np.all(
        spheres.frame_of_sphere[spheres.pair_i] != spheres.frame_of_sphere[spheres.pair_j]
    )
    counts = np.bincount(spheres.pair_frame_pair, minlength=spheres.n_frame_pairs)
    np.testing.assert_array_equal(counts, np.diff(spheres.pair_start))
    masked, _ = build_sphere_set(kin, xrdf, include_masked=True)
    assert masked.n_frame_pairs == spheres.n_frame_pairs + 2
    assert int(masked.frame_pair_masked.sum()) == 2


def test_pair_clearance_matches_sphere_distance() -> None:
    kin, xrdf = three_link()
    spheres, _ = build_sphere_set(kin, xrdf)
    q = fixed_configs(kin, 5, seed=2)
    c = sphere_world_centers(kin, spheres, q)
    assert c.shape == (5, spheres.n_spheres, 3)
    clr = pair_clearance(spheres, c)
    i, j = int(spheres.pair_i[0]), int(spheres.pair_j[0])
    expect = (
        np.linalg.norm(c[:, i] - c[:, j], axis=1) - spheres.self_radii[i] - spheres.self_radii[j]
    )
    np.testing.assert_allclose(clr[:, 0], expect)


def test_colliding_frame_pairs_at_one_configuration() -> None:
    kin, xrdf = three_link()
    # folded back: link2 swings over link1 and the base
    found = None
    for q in fixed_configs(kin, 200, seed=5):
        cs = colliding_frame_pairs(kin, xrdf, q)
        if len(cs) >= 2:
            found = (q, cs)
            break
    assert found is not None
    q, cs = found
    assert [c.clearance for c in cs] == sorted(c.clearance for c in cs)
    assert all(c.clearance < 0 and not c.masked for c in cs)
    ref, _, boundary = brute_force(kin, xrdf, q[None, :], include_masked=False)
    assert not boundary
    assert {frozenset((c.frame_a, c.frame_b)) for c in cs} == {k for k, v in ref.items() if v[0]}
    # masked pairs appear only when asked for
    with_masked = colliding_frame_pairs(kin, xrdf, q, include_masked=True)
    assert len(with_masked) >= len(cs)
