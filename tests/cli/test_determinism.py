"""Same inputs and options, same bytes out: the one command and sphere fitting in separate
processes with different hash seeds and BLAS/OpenMP thread counts, on real robots."""

from __future__ import annotations

import os
import platform
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import trimesh

from tests.paths import UR10E_URDF, UR10E_XRDF
from tests.robots import robot_urdf
from xrdf_tools.spheres.inside import points_inside

THREAD_VARS = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")

#: two process environments that differ in everything that must not matter
SETTINGS = (
    {"PYTHONHASHSEED": "0", **dict.fromkeys(THREAD_VARS, "1")},
    {"PYTHONHASHSEED": "4242", **dict.fromkeys(THREAD_VARS, "2")},
)


def _xrdf(args: list[str], env_extra: dict[str, str], out: Path) -> bytes:
    env = {k: v for k, v in os.environ.items() if k not in THREAD_VARS}
    env.update(env_extra)
    cmd = [sys.executable, "-m", "xrdf_tools", *args, "-q", "-o", str(out)]
    done = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    return out.read_bytes()


def _srdf_of(urdf: Path, name: str) -> Path:
    return urdf.parent.parent / "srdf" / name


@pytest.mark.slow
@pytest.mark.parametrize(
    ("robot", "srdf"),
    [("ur5", "ur5.srdf"), ("panda", "panda.srdf"), ("kinova", "kinova.srdf")],
)
def test_one_command_is_byte_identical_across_processes(
    tmp_path: Path, robot: str, srdf: str
) -> None:
    urdf = robot_urdf(robot)
    args = ["convert", str(urdf), "--srdf", str(_srdf_of(urdf, srdf)), "--fit-spheres"]
    first = _xrdf(args, SETTINGS[0], tmp_path / "a.xrdf")
    second = _xrdf(args, SETTINGS[1], tmp_path / "b.xrdf")
    assert b"collision_spheres" in first
    assert first == second


def test_sphere_fit_of_one_link_is_byte_identical_across_processes(tmp_path: Path) -> None:
    urdf = robot_urdf("ur5")
    args = ["spheres", str(urdf), "--links", "shoulder_link"]
    outputs = {_xrdf(args, s, tmp_path / f"{i}.xrdf") for i, s in enumerate(SETTINGS)}
    assert len(outputs) == 1


@pytest.mark.slow
def test_morphit_sphere_fit_is_byte_identical_across_processes_and_threads(
    tmp_path: Path,
) -> None:
    """``--method morphit``: seeded from the seed and each solid's content, and MorphIt's
    own threads (RAYON_NUM_THREADS) change nothing; counts by our default, a clip plane."""
    pytest.importorskip("morphit_rs")
    urdf = robot_urdf("panda")
    args = ["spheres", str(urdf), "--links", "panda_link0,panda_hand", "--method", "morphit"]
    args += ["--clip", "panda_link0:0,0,1,0.02"]
    outputs = {
        _xrdf(args, {**s, "RAYON_NUM_THREADS": str(i + 1)}, tmp_path / f"{i}.xrdf")
        for i, s in enumerate(SETTINGS)
    }
    assert len(outputs) == 1
    assert b"panda_hand:" in next(iter(outputs))


def test_report_with_certify_is_byte_identical_across_processes_and_jobs(tmp_path: Path) -> None:
    """No wall time in the report (only with --timings) and a --certify budget counted in
    boxes: the JSON, text and SARIF reports are the same bytes in any process, with any jobs."""
    base = ["report", str(UR10E_XRDF), "--urdf", str(UR10E_URDF), "-n", "3000", "--certify"]
    base += ["--certify-boxes", "20000"]
    got = {}
    for fmt in ("json", "text"):
        one = _xrdf([*base, "-f", fmt, "-j", "1"], SETTINGS[0], tmp_path / f"a.{fmt}")
        two = _xrdf([*base, "-f", fmt, "-j", "2"], SETTINGS[1], tmp_path / f"b.{fmt}")
        assert one == two, fmt
        got[fmt] = one
    assert b'"certify_boxes": ' in got["json"] and b"boxes)" in got["text"]
    timed = _xrdf([*base, "-f", "json", "--timings"], SETTINGS[0], tmp_path / "t.json")
    assert b'"elapsed_s": ' in timed and b'"elapsed_s": ' not in got["json"]


def test_mcap_and_png_drawings_are_byte_identical_across_processes(tmp_path: Path) -> None:
    base = ["viz", str(UR10E_XRDF), "--urdf", str(UR10E_URDF), "-n", "5", "--meshes", "none"]
    outputs: dict[str, set[bytes]] = {"mcap": set(), "png": set()}
    for i, setting in enumerate(SETTINGS):
        env = {k: v for k, v in os.environ.items() if k not in THREAD_VARS} | setting
        for kind in outputs:
            out = tmp_path / f"{i}.{kind}"
            cmd = [sys.executable, "-m", "xrdf_tools", *base, f"--{kind}", str(out), "-q"]
            done = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=600)
            assert done.returncode == 0, done.stderr
            outputs[kind].add(out.read_bytes())
    assert {kind: len(seen) for kind, seen in outputs.items()} == {"mcap": 1, "png": 1}


