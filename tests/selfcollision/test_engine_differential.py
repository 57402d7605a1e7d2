"""The report's counts and clearances against the reference counter on small robots written
here: shapes of c-space and mask that the real robots of the other tests do not have.

Each case runs :func:`xrdf_tools.report.self_collision_report` and the plain float64 counter
:func:`tests.collision_reference.count_chunk` on the same sampled configurations and compares,
per frame pair, the collision count and the minimum clearance (exact below the margin, a lower
bound above it).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from tests.collision_reference import count_chunk
from tests.sphere_xrdf import Spheres, sphere_xrdf
from xrdf_tools.report import Report, self_collision_report
from xrdf_tools.report.results import ConfigsError
from xrdf_tools.robot.binding import cspace_indices
from xrdf_tools.robot.kinematics import build_kinematic_model, default_configuration
from xrdf_tools.robot.urdf_source import load_urdf
from xrdf_tools.selfcollision.collision import build_sphere_set
from xrdf_tools.selfcollision.sampling import sample_rows
from xrdf_tools.xrdf.io import parse_xrdf

MARGIN = 0.01


#: frame -> spheres (x, y, z, radius)
def _joint(
    name: str, kind: str, parent: str, child: str, xyz: str, extra: str = "", rpy: str = "0 0 0"
) -> str:
    return (
        f'<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>'
        f'<origin xyz="{xyz}" rpy="{rpy}"/>{extra}</joint>'
    )


def _revolute(axis: str = "0 1 0", lo: float = -3.0, hi: float = 3.0) -> str:
    return f'<axis xyz="{axis}"/><limit lower="{lo}" upper="{hi}" effort="1" velocity="1"/>'


def _urdf(tmp_path: Path, links: list[str], joints: list[str]) -> Path:
    path = tmp_path / "robot.urdf"
    body = "".join(f'<link name="{n}"/>' for n in links) + "".join(joints)
    path.write_text(f'<?xml version="1.0"?><robot name="r">{body}</robot>\n')
    return path


def report_against_reference(
    urdf_path: Path, xrdf_text: str, samples: int, seed: int = 0, **options: object
) -> Report:
    """The report of ``samples`` configurations, checked pair by pair against the reference
    counter on the same configurations."""
    urdf = load_urdf(urdf_path)
    xrdf = parse_xrdf(xrdf_text, "robot.xrdf")
    report = self_collision_report(
        urdf,
        xrdf,
        samples=samples,
        seed=seed,
        clearance_margin=MARGIN,
        **options,  # type: ignore[arg-type]
    )
    kin, _ = build_kinematic_model(urdf, xrdf)
    spheres, _ = build_sphere_set(kin, xrdf, include_masked=True)
    _, idx = cspace_indices(kin, xrdf)
    q = np.repeat(default_configuration(kin, xrdf.default_joint_positions)[None], samples, 0)
    q[:, idx] = sample_rows(kin.lower[idx], kin.upper[idx], 0, samples, method="uniform", seed=seed)
    ref = count_chunk(kin, spheres, q, margin=MARGIN)
    stats = {(p.frame_a, p.frame_b): p for p in report.pairs}
    for k, name in enumerate(spheres.frame_pair_names()):
        pair = stats[name]
        if not pair.sampled:
            continue
        assert pair.hits == int(ref.hits[k].sum()), name
        true_min = float(ref.min_clearance[k])
        assert pair.min_clearance is not None, name
        if true_min <= ref.clearance_bound[k] and true_min < MARGIN:  # exact below the margin
            assert not pair.min_clearance_is_bound, name
            assert pair.min_clearance == pytest.approx(true_min, abs=1e-12), name
        elif true_min <= ref.clearance_bound[k]:
            assert pair.min_clearance <= true_min + 1e-12, name
    return report


def test_a_two_joint_grid_whose_body_pair_holds_an_unsampled_frame_pair(tmp_path: Path) -> None:
    """base/l2 are adjacent and masked (never sampled), but base/tool and b2/l2 are sampled:
    the body pair of the static base (base, b2) and the hand (l2, tool) holds sphere pairs
    that are not counted. They must neither make every cell of its two-joint grid far (the
    grid then skipped every configuration: base/tool "never" against 1,555 hits) nor give
    the grid a clearance bound of −inf."""
    path = _urdf(
        tmp_path,
        ["base", "l1", "l2", "tool", "b2"],
        [
            _joint("j1", "revolute", "base", "l1", "0 0 0.1", _revolute()),
            _joint("j2", "revolute", "l1", "l2", "0 0 0.3", _revolute()),
            _joint("jt", "fixed", "l2", "tool", "0 0 0.3"),
            _joint("jb", "fixed", "base", "b2", "0.3 0 0"),
        ],
    )
    spheres: Spheres = {
        "base": [(0, 0, 0, 0.08)],
        "l2": [(0, 0, 0.1, 0.04)],
        "b2": [(0, 0, 0, 0.05)],
        "tool": [(0, 0, 0, 0.05)],
    }
    report = report_against_reference(
        path, sphere_xrdf(["j1", "j2"], spheres, {"base": ["l2"]}), 20_000
    )
    tool = next(p for p in report.pairs if {p.frame_a, p.frame_b} == {"base", "tool"})
    assert tool.hits and tool.classification == "sometimes"


def test_a_one_joint_grid_whose_body_pair_holds_an_unsampled_frame_pair(tmp_path: Path) -> None:
    """One joint (l3 on a mimic of the c-space joint j1): base/l3 are adjacent and masked,
    l5/l3 is sampled, so the side of l3 and l6 holds l3's spheres against base although
    base/l3 is not counted. The grid's far cells are right, but their clearance bound was
    −inf: a pair colliding in 6 % of the samples had no minimum clearance in the report."""
    path = _urdf(
        tmp_path,
        ["base", "l1", "l2", "l3", "l5", "l6"],
        [
            _joint(
                "j1", "continuous", "base", "l1", "0.094 -0.122 0.08", '<axis xyz="0.3 -0.2 0.9"/>'
            ),
            _joint("j2", "fixed", "base", "l2", "0.047 0.019 0.155", rpy="1.084 -0.494 0.852"),
            _joint(
                "j3",
                "revolute",
                "l2",
                "l3",
                "-0.033 -0.094 0.096",
                _revolute("0.3 -0.2 0.9", -0.204, 1.356)
                + '<mimic joint="j1" multiplier="2.0" offset="-0.3"/>',
                rpy="2.504 1.764 -1.164",
            ),
            _joint("j5", "fixed", "l2", "l5", "0.099 -0.001 0.108", rpy="0.146 -1.816 -2.555"),
            _joint("j6", "fixed", "l3", "l6", "0.119 0.101 0.084"),
        ],
    )
    spheres: Spheres = {
        "base": [(-0.0307, 0.0049, -0.0211, 0.0153)],
        "l3": [
            (-0.0497, 0.0407, 0.0171, 0.0203),
            (-0.0242, -0.0034, 0.0318, 0.0159),
            (0.0468, 0.0444, -0.0255, 0.042),
            (-0.014, 0.0197, -0.0413, 0.0335),
        ],
        "l6": [
            (0.0126, 0.0193, 0.0391, 0.0221),
            (-0.0347, -0.0109, 0.0069, 0.058),
            (0.0211, 0.0238, 0.0473, 0.0234),
            (-0.0241, -0.0077, -0.0205, 0.0426),
            (0.0452, -0.0346, 0.0018, 0.0439),
        ],
        "l5": [
            (-0.0007, 0.0414, 0.0237, 0.0541),
            (-0.0388, -0.0304, -0.0434, 0.0515),
            (0.0463, -0.0486, 0.0289, 0.0464),
        ],
    }
    report = report_against_reference(path, sphere_xrdf(["j1"], spheres, {"l3": ["base"]}), 20_000)
    l6 = next(p for p in report.pairs if {p.frame_a, p.frame_b} == {"base", "l6"})
    assert l6.hits and l6.min_clearance is not None and l6.min_clearance < 0


def test_given_configurations_outside_the_joint_limits_are_counted(tmp_path: Path) -> None:
    """A recorded trajectory may leave the limits: a slide of [0.5, 1.0] m at 0 puts the
    carriage on the base. The engine proved at build time, over the limits, that the two
    never come near and counted none of the 54 collisions."""
    slide = '<axis xyz="1 0 0"/><limit lower="0.5" upper="1.0" effort="1" velocity="1"/>'
    path = _urdf(
        tmp_path,
        ["base", "carriage", "arm"],
        [
            _joint("slide", "prismatic", "base", "carriage", "0 0 0", slide),
            _joint("turn", "revolute", "carriage", "arm", "0 0 0.1", _revolute("0 0 1")),
        ],
    )
    spheres: Spheres = {
        "base": [(0, 0, 0, 0.1)],
        "carriage": [(0, 0, 0, 0.05)],
        "arm": [(0.2, 0, 0, 0.05)],
    }
    urdf, xrdf = load_urdf(path), parse_xrdf(sphere_xrdf(["slide", "turn"], spheres), "robot.xrdf")
    rng = np.random.default_rng(0)
    configs = np.column_stack([rng.uniform(-0.5, 1.0, 300), rng.uniform(-9.0, 9.0, 300)])
    report = self_collision_report(urdf, xrdf, configs=configs, clearance_margin=MARGIN)
    kin, _ = build_kinematic_model(urdf, xrdf)
    spheres_set, _ = build_sphere_set(kin, xrdf, include_masked=True)
    ref = count_chunk(kin, spheres_set, configs, margin=MARGIN)
    stats = {(p.frame_a, p.frame_b): p for p in report.pairs}
    for k, name in enumerate(spheres_set.frame_pair_names()):
        assert stats[name].hits == int(ref.hits[k].sum()), name
    carriage = stats[("base", "carriage")]
    assert carriage.hits and carriage.hits == sum(
        any({c.frame_a, c.frame_b} == {"base", "carriage"} for c in t.contacts)
        for t in report.trajectory or ()
    )


def test_given_configurations_must_be_finite(tmp_path: Path) -> None:
    path = _urdf(
        tmp_path,
        ["base", "arm"],
        [_joint("turn", "revolute", "base", "arm", "0 0 0.1", _revolute("0 0 1"))],
    )
    spheres: Spheres = {"base": [(0, 0, 0, 0.1)], "arm": [(0.2, 0, 0, 0.05)]}
    urdf, xrdf = load_urdf(path), parse_xrdf(sphere_xrdf(["turn"], spheres), "robot.xrdf")
    with pytest.raises(ConfigsError, match="configuration 1: turn is nan"):
        self_collision_report(urdf, xrdf, configs=[[0.0], [np.nan]])


_AXES = ("0 0 1", "0 0 -1", "0.7071 0.7071 0", "1 1 0", "0 2 1", "0.3 -0.2 0.9")


def _random_robot(rng: np.random.Generator, n_links: int) -> tuple[list[str], list[str], list[str]]:
    """A random tree: links, joints (revolute, continuous, prismatic, fixed; odd and
    non-normalised axes, rpy origins, some mimic joints) and the joints that can be c-space."""
    links, joints, movable = ["base"], [], []
    for i in range(1, n_links):
        parent = links[int(rng.integers(max(0, len(links) - 3), len(links)))]
        kind = str(
            rng.choice(["revolute", "revolute", "continuous", "prismatic", "fixed", "fixed"])
        )
        xyz = " ".join(f"{v:.3f}" for v in (*rng.uniform(-0.15, 0.15, 2), rng.uniform(0.05, 0.2)))
        rpy = " ".join(f"{v:.3f}" for v in rng.uniform(-3.2, 3.2, 3))
        extra = "" if kind == "fixed" else f'<axis xyz="{rng.choice(_AXES)}"/>'
        if kind in ("revolute", "prismatic"):
            span = 3.5 if kind == "revolute" else float(rng.choice([0.05, 0.5]))
            lo, hi = sorted(rng.uniform(-span, span, 2))
            extra += f'<limit lower="{lo:.4f}" upper="{hi:.4f}" effort="1" velocity="1"/>'
        if kind != "fixed" and movable and rng.random() < 0.2:
            extra += f'<mimic joint="{rng.choice(movable)}" multiplier="-1.5" offset="0.2"/>'
        elif kind != "fixed":
            movable.append(f"j{i}")
        joints.append(_joint(f"j{i}", kind, parent, f"l{i}", xyz, extra, rpy))
        links.append(f"l{i}")
    return links, joints, movable


@pytest.mark.parametrize("seed", range(8))
def test_random_robots_agree_with_the_reference_counter(tmp_path: Path, seed: int) -> None:
    """Random trees, a random c-space (joints held in between), spheres on most links and
    every parent/child pair with spheres masked, as a converted XRDF masks adjacent links."""
    rng = np.random.default_rng(seed)
    links, joints, movable = _random_robot(rng, int(rng.integers(4, 12)))
    if not movable:
        pytest.skip("no joint to move")
    path = _urdf(tmp_path, links, joints)
    cspace = [j for j in movable if rng.random() < 0.5] or movable[:1]
    spheres: Spheres = {
        link: [
            (
                *(float(v) for v in rng.uniform(-0.08, 0.08, 3).round(4)),
                float(rng.uniform(0.01, 0.05)),
            )
            for _ in range(int(rng.integers(1, 5)))
        ]
        for link in links
        if rng.random() < 0.85
    }
    ignore: dict[str, list[str]] = {}
    for link, joint in zip(links[1:], joints, strict=True):
        parent = joint.split('<parent link="')[1].split('"')[0]
        if link in spheres and parent in spheres:
            ignore.setdefault(parent, []).append(link)
    report_against_reference(path, sphere_xrdf(cspace, spheres, ignore), 1500, seed=seed)
