"""Sphere fitting against MorphIt (``morphit-rs``), same counts, one scorer, same run.

For each robot (example-robot-data Panda, UR5, Kinova and the TIAGo mobile base), every link's
solid (as ``xrdf spheres`` prepares it) is fitted by ours and by MorphIt (``morphit-rs``, preset
``MorphIt-B``, one thread) with the same number of spheres, and both are scored by
:func:`xrdf_tools.spheres.metrics.measure` with the same samples. The per-link counts split the
robot's total over its links in proportion to the two-thirds power of each link's volume
(at least one each), a rule neither fitter chooses.

Rows (one JSON object per line on stdout):

* ``link``  -- per link: both fits' metrics (``ours`` / ``morphit``), fit seconds and whether
  ours is Pareto-better (coverage >= MorphIt's and protrusion p95 <= MorphIt's);
* ``robot`` -- pooled metrics of both, the total fit time of each, their ratios, how many
  links ours wins and whether the whole robot meets the target (every link Pareto-better and
  no slower).

Run: ``python benchmarks/bench_spheres.py [--robots panda ur5 kinova tiago_base]
[--total N ...] [--samples N] [--seed S]``. Needs ``morphit-rs`` (the ``dev`` extra); threads
are pinned to one so both timings are single-core.
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "RAYON_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import json  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402
from typing import Any  # noqa: E402

#: robot -> (URDF below example-robot-data's robots/, links (None: all), totals to fit)
ROBOTS: dict[str, tuple[str, list[str] | None, list[int]]] = {
    "panda": ("panda_description/urdf/panda.urdf", None, [57, 87]),
    "ur5": ("ur_description/urdf/ur5_robot.urdf", None, [40]),
    "kinova": ("kinova_description/robots/kinova.urdf", None, [40]),
    "tiago_base": ("tiago_description/robots/tiago.urdf", ["base_link"], [12]),
}

FIELDS = (
    "coverage",
    "surface_coverage",
    "protrusion_share",
    "protrusion_mean",
    "protrusion_p95",
    "surface_gap_mean",
    "surface_gap_p95",
    "max_uncovered_gap",
    "volume_ratio",
)


def _robots() -> Path:
    import trimesh

    return (
        Path(trimesh.__file__).resolve().parents[1] / "cmeel.prefix/share/example-robot-data/robots"
    )


def split_counts(volumes: dict[str, float], total: int) -> dict[str, int]:
    """``total`` spheres over the links, in proportion to volume^(2/3), at least one each
    (largest remainder, ties by link order)."""
    weight = {k: max(v, 1e-12) ** (2.0 / 3.0) for k, v in volumes.items()}
    spare = total - len(weight)
    share = {k: spare * w / sum(weight.values()) for k, w in weight.items()}
    counts = {k: 1 + int(s) for k, s in share.items()}
    rest = sorted(weight, key=lambda k: -(share[k] - int(share[k])))
    for k in rest[: total - sum(counts.values())]:
        counts[k] += 1
    return counts


def _numbers(m: Any) -> dict[str, float]:
    out = {f: round(getattr(m, f), 4) for f in FIELDS}
    for f in ("protrusion_mean", "protrusion_p95", "surface_gap_mean", "surface_gap_p95"):
        out[f] = round(getattr(m, f) * 1000, 2)  # millimetres
    out["max_uncovered_gap"] = round(m.max_uncovered_gap * 1000, 2)
    out["spheres"] = m.sphere_count
    return out


def morphit_fit(solid: Any, k: int, seed: int) -> tuple[Any, float]:
    """MorphIt's spheres for ``solid`` (preset MorphIt-B, ``k`` spheres) and its seconds."""
    import morphit_rs as mi
    import numpy as np

    from xrdf_tools.xrdf.model import Sphere

    mesh = mi.Mesh.from_arrays(
        np.asarray(solid.vertices, dtype=np.float64), np.asarray(solid.faces, dtype=np.uint32)
    )
    config = mi.Config.preset("MorphIt-B", num_spheres=k, seed=seed)
    t0 = time.perf_counter()
    result = mi.pack(mesh, config)
    dt = time.perf_counter() - t0
    spheres = tuple(
        Sphere(tuple(float(x) for x in c), float(r))  # type: ignore[arg-type]
        for c, r in zip(result.centers, result.radii, strict=True)
    )
    return spheres, dt


