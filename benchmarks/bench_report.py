"""Throughput of the self-collision counting behind ``xrdf report``, on one CPU thread.

Prints ONE JSON line:

* ``configs_per_s``: end to end (uniform sampling + FK + sphere transform + pair tests +
  accumulation), every unmasked frame pair counted, no early exit: the issue's target metric;
* ``report_configs_per_s``: the full :func:`self_collision_report` with its defaults (also
  counts masked non-adjacent pairs and keeps minimum clearances exact below 1 cm);
* ``naive_configs_per_s``: yourdfpy FK per configuration + the same sphere-pair test in a
  Python loop, on a smaller sample; ``speedup`` = ours / naive;
* ``peak_rss_mb`` of the process and the sizes involved.

Usage: ``python benchmarks/bench_report.py [--samples N] [--naive N]`` (needs the
``example-robot-data`` package for the Panda URDF; the XRDF is ``fixtures/panda/panda.xrdf``).
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMEXPR_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import importlib.metadata  # noqa: E402
import json  # noqa: E402
import math  # noqa: E402
import resource  # noqa: E402
import sys  # noqa: E402
import sysconfig  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

REPO = Path(__file__).resolve().parent.parent
REL = Path("cmeel.prefix", "share", "example-robot-data", "robots")
PANDA = Path("panda_description", "urdf", "panda.urdf")


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


def ours(urdf_path: Path, n: int, chunk: int) -> tuple[float, int, int]:
    from xrdf_tools.collision import build_sphere_set, count_chunk
    from xrdf_tools.kinematics import build_kinematic_model, full_configuration
    from xrdf_tools.sampling import iter_samples
    from xrdf_tools.urdf_source import load_urdf
    from xrdf_tools.xrdf_io import load_xrdf

    xrdf = load_xrdf(REPO / "fixtures" / "panda" / "panda.xrdf")
    kin, _ = build_kinematic_model(load_urdf(urdf_path), xrdf)
    spheres, _ = build_sphere_set(kin, xrdf)  # unmasked frame pairs only
    assert xrdf.cspace is not None
    names = list(xrdf.cspace.joint_names)
    idx = [kin.actuated_index(j) for j in names]
    lo, hi = kin.lower[idx], kin.upper[idx]
    hits = np.zeros(spheres.n_frame_pairs, dtype=np.int64)
    t0 = time.perf_counter()
    for q_c in iter_samples(lo, hi, n, method="uniform", seed=0, chunk=chunk):
        q = full_configuration(kin, names, q_c, xrdf.default_joint_positions)
        hits += count_chunk(kin, spheres, q).hits.sum(axis=1)
    dt = time.perf_counter() - t0
    return n / dt, spheres.n_spheres, spheres.n_pairs


def report_mode(urdf_path: Path, n: int) -> float:
    from xrdf_tools.report import self_collision_report
    from xrdf_tools.urdf_source import load_urdf
    from xrdf_tools.xrdf_io import load_xrdf

    xrdf = load_xrdf(REPO / "fixtures" / "panda" / "panda.xrdf")
    urdf = load_urdf(urdf_path)
    t0 = time.perf_counter()
    r = self_collision_report(urdf, xrdf, samples=n, seed=0)
    return n / (time.perf_counter() - t0) if r.samples else 0.0


def naive(urdf_path: Path, n: int) -> float:
    """yourdfpy FK per configuration + a Python double loop over the unmasked sphere pairs."""
    import yourdfpy

    from xrdf_tools.xrdf_io import load_xrdf

    xrdf = load_xrdf(REPO / "fixtures" / "panda" / "panda.xrdf")
    sc = xrdf.self_collision
    assert sc is not None and xrdf.cspace is not None
    robot = yourdfpy.URDF.load(str(urdf_path), load_meshes=False, build_collision_scene_graph=False)
    spheres = [
        (frame, s.center, s.radius + sc.buffer_distance.get(frame, 0.0))
        for frame, sph in xrdf.self_collision_spheres().items()
        for s in sph
        if s.radius >= 0
    ]
    pairs = [
        (i, j)
        for i in range(len(spheres))
        for j in range(i + 1, len(spheres))
        if spheres[i][0] != spheres[j][0] and not sc.is_ignored(spheres[i][0], spheres[j][0])
    ]
    names = list(xrdf.cspace.joint_names)
    joints = robot.joint_map
    lo = np.array([joints[j].limit.lower for j in names])
    hi = np.array([joints[j].limit.upper for j in names])
    rng = np.random.default_rng(0)
    frames = sorted({s[0] for s in spheres})
    t0 = time.perf_counter()
    for _ in range(n):
        q = rng.uniform(lo, hi)
        robot.update_cfg(dict(zip(names, q, strict=True)))
        poses = {f: robot.get_transform(f) for f in frames}
        world = [poses[f][:3, :3] @ np.asarray(c) + poses[f][:3, 3] for f, c, _ in spheres]
        hit: set[tuple[str, str]] = set()
        for i, j in pairs:
            if math.dist(world[i], world[j]) < spheres[i][2] + spheres[j][2]:
                hit.add((spheres[i][0], spheres[j][0]))
    return n / (time.perf_counter() - t0)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--samples", type=int, default=1_000_000, help="samples for our run")
    ap.add_argument("--report-samples", type=int, default=200_000)
    ap.add_argument("--naive", type=int, default=300, help="samples for the naive baseline")
    ap.add_argument("--chunk", type=int, default=8192)
    args = ap.parse_args()
    urdf = panda_urdf()
    ours(urdf, min(args.samples, 20_000), args.chunk)  # warm-up (imports, caches)
    rate, n_spheres, n_pairs = ours(urdf, args.samples, args.chunk)
    rep = report_mode(urdf, args.report_samples)
    base = naive(urdf, args.naive)
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    target = 300_000
    out = {
        "robot": "panda (example-robot-data) + fixtures/panda/panda.xrdf",
        "threads": 1,
        "spheres": n_spheres,
        "unmasked_sphere_pairs": n_pairs,
        "samples": args.samples,
        "configs_per_s": round(rate),
        "report_configs_per_s": round(rep),
        "naive_samples": args.naive,
        "naive_configs_per_s": round(base, 1),
        "speedup": round(rate / base, 1),
        "target_configs_per_s": target,
        "target_met": rate >= target,
        "peak_rss_mb": round(peak, 1),
        "cpu_count": os.cpu_count(),
    }
    print(json.dumps(out))


if __name__ == "__main__":
    main()
