"""The one command, the report and lint for cuRobo on the arm of a mobile manipulator (TIAGo)
and of a humanoid (Talos, whose meshes are ``package:///`` URIs): every link with collision
geometry gets spheres, and the file is planning-ready."""

from __future__ import annotations

from pathlib import Path

import pytest
from typer.testing import CliRunner

from tests.robots import robots_dir
from xrdf_tools.cli import app
from xrdf_tools.robot.xacro_source import load_robot
from xrdf_tools.xrdf.io import load_xrdf

CASES = {
    "tiago-arm": (
        "tiago_description/robots/tiago.urdf",
        None,
        ["--chain", "base_footprint:arm_tool_link"],
    ),
    "talos-left-arm": (
        "talos_data/robots/talos_full_v2.urdf",
        "talos_data/srdf/talos.srdf",
        ["--group", "l_arm"],
    ),
}


_FITTED: dict[str, Path] = {}


def _fitted(
    runner: CliRunner, case: str, tmp_path_factory: pytest.TempPathFactory
) -> tuple[Path, Path]:
    """(URDF, XRDF fitted by the one command) of a case, converted once per session."""
    root = robots_dir()
    if root is None:
        pytest.skip("example-robot-data is not installed")
    urdf_rel, srdf_rel, choice = CASES[case]
    urdf = root / urdf_rel
    if case not in _FITTED:
        out = tmp_path_factory.mktemp(case) / "r.xrdf"
        # 10,000 samples for the mask (default 100,000): nothing here depends on the mask
        args = ["convert", str(urdf), *choice, "--fit-spheres", "-n", "10000", "-q", "-o", str(out)]
        if srdf_rel is not None:
            args += ["--srdf", str(root / srdf_rel)]
        done = runner.invoke(app, args)
        assert done.exit_code == 0, done.output
        _FITTED[case] = out
    return urdf, _FITTED[case]


@pytest.mark.slow
@pytest.mark.parametrize("case", sorted(CASES))
def test_one_command_report_and_lint_on_a_big_robot(
    runner: CliRunner, case: str, tmp_path_factory: pytest.TempPathFactory
) -> None:
    """Every link with geometry gets spheres, the report runs and lint for cuRobo is clean;
    on TIAGo's arm the report's engine also equals the plain counter (one fit serves both:
    a fit is the most of the test's time)."""
    urdf, fitted = _fitted(runner, case, tmp_path_factory)
    x = load_xrdf(fitted)
    with_spheres = {k for k, v in x.self_collision_spheres().items() if v}
    with_geometry = set(load_robot(urdf).collision_counts)
    assert with_geometry and with_geometry <= with_spheres, sorted(with_geometry - with_spheres)
    report = runner.invoke(app, ["report", str(fitted), "--urdf", str(urdf), "-n", "2000", "-q"])
    assert report.exit_code in (0, 1), report.output
    lint = runner.invoke(app, ["lint", str(fitted), "--urdf", str(urdf), "--target", "curobo"])
    assert lint.exit_code == 0, lint.output
    if case == "tiago-arm":
        _assert_engine_equals_the_reference_counter(urdf, fitted)


def _assert_engine_equals_the_reference_counter(urdf: Path, out: Path) -> None:
    """The report's engine (float32 path, path-local poses, the float64 second look, pairs
    decided once) against the plain float64 counter, on the arm of a mobile manipulator whose
    wrist spheres nearly keep their distance as the wrist turns."""
    import numpy as np

    from tests.collision_reference import count_chunk
    from xrdf_tools.robot.kinematics import build_kinematic_model, default_configuration
    from xrdf_tools.robot.urdf_source import load_urdf
    from xrdf_tools.selfcollision.collision import build_sphere_set
    from xrdf_tools.selfcollision.engine import CountEngine, EngineTotals
    from xrdf_tools.selfcollision.sampling import iter_samples

    xrdf = load_xrdf(out)
    kin, _ = build_kinematic_model(load_urdf(urdf), xrdf)
    spheres, _ = build_sphere_set(kin, xrdf, include_masked=True)
    assert xrdf.cspace is not None
    idx = np.array([kin.actuated_index(j) for j in xrdf.cspace.joint_names])
    q0 = default_configuration(kin, xrdf.default_joint_positions)
    engine = CountEngine(kin, spheres, idx, q0, margin=0.01)
    totals = EngineTotals.empty(spheres.n_frame_pairs)
    hits = np.zeros(spheres.n_frame_pairs, dtype=np.int64)
    ref_min = np.full(spheres.n_frame_pairs, np.inf)
    for qc in iter_samples(
        kin.lower[idx], kin.upper[idx], 600, method="uniform", seed=1, chunk=300
    ):
        engine.count(qc, totals)
        q = np.repeat(q0[None, :], len(qc), axis=0)
        q[:, idx] = qc
        ref = count_chunk(kin, spheres, q, margin=0.01)
        hits += ref.hits.sum(axis=1)
        np.minimum(
            ref_min,
            np.where(ref.min_clearance <= ref.clearance_bound, ref.min_clearance, np.inf),
            out=ref_min,
        )
    np.testing.assert_array_equal(totals.hits, hits)
    near = ref_min < 0.01
    assert near.sum() > 10
    np.testing.assert_allclose(totals.min_clearance[near], ref_min[near], rtol=0, atol=1e-12)