def _convex_reference(mesh: trimesh.Trimesh, points: np.ndarray) -> np.ndarray:
    """Inside a convex mesh: behind every face plane (a plain loop over faces)."""
    inside = np.ones(len(points), dtype=bool)
    for normal, origin in zip(mesh.face_normals, mesh.triangles[:, 0], strict=True):
        inside &= (points - origin) @ normal < 0.0
    return inside


def _winding_reference(mesh: trimesh.Trimesh, point: np.ndarray) -> bool:
    """Inside by the winding number (sum of solid angles), one point at a time."""
    total = 0.0
    for tri in mesh.triangles:
        a, b, c = tri - point
        la, lb, lc = np.linalg.norm(a), np.linalg.norm(b), np.linalg.norm(c)
        num = float(np.dot(a, np.cross(b, c)))
        den = la * lb * lc + np.dot(a, b) * lc + np.dot(b, c) * la + np.dot(c, a) * lb
        total += 2.0 * float(np.arctan2(num, den))
    return abs(total / (4.0 * np.pi)) > 0.5


def test_inside_matches_the_face_planes_also_when_rays_graze_edges_and_vertices() -> None:
    mesh = trimesh.creation.icosphere(subdivisions=2)
    rng = np.random.default_rng(3)
    random = rng.uniform(-1.1, 1.1, size=(3000, 3))
    v = mesh.vertices[mesh.vertices[:, 2] > 0.5]
    edges = mesh.vertices[mesh.edges_unique].mean(1)
    edges = edges[edges[:, 2] > 0.5]
    # rays from just below a vertex or an edge midpoint pass exactly through it
    grazing = np.concatenate([v, edges]) - [0.0, 0.0, 0.05]
    points = np.concatenate([random, grazing])
    expected = _convex_reference(mesh, points)
    assert expected[len(random) :].all()
    assert np.array_equal(points_inside(mesh, points), expected)


def test_inside_matches_the_winding_number_on_a_real_mesh_with_several_shells() -> None:
    from xrdf_tools.spheres.geometry import load_link_geometry

    geoms, _ = load_link_geometry(robot_urdf("ur5"), links=["forearm_link"])
    mesh = geoms["forearm_link"].solid
    rng = np.random.default_rng(0)
    points = rng.uniform(mesh.bounds[0] - 0.01, mesh.bounds[1] + 0.01, size=(150, 3))
    expected = np.array([_winding_reference(mesh, p) for p in points])
    assert 10 < expected.sum() < 140
    assert np.array_equal(points_inside(mesh, points), expected)


def _machine_like_another() -> dict[str, str]:
    """Process settings under which numpy and its BLAS compute as another x86-64 machine
    would: OpenBLAS' kernels of an SSE4.2 CPU (no FMA, other blocking) and none of numpy's
    dispatched SIMD loops (AVX2, AVX-512); empty when this is not such a machine."""
    if platform.machine().lower() not in ("x86_64", "amd64"):
        return {}
    from numpy._core import _multiarray_umath as umath

    return {
        "OPENBLAS_CORETYPE": "Nehalem",
        "NPY_DISABLE_CPU_FEATURES": " ".join(umath.__cpu_dispatch__),
    }


def _bytes_of(args: list[str], env_extra: dict[str, str], out: Path | None = None) -> bytes:
    """What ``xrdf ARGS -q`` writes: the file ``out`` when given, else standard output."""
    env = {**os.environ, **env_extra}
    cmd = [sys.executable, "-m", "xrdf_tools", *args, "-q"]
    done = subprocess.run(cmd, env=env, capture_output=True, timeout=600)
    assert done.returncode == 0, done.stderr.decode()
    return out.read_bytes() if out is not None else done.stdout


@pytest.mark.slow
def test_outputs_do_not_depend_on_the_machines_blas_or_simd(tmp_path: Path) -> None:
    """The report's JSON, an MCAP recording, a PNG and a fit on the example-robot-data Panda,
    computed with this machine's BLAS and numpy's SIMD loops and again as an SSE4.2 machine
    computes them: the same bytes. (The report's clearance bounds came from float32 products,
    whose last bits follow the BLAS kernel; the PNG's polygons were drawn in the order numpy's
    unstable sort left equal depths in, which its AVX-512 sort and its portable one differ on.)"""
    other = _machine_like_another()
    if not other:
        pytest.skip("emulating another machine needs x86-64 (OpenBLAS core types)")
    urdf = robot_urdf("panda")
    xrdf = Path(__file__).parents[2] / "fixtures" / "panda" / "panda.xrdf"
    robot = [str(xrdf), "--urdf", str(urdf)]
    for i, env in enumerate(({}, other)):
        mcap, fit, png = tmp_path / f"{i}.mcap", tmp_path / f"{i}.xrdf", tmp_path / f"{i}.png"
        got = (
            _bytes_of(["report", *robot, "-n", "20000", "--format", "json"], env),
            _bytes_of(["viz", *robot, "--samples", "20", "--mcap", str(mcap)], env, mcap),
            _bytes_of(["viz", *robot, "--png", str(png), "--view", "front"], env, png),
            _bytes_of(
                ["spheres", str(urdf), "--links", "panda_link3,panda_hand", "-o", str(fit)],
                env,
                fit,
            ),
        )
        assert all(got)
        if i == 0:
            first = got
    assert got == first
