"""Throughput of ``xrdf report``'s counting, one CPU thread, against the old engine in the same run.

Prints ONE JSON line. The work is the report's default: every unmasked frame pair and every
masked pair that is not adjacent, exact counts, minimum clearances exact below 1 cm, uniform
samples. For the Panda (example-robot-data URDF, ``fixtures/panda/panda.xrdf``: cuRobo's 61
spheres) and for the same model with every sphere split in 2 and in 4 (122, 244 spheres):

* ``configs_per_s``: :class:`xrdf_tools.selfcollision.engine.CountEngine` through ``count_sampled``
  (sampling included, one process): the issue's metric;
* ``baseline_configs_per_s``: the old engine (``count_chunk`` in ``tests/collision_reference.py``,
  float64 with bounding-sphere culling, what ``xrdf report`` ran before) on the same work, same
  process; ``ratio`` = ours / baseline (absolute rates are noisy on a shared machine, ratios less
  so);
* ``report_configs_per_s``: the whole ``self_collision_report`` (setup included).

Also ``jobs2_speedup`` (``count_sampled`` with 2 worker processes vs 1) and, with
``--memory``, the peak RSS of ``xrdf report -n 10000000 -j 1`` measured in a child process
alone (its own ``wait4`` resource usage, not this process's).

``robots`` (unless ``--robots 0``): big robots whose c-space moves a small part of them, each
beside franka on the same samples (``--robot-samples``, default 100,000), as ratios of time
(``ratio_to_franka``; the bar is 3): Talos' left arm (SRDF group ``l_arm``), TIAGo's arm
(``--chain base_footprint:arm_tool_link``) and PR2's two arms (``left_arm`` + ``right_arm``),
each from the example-robot-data URDF, and two Pandas on a table from xacro (rtb-data's
``dual_panda_example.urdf.xacro``, both arms' 14 joints), with spheres fitted by
``xrdf convert --fit-spheres`` once and cached in ``--cache`` (default: a directory in the
temporary directory; fitting takes minutes). Two figures per robot: the engine alone (chunks
of 65,536) and the whole report (setup included, in the report's own chunks:
``report_chunk``, from the robot's size).

Usage: ``python benchmarks/bench_report.py [--samples N] [--baseline N] [--jobs-samples N]
[--memory] [--robots 0|1] [--robot-samples N] [--cache DIR]`` (needs the
``example-robot-data`` package).
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMEXPR_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import importlib.metadata  # noqa: E402
import json  # noqa: E402
import resource  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import sysconfig  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402
import yaml  # noqa: E402

REPO = Path(__file__).resolve().parent.parent
XRDF = REPO / "fixtures" / "panda" / "panda.xrdf"
REL = Path("cmeel.prefix", "share", "example-robot-data", "robots")
PANDA = Path("panda_description", "urdf", "panda.urdf")
CHUNK = 65536  # the report's default chunk
OLD_CHUNK = 8192  # the chunk the old report used
MARGIN = 0.01
TARGET = 1_000_000


def panda_urdf() -> Path:
    candidates = []
    try:
        dist = importlib.metadata.distribution("example-robot-data")
        candidates.append(Path(str(dist.locate_file(REL))))
    except importlib.metadata.PackageNotFoundError:
        pass
    candidates += [Path(sysconfig.get_paths()[k]) / REL for k in ("purelib", "platlib")]
    for c in candidates:
        if (c / PANDA).is_file():
            return c / PANDA
    sys.exit("bench_report: example-robot-data is not installed (pip install example-robot-data)")


def split_spheres(text: str, k: int) -> str:
    """The XRDF with every sphere replaced by ``k`` smaller ones around it (k = 1, 2 or 4)."""
    if k == 1:
        return text
    doc = yaml.safe_load(text)
    offsets = [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0)][:k]
    for group in doc["geometry"].values():
        for frame, spheres in group["spheres"].items():
            new = []
            for s in spheres:
                r = float(s["radius"])
                if r < 0:
                    new.append(s)
                    continue
                for o in offsets:
                    c = [float(x) + 0.4 * r * d for x, d in zip(s["center"], o, strict=True)]
                    new.append({"center": c, "radius": 0.7 * r})
            group["spheres"][frame] = new
    return yaml.safe_dump(doc, sort_keys=False)


def setup(urdf_path: Path, text: str) -> dict[str, Any]:
    from xrdf_tools.report import adjacent_frame_pairs
    from xrdf_tools.robot.kinematics import build_kinematic_model, default_configuration
    from xrdf_tools.robot.urdf_source import load_urdf
    from xrdf_tools.selfcollision.collision import build_sphere_set
    from xrdf_tools.selfcollision.engine import CountEngine
    from xrdf_tools.xrdf.io import parse_xrdf

    xrdf = parse_xrdf(text, "bench.xrdf")
    urdf = load_urdf(urdf_path)
    kin, _ = build_kinematic_model(urdf, xrdf)
    spheres, _ = build_sphere_set(kin, xrdf, include_masked=True)
    adjacent = adjacent_frame_pairs(kin, spheres.frame_names)
    adj = np.array([frozenset(p) in adjacent for p in spheres.frame_pair_names()])
    work = spheres.select_frame_pairs(~(spheres.frame_pair_masked & adj))  # the report's work
    assert xrdf.cspace is not None
    idx = np.array([kin.actuated_index(j) for j in xrdf.cspace.joint_names])
    q0 = default_configuration(kin, xrdf.default_joint_positions)
    engine = CountEngine(kin, work, idx, q0, margin=MARGIN)
    return {
        "xrdf": xrdf,
        "urdf": urdf,
        "kin": kin,
        "work": work,
        "idx": idx,
        "q0": q0,
        "engine": engine,
    }


def ours(case: dict[str, Any], n: int, jobs: int = 1) -> tuple[float, Any]:
    from xrdf_tools.selfcollision.engine import count_sampled

    kin, idx = case["kin"], case["idx"]
    t0 = time.perf_counter()
    totals = count_sampled(
        case["engine"],
        kin.lower[idx],
        kin.upper[idx],
        n,
        method="uniform",
        seed=0,
        chunk=CHUNK,
        jobs=jobs,
    )
    return n / (time.perf_counter() - t0), totals


def baseline(case: dict[str, Any], n: int) -> tuple[float, Any]:
    """The old engine, as the report ran it: float64 FK, culling, exact minima below 1 cm."""
    if str(REPO) not in sys.path:
        sys.path.insert(0, str(REPO))  # the reference counter is test code
    from tests.collision_reference import count_chunk
    from xrdf_tools.selfcollision.sampling import iter_samples

    kin, idx, q0, work = case["kin"], case["idx"], case["q0"], case["work"]
    hits = np.zeros(work.n_frame_pairs, dtype=np.int64)
    t0 = time.perf_counter()
    for q_c in iter_samples(
        kin.lower[idx], kin.upper[idx], n, method="uniform", seed=0, chunk=OLD_CHUNK
    ):
        q = np.repeat(q0[None, :], len(q_c), axis=0)
        q[:, idx] = q_c
        hits += count_chunk(kin, work, q, margin=MARGIN).hits.sum(axis=1)
    return n / (time.perf_counter() - t0), hits


def report_rate(case: dict[str, Any], n: int) -> float:
    from xrdf_tools.report import self_collision_report

    t0 = time.perf_counter()
    self_collision_report(case["urdf"], case["xrdf"], samples=n, seed=0, jobs=1)
    return n / (time.perf_counter() - t0)


def measure(urdf: Path, text: str, n: int, n_base: int, rounds: int) -> dict[str, Any]:
    """Interleaved rounds of the old engine and ours; the best round of each counts (the
    machine is shared: the best round is the one least disturbed by other jobs)."""
    case = setup(urdf, text)
    ours(case, min(n, 2 * CHUNK))  # warm-up
    base_rates, rates = [], []
    for _ in range(rounds):
        rate_b, base_hits = baseline(case, n_base)
        base_rates.append(rate_b)
        rates.append(ours(case, n)[0])
    _, check = ours(case, n_base)
    assert np.array_equal(check.hits, base_hits), "engine counts differ from the old engine"
    work = case["work"]
    return {
        "spheres": int(work.n_spheres),
        "sphere_pairs": int(work.n_pairs),
        "frame_pairs": int(work.n_frame_pairs),
        "configs_per_s": round(max(rates)),
        "baseline_configs_per_s": round(max(base_rates)),
        "ratio": round(max(rates) / max(base_rates), 2),
        "median_ratio": round(float(np.median(np.array(rates) / np.array(base_rates))), 2),
        "report_configs_per_s": round(report_rate(case, n)),
        "counts_equal_baseline": True,
    }


def memory_10m(urdf: Path) -> float:
    """Peak RSS (MB) of ``xrdf report -n 10,000,000 -j 1`` run as a child process: the child's
    own resource usage from ``wait4`` (``RUSAGE_CHILDREN`` would report the largest child of
    this process so far, or this process's peak inherited at fork)."""
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "r.json"
        cmd = [
            sys.executable,
            "-m",
            "xrdf_tools",
            "report",
            str(XRDF),
            "--urdf",
            str(urdf),
            "-n",
            "10000000",
            "-j",
            "1",
            "-f",
            "json",
            "-o",
            str(out),
        ]
        proc = subprocess.Popen(cmd, cwd=REPO, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        _, status, usage = os.wait4(proc.pid, 0)
        proc.returncode = os.waitstatus_to_exitcode(status)
        if proc.returncode != 0:
            sys.exit(f"bench_report: the child report failed (exit {proc.returncode})")
    return usage.ru_maxrss / 1024.0


def _robots_dir() -> Path:
    return panda_urdf().parents[2]


def _convert(cache: Path, name: str, args: list[str]) -> Path:
    """``xrdf convert … --fit-spheres`` once; the result is cached as ``cache/name.xrdf``."""
    out = cache / f"{name}.xrdf"
    if not out.is_file():
        cmd = [sys.executable, "-m", "xrdf_tools", "convert", *args]
        cmd += ["--fit-spheres", "-n", "2000", "-q", "-o", str(out)]
        subprocess.run(cmd, check=True, cwd=REPO)
    return out


def big_robots(cache: Path) -> list[tuple[str, Path, Path]]:
    """(name, URDF, XRDF) of the big robots; their XRDFs are fitted once into ``cache``."""
    cache.mkdir(parents=True, exist_ok=True)
    robots = _robots_dir()
    share = robots.parent
    talos = cache / "talos.urdf"  # its meshes are package:/// URIs: point them at the files
    if not talos.is_file():
        text = (robots / "talos_data/robots/talos_full_v2.urdf").read_text()
        talos.write_text(text.replace("package:///example-robot-data", str(share)))
    tiago = robots / "tiago_description/robots/tiago.urdf"
    pr2 = robots / "pr2_description/urdf/pr2.urdf"
    pkg = ["--package-path", f"example-robot-data={share}"]
    return [
        (
            "talos_left_arm",
            talos,
            _convert(
                cache,
                "talos_left_arm",
                [
                    str(talos),
                    "--srdf",
                    str(robots / "talos_data/srdf/talos.srdf"),
                    "--group",
                    "l_arm",
                    *pkg,  # two ankle meshes are package://example-robot-data/… URIs
                ],
            ),
        ),
        (
            "tiago_arm",
            tiago,
            _convert(
                cache, "tiago_arm", [str(tiago), "--chain", "base_footprint:arm_tool_link", *pkg]
            ),
        ),
        (
            "pr2_two_arms",
            pr2,
            _convert(
                cache,
                "pr2_arms",
                [
                    str(pr2),
                    "--srdf",
                    str(robots / "pr2_description/srdf/pr2.srdf"),
                    "--group",
                    "left_arm",
                    "--group",
                    "right_arm",
                    *pkg,
                ],
            ),
        ),
        *_dual_panda(cache),
    ]


def _dual_panda(cache: Path) -> list[tuple[str, Path, Path]]:
    """Two Pandas on a table, from rtb-data's xacro (none without rtb-data): its expanded
    URDF and its XRDF (both arms, fitted once into ``cache``)."""
    import importlib.util

    spec = importlib.util.find_spec("rtbdata")
    if spec is None or spec.origin is None:
        return []
    xacro = Path(spec.origin).parent / "xacro/qut_frankie_description/robots"
    xacro = xacro / "dual_panda_example.urdf.xacro"
    urdf = cache / "dual_panda.urdf"
    if not urdf.is_file():
        cmd = [sys.executable, "-m", "xrdf_tools", "expand", str(xacro), "-o", str(urdf)]
        subprocess.run(cmd, check=True, cwd=REPO)
    joints = ",".join(f"panda_{a}_joint{j}" for a in (1, 2) for j in range(1, 8))
    return [("dual_panda", urdf, _convert(cache, "dual_panda", [str(xacro), "--joints", joints]))]


def robot_times(urdf: Path, xrdf: Path, n: int) -> tuple[float, float, dict[str, int]]:
    """Seconds of the engine alone and of the whole report on ``n`` samples (best of 2)."""
    case = setup(urdf, xrdf.read_text())
    engine = min(n / ours(case, n)[0] for _ in range(2))
    whole = min(n / report_rate(case, n) for _ in range(2))
    work = case["work"]
    size = {
        "spheres": int(work.n_spheres),
        "frame_pairs": int(work.n_frame_pairs),
        "body_pairs": len(case["engine"].pairs),
        "report_chunk": case["engine"].chunk_limit(),  # configurations per chunk of the report
    }
    return engine, whole, size


def compare_robots(cache: Path, n: int) -> list[dict[str, Any]]:
    """Each big robot beside franka (the fixture, same samples), as time ratios."""
    f_engine, f_whole, _ = robot_times(panda_urdf(), XRDF, n)
    out = []
    for name, urdf, xrdf in big_robots(cache):
        engine, whole, size = robot_times(urdf, xrdf, n)
        out.append(
            {
                "robot": name,
                **size,
                "samples": n,
                "engine_s": round(engine, 3),
                "franka_engine_s": round(f_engine, 3),
                "engine_ratio_to_franka": round(engine / f_engine, 2),
                "report_s": round(whole, 3),
                "franka_report_s": round(f_whole, 3),
                "ratio_to_franka": round(whole / f_whole, 2),
            }
        )
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--samples", type=int, default=1_000_000, help="samples for our engine")
    ap.add_argument("--baseline", type=int, default=100_000, help="samples for the old engine")
    ap.add_argument("--jobs-samples", type=int, default=2_000_000, help="0: skip --jobs 2")
    ap.add_argument("--rounds", type=int, default=3, help="interleaved rounds (best counts)")
    ap.add_argument("--memory", action="store_true", help="also run 10M samples in a child")
    ap.add_argument("--robots", type=int, default=1, help="0: skip Talos, TIAGo and PR2")
    ap.add_argument("--robot-samples", type=int, default=100_000, help="samples per big robot")
    ap.add_argument(
        "--cache",
        type=Path,
        default=Path(tempfile.gettempdir()) / "xrdf-bench-report",
        help="where the fitted XRDFs of the big robots are kept",
    )
    ap.add_argument("--panda", type=int, default=1, help="0: skip the Panda split cases")
    args = ap.parse_args()
    urdf = panda_urdf()
    text = XRDF.read_text()
    cases = [
        measure(urdf, split_spheres(text, k), args.samples // k, args.baseline // k, args.rounds)
        for k in ((1, 2, 4) if args.panda else ())
    ]
    out: dict[str, Any] = {
        "robot": "panda (example-robot-data) + fixtures/panda/panda.xrdf, spheres split 1/2/4",
        "work": "unmasked + masked non-adjacent frame pairs, exact counts, exact minima < 1 cm",
        "threads": 1,
        "cpu_count": os.cpu_count(),
        "load_average": round(os.getloadavg()[0], 2),
        "cases": cases,
        "target_configs_per_s": TARGET,
        "target_met": bool(cases) and cases[0]["configs_per_s"] >= TARGET,
    }
    if args.robots:
        out["robots"] = compare_robots(args.cache, args.robot_samples)
        out["robots_bar_met"] = all(r["ratio_to_franka"] <= 3.0 for r in out["robots"])
    if args.jobs_samples and args.panda:
        case = setup(urdf, text)
        one, t1 = ours(case, args.jobs_samples, jobs=1)
        two, t2 = ours(case, args.jobs_samples, jobs=2)
        assert np.array_equal(t1.hits, t2.hits), "--jobs 2 changed the counts"
        out["jobs2_samples"] = args.jobs_samples
        out["jobs2_speedup"] = round(two / one, 2)
    out["peak_rss_mb"] = round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0, 1)
    if args.memory:
        out["peak_rss_mb_10m_samples"] = round(memory_10m(urdf), 1)
    print(json.dumps(out))


if __name__ == "__main__":
    main()
