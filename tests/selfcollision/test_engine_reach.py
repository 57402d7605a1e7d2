"""The reach step's build-time proofs, checked against sampled configurations.

:mod:`xrdf_tools.selfcollision.engine.reach` drops sphere pairs that can never come within the
margin, with a lower bound of their gap. A body sliding on a prismatic joint sweeps segments;
a body two revolute joints below another keeps its ``(ρ, z)`` curve about the outer axis. On
PR2 (a prismatic torso under the right arm, seeded spheres on every link) every gap these
proofs claim must be at most the smallest gap seen in many configurations, and the segment's
(exact) gap must be reached closely; the engine's counts still equal the reference counter.
"""

from __future__ import annotations

import numpy as np
import pytest

from tests.collision_reference import count_chunk
from tests.robots import robot_urdf
from tests.selfcollision.test_engine import engine_for
from xrdf_tools.robot.kinematics import KinematicModel, build_kinematic_model
from xrdf_tools.robot.urdf_source import load_urdf
from xrdf_tools.selfcollision.collision import SphereSet, sphere_world_centers
from xrdf_tools.selfcollision.engine import CountEngine
from xrdf_tools.selfcollision.engine.bodies import PRISM, ROT
from xrdf_tools.selfcollision.engine.reach import Reach
from xrdf_tools.xrdf.io import parse_xrdf
from xrdf_tools.xrdf.model import Xrdf

CSPACE = ["torso_lift_joint"] + [
    f"r_{j}_joint"
    for j in (
        "shoulder_pan",
        "shoulder_lift",
        "upper_arm_roll",
        "elbow_flex",
        "forearm_roll",
        "wrist_flex",
        "wrist_roll",
    )
]
LINKS = [
    "base_link",
    "torso_lift_link",
    "r_shoulder_pan_link",
    "r_shoulder_lift_link",
    "r_upper_arm_roll_link",
    "r_upper_arm_link",
    "r_elbow_flex_link",
    "r_forearm_roll_link",
    "r_forearm_link",
    "r_wrist_flex_link",
    "r_wrist_roll_link",
]


def _xrdf() -> str:
    rng = np.random.default_rng(19)
    n = len(CSPACE)
    lines = [
        "format: xrdf",
        "format_version: 1.0",
        "cspace:",
        f"  joint_names: [{', '.join(CSPACE)}]",
        f"  acceleration_limits: [{', '.join(['10.0'] * n)}]",
        f"  jerk_limits: [{', '.join(['100.0'] * n)}]",
        "collision:",
        "  geometry: body",
        "self_collision:",
        "  geometry: body",
        "geometry:",
        "  body:",
        "    spheres:",
    ]
    for name in LINKS:
        lines.append(f"      {name}:")
        for _ in range(6):
            c = rng.uniform(-0.25, 0.25, 3)
            r = rng.uniform(0.01, 0.05)
            lines.append(
                f"        - {{center: [{c[0]:.4f}, {c[1]:.4f}, {c[2]:.4f}], radius: {r:.4f}}}"
            )
    return "\n".join(lines) + "\n"


@pytest.fixture(scope="module")
def pr2_arm() -> tuple[KinematicModel, Xrdf, CountEngine, SphereSet, np.ndarray]:
    urdf = load_urdf(robot_urdf("pr2"))
    xrdf = parse_xrdf(_xrdf(), "pr2_right_arm.xrdf")
    kin, _ = build_kinematic_model(urdf, xrdf)
    varying = [kin.actuated_index(j) for j in CSPACE]
    eng, spheres, q0 = engine_for(kin, xrdf, True, varying, margin=0.01)
    rng = np.random.default_rng(5)
    q = np.repeat(q0[None, :], 20000, axis=0)
    q[:, varying] = rng.uniform(kin.lower[varying], kin.upper[varying], (20000, len(varying)))
    # the ends of every joint's range too (a segment's ends, an arc's ends)
    q[:2000, varying] = np.where(rng.random((2000, len(varying))) < 0.5, 0.0, 1.0)
    q[:2000, varying] = kin.lower[varying] + q[:2000, varying] * (
        kin.upper[varying] - kin.lower[varying]
    )
    return kin, xrdf, eng, spheres, q