def bench_robot(name: str, total: int, samples: int, seed: int) -> list[dict[str, Any]]:
    from xrdf_tools.spheres import fit_link_spheres, link_seed
    from xrdf_tools.spheres.geometry import load_link_geometry
    from xrdf_tools.spheres.metrics import measure, pooled

    rel, links, _ = ROBOTS[name]
    urdf = _robots() / rel
    geoms, _ = load_link_geometry(urdf, links=links)
    counts = split_counts({k: float(g.solid.volume) for k, g in geoms.items()}, total)
    t0 = time.perf_counter()
    ours, _ = fit_link_spheres(urdf, links=list(geoms), per_link=counts, seed=seed)
    t_ours = time.perf_counter() - t0
    rows: list[dict[str, Any]] = []
    m_ours, m_peer, p_ours, p_peer = [], [], [], []
    t_peer = 0.0
    wins = 0
    for link, g in geoms.items():
        peer, dt = morphit_fit(g.solid, counts[link], seed)
        t_peer += dt
        a, pa = measure(g.solid, ours.get(link, ()), samples=samples, seed=link_seed(seed, link))
        b, pb = measure(g.solid, peer, samples=samples, seed=link_seed(seed, link))
        m_ours.append(a)
        m_peer.append(b)
        p_ours.append(pa)
        p_peer.append(pb)
        win = a.coverage >= b.coverage and a.protrusion_p95 <= b.protrusion_p95
        wins += win
        rows.append(
            {
                "row": "link",
                "robot": name,
                "total": total,
                "link": link,
                "ours": _numbers(a),
                "morphit": _numbers(b),
                "morphit_seconds": round(dt, 3),
                "pareto_better": bool(win),
            }
        )
    a_all, b_all = pooled(m_ours, p_ours), pooled(m_peer, p_peer)
    rows.append(
        {
            "row": "robot",
            "robot": name,
            "total": total,
            "ours": _numbers(a_all),
            "morphit": _numbers(b_all),
            "fit_seconds": {"ours": round(t_ours, 2), "morphit": round(t_peer, 2)},
            "ratio": {
                "coverage": round(a_all.coverage / max(b_all.coverage, 1e-9), 3),
                "protrusion_p95": round(a_all.protrusion_p95 / max(b_all.protrusion_p95, 1e-9), 3),
                "surface_gap_p95": round(
                    a_all.surface_gap_p95 / max(b_all.surface_gap_p95, 1e-9), 3
                ),
                "fit_seconds": round(t_ours / max(t_peer, 1e-9), 3),
            },
            "links_pareto_better": f"{wins}/{len(geoms)}",
            "target_met": bool(wins == len(geoms) and t_ours <= t_peer),
        }
    )
    return rows


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--robots", nargs="+", default=list(ROBOTS), choices=list(ROBOTS))
    ap.add_argument("--total", type=int, nargs="+", help="total spheres (default per robot)")
    ap.add_argument("--samples", type=int, default=20_000, help="metric samples per link")
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()
    try:
        import morphit_rs

        morphit_rs.set_num_threads(1)
    except ImportError:
        print("morphit-rs is not installed (pip install -e '.[dev]')", file=sys.stderr)
        return 2
    if not (_robots() / ROBOTS["panda"][0]).exists():
        print(f"example-robot-data not installed ({_robots()})", file=sys.stderr)
        return 2
    for name in args.robots:
        for total in args.total or ROBOTS[name][2]:
            for row in bench_robot(name, total, args.samples, args.seed):
                print(json.dumps(row), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