def _sampled_gaps(
    kin: KinematicModel, spheres: SphereSet, q: np.ndarray, ia: np.ndarray, ib: np.ndarray
) -> np.ndarray:
    """Smallest gap [len(ia), len(ib)] of each sphere pair over the configurations ``q``."""
    r = spheres.self_radii
    out = np.full((len(ia), len(ib)), np.inf)
    for s0 in range(0, len(q), 2000):
        c = sphere_world_centers(kin, spheres, q[s0 : s0 + 2000])
        d = np.linalg.norm(c[:, ia, None, :] - c[:, None, ib, :], axis=-1)
        np.minimum(out, d.min(axis=0) - (r[ia, None] + r[None, ib]), out=out)
    return out


def _cases(eng: CountEngine) -> list[tuple[str, int, int]]:
    """(proof, ancestor body, descendant body) of every body pair a new proof applies to."""
    b = eng.bodies
    out = []
    for d in range(1, b.n):
        top = d
        if b.kind[d] == PRISM:
            out.append(("segment", b.parent[d], d))
        elif b.parent[d] > 0 and b.kind[b.parent[d]] == ROT:
            top = b.parent[d]
            out.append(("swept", b.parent[top], d))
    return out


def test_segment_and_swept_gaps_never_exceed_what_configurations_reach(pr2_arm) -> None:  # type: ignore[no-untyped-def]
    kin, _, eng, spheres, q = pr2_arm
    reach = Reach.of(kin, eng.varying, eng.bodies)
    cases = _cases(eng)
    assert {c for c, _, _ in cases} == {"segment", "swept"}
    r = spheres.self_radii
    for proof, anc, desc in cases:
        ia = np.flatnonzero(eng.sphere_body == anc)
        ib = np.flatnonzero(eng.sphere_body == desc)
        xa, xb = eng.local[ia], eng.local[ib]
        if proof == "segment":
            g_a, g_b = reach._segments(desc, xa, r[ia], xb, r[ib])
        else:
            g_a, g_b = reach._swept(eng.bodies.parent[desc], desc, xa, r[ia], xb, r[ib])
        seen = _sampled_gaps(kin, spheres, q, ia, ib)
        assert np.all(g_a <= seen.min(axis=1) + 1e-9), (proof, anc, desc)
        assert np.all(g_b <= seen.min(axis=0) + 1e-9), (proof, anc, desc)
        if proof == "segment":  # exact: the sampled travel comes within a few mm of it
            assert np.all(seen.min(axis=1) - g_a < 0.005)
        # never NaN, and tighter than a ball around the joint for some spheres
        assert not np.isnan(g_a).any() and not np.isnan(g_b).any()
        centre, ext = reach._ball(desc if proof == "segment" else eng.bodies.parent[desc], desc)
        u = np.linalg.norm(xa - centre, axis=1) - r[ia]
        ball_b = u.min() - (np.linalg.norm(xb, axis=1) + r[ib] + ext)
        assert np.any(g_b > ball_b + 0.01), (proof, anc, desc)  # (the reach step takes both)
        if proof == "segment":
            assert np.all(g_b >= ball_b - 1e-9)


def test_pruned_engine_counts_equal_the_reference_counter(pr2_arm) -> None:  # type: ignore[no-untyped-def]
    kin, _, eng, spheres, q = pr2_arm
    ref = count_chunk(kin, spheres, q[:3000], margin=0.01)
    hits = eng.count(q[:3000, eng.varying])
    np.testing.assert_array_equal(hits, ref.hits)
    assert 0 < hits.sum() < hits.size
    assert np.isfinite(eng.reach_bound).any()  # some sphere pairs were dropped
