"""Sphere fitting against MorphIt (``morphit-rs``), same counts, one scorer, same run.

For each robot (example-robot-data Panda, UR5, Kinova and the TIAGo mobile base), every link's
solid (as ``xrdf spheres`` prepares it) is fitted by ours and by MorphIt (``morphit-rs``, preset
``MorphIt-B``, one thread) with the same number of spheres, and both are scored by
:func:`xrdf_tools.spheres.metrics.measure` with the same samples. The per-link counts split the
robot's total over its links in proportion to the two-thirds power of each link's volume
(at least one each), a rule neither fitter chooses.

Ours runs four ways, timed from loaded solids like MorphIt: ``mode: default`` (what
``xrdf spheres --per-link`` does: greedy spheres refined on coverage and on the protrusion
of their union, :mod:`xrdf_tools.spheres.refine`), ``mode: hard`` (the greedy fit within our
default protrusion bound, 6 % of the cube root of the link volume, not refined:
``CountPolicy(refine=False)``), ``mode: matched``: the greedy fit at MorphIt's protrusion. That
bound is a hard maximum, so our p95 sits below it; per link the bound is searched (bisection,
0.7 to 1.6 times MorphIt's p95 on that link, untimed) for the largest one whose p95 stays
within MorphIt's, and the timed run fits every link once at those bounds: at equal
protrusion, the comparison is coverage against coverage. ``mode: coverage`` is ours with
``CountPolicy(count_coverage=0.975)``: per link the smallest bound at which its spheres cover
97.5 % of its volume (our own samples), found by the fitter itself (timed; no knowledge of
MorphIt).

Rows (one JSON object per line on stdout):

* ``link``  -- per link and mode: both fits' metrics (``ours`` / ``morphit``; lengths in mm)
  and whether ours is Pareto-better (coverage >= MorphIt's and protrusion p95 <= MorphIt's);
* ``robot`` -- per mode: pooled metrics of both, the fit time of each, their ratios, how many
  links ours wins and whether the whole robot meets the target (every link Pareto-better and
  no slower).

Each fitter's time is the fastest of ``--repeat`` (default 2) identical runs of the whole
robot, so that a moment of load on a shared machine does not decide the ratio.

Run: ``python benchmarks/bench_spheres.py [--robots panda ur5 kinova tiago_base]
[--total N ...] [--samples N] [--seed S] [--repeat N]``; ``--png FILE`` draws two Panda
links instead (docs/images/spheres_vs_morphit.png). Needs ``morphit-rs`` (the ``dev``
extra); threads are pinned to one so both timings are single-core.
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

#: ``mode: coverage``: each link's bound is the smallest at which its spheres cover this share
COVERAGE_MODE = 0.975

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


def _ours(
    geoms: Any,
    counts: dict[str, int],
    seed: int,
    budget: Any,
    coverage: float | None = None,
    refine: bool = True,
    repeat: int = 1,
) -> tuple[Any, float]:
    """Our spheres and the seconds of the fastest of ``repeat`` identical fits."""
    from xrdf_tools.spheres.count_policy import CountPolicy
    from xrdf_tools.spheres.robot_fit import fit_robot

    policy = CountPolicy(per_link=counts, count_coverage=coverage, refine=refine)
    best = float("inf")
    for _ in range(max(repeat, 1)):
        t0 = time.perf_counter()
        result = fit_robot("", geometry=geoms, counts=policy, seed=seed, max_protrusion=budget)
        best = min(best, time.perf_counter() - t0)
    return result.spheres, best


def equal_p95_budget(geom: Any, k: int, seed: int, p95: float, samples: int) -> float:
    """The largest protrusion bound (between 0.7 and 1.6 times MorphIt's p95, by bisection)
    whose fit keeps our protrusion p95 within MorphIt's: our operating point at equal p95."""
    from xrdf_tools.spheres import link_seed
    from xrdf_tools.spheres.metrics import measure

    def p95_at(factor: float) -> float:
        fitted, _ = _ours({geom.link: geom}, {geom.link: k}, seed, p95 * factor)
        m, _ = measure(
            geom.solid, fitted.get(geom.link, ()), samples=samples, seed=link_seed(seed, geom.link)
        )
        return float(m.protrusion_p95)

    lo, hi = 0.7, 1.6
    if p95 <= 0.0 or p95_at(lo) > p95:
        return p95 * lo
    for _ in range(6):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if p95_at(mid) <= p95 else (lo, mid)
    return p95 * lo


def bench_robot(
    name: str, total: int, samples: int, seed: int, repeat: int = 2
) -> list[dict[str, Any]]:
    from xrdf_tools.spheres import link_seed
    from xrdf_tools.spheres.geometry import load_link_geometry
    from xrdf_tools.spheres.metrics import measure, pooled

    rel, links, _ = ROBOTS[name]
    geoms, _ = load_link_geometry(_robots() / rel, links=links)
    counts = split_counts({k: float(g.solid.volume) for k, g in geoms.items()}, total)
    peer: dict[str, Any] = {}
    t_peer = float("inf")
    for _ in range(max(repeat, 1)):  # the fastest of `repeat` runs, like ours
        total_seconds = 0.0
        for link, g in geoms.items():
            peer[link], dt = morphit_fit(g.solid, counts[link], seed)
            total_seconds += dt
        t_peer = min(t_peer, total_seconds)

    def score(fitted: Any) -> tuple[list[Any], list[Any]]:
        got = [
            measure(g.solid, fitted.get(k, ()), samples=samples, seed=link_seed(seed, k))
            for k, g in geoms.items()
        ]
        return [m for m, _ in got], [p for _, p in got]

    m_peer, p_peer = score(peer)
    budget = {
        k: equal_p95_budget(g, counts[k], seed, m.protrusion_p95, samples)
        for (k, g), m in zip(geoms.items(), m_peer, strict=True)
    }
    ours_default, t_default = _ours(geoms, counts, seed, None, repeat=repeat)
    ours_hard, t_hard = _ours(geoms, counts, seed, None, refine=False, repeat=repeat)
    ours_matched, t_matched = _ours(geoms, counts, seed, budget, repeat=repeat)
    ours_coverage, t_coverage = _ours(geoms, counts, seed, None, COVERAGE_MODE, repeat=repeat)
    rows: list[dict[str, Any]] = []
    wins = {"default": 0, "hard": 0, "matched": 0, "coverage": 0}
    overall: dict[str, Any] = {"morphit": pooled(m_peer, p_peer)}
    fits = (
        ("default", ours_default),
        ("hard", ours_hard),
        ("matched", ours_matched),
        ("coverage", ours_coverage),
    )
    for mode, fitted in fits:
        m_ours, p_ours = score(fitted)
        overall[mode] = pooled(m_ours, p_ours)
        for (link, a), b in zip(zip(geoms, m_ours, strict=True), m_peer, strict=True):
            win = a.coverage >= b.coverage and a.protrusion_p95 <= b.protrusion_p95
            wins[mode] += win
            rows.append(
                {
                    "row": "link",
                    "robot": name,
                    "total": total,
                    "mode": mode,
                    "link": link,
                    "ours": _numbers(a),
                    "morphit": _numbers(b),
                    "pareto_better": bool(win),
                }
            )
    b_all = overall["morphit"]
    times = (
        ("default", t_default),
        ("hard", t_hard),
        ("matched", t_matched),
        ("coverage", t_coverage),
    )
    for mode, t_ours in times:
        a_all = overall[mode]
        rows.append(
            {
                "row": "robot",
                "robot": name,
                "total": total,
                "mode": mode,
                "ours": _numbers(a_all),
                "morphit": _numbers(b_all),
                "fit_seconds": {"ours": round(t_ours, 2), "morphit": round(t_peer, 2)},
                "ratio": {
                    "coverage": round(a_all.coverage / max(b_all.coverage, 1e-9), 3),
                    "protrusion_p95": round(
                        a_all.protrusion_p95 / max(b_all.protrusion_p95, 1e-9), 3
                    ),
                    "surface_gap_p95": round(
                        a_all.surface_gap_p95 / max(b_all.surface_gap_p95, 1e-9), 3
                    ),
                    "fit_seconds": round(t_ours / max(t_peer, 1e-9), 3),
                },
                "links_pareto_better": f"{wins[mode]}/{len(geoms)}",
                "target_met": bool(wins[mode] == len(geoms) and t_ours <= t_peer),
            }
        )
    return rows


def render_png(path: Path, links: list[str], total: int, seed: int, samples: int) -> None:
    """Panda links side by side: our default fit (left) and MorphIt's (right), same counts as
    the ``total`` run, each sphere drawn over the link's mesh."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    from xrdf_tools.spheres import link_seed
    from xrdf_tools.spheres.geometry import load_link_geometry
    from xrdf_tools.spheres.metrics import measure

    geoms, _ = load_link_geometry(_robots() / ROBOTS["panda"][0])
    counts = split_counts({k: float(g.solid.volume) for k, g in geoms.items()}, total)
    fig = plt.figure(figsize=(4.2 * 2, 3.8 * len(links)), dpi=110)
    u, v = np.meshgrid(np.linspace(0, 2 * np.pi, 24), np.linspace(0, np.pi, 12))
    for row, link in enumerate(links):
        g = geoms[link]
        peer, _ = morphit_fit(g.solid, counts[link], seed)
        m_peer, _ = measure(g.solid, peer, samples=samples, seed=link_seed(seed, link))
        ours, _ = _ours({link: g}, {link: counts[link]}, seed, None)
        m_ours, _ = measure(g.solid, ours[link], samples=samples, seed=link_seed(seed, link))
        for col, (name, spheres, m) in enumerate(
            (("ours", ours[link], m_ours), ("MorphIt", peer, m_peer))
        ):
            ax = fig.add_subplot(len(links), 2, 2 * row + col + 1, projection="3d")
            tris = np.asarray(g.solid.vertices)[np.asarray(g.solid.faces)]
            ax.add_collection3d(
                Poly3DCollection(tris, facecolor=(0.6, 0.6, 0.6, 0.25), edgecolor="none")
            )
            for s in spheres:
                c, r = np.asarray(s.center), s.radius
                ax.plot_surface(
                    c[0] + r * np.cos(u) * np.sin(v),
                    c[1] + r * np.sin(u) * np.sin(v),
                    c[2] + r * np.cos(v),
                    color=(0.15, 0.4, 0.85) if col == 0 else (0.85, 0.35, 0.15),
                    alpha=0.35,
                    linewidth=0,
                )
            lo, hi = np.asarray(g.solid.bounds)
            mid, half = (lo + hi) / 2, float((hi - lo).max()) / 2 * 1.15
            for setter, k in ((ax.set_xlim, 0), (ax.set_ylim, 1), (ax.set_zlim, 2)):
                setter(mid[k] - half, mid[k] + half)
            ax.set_box_aspect((1, 1, 1))
            ax.set_axis_off()
            ax.set_title(
                f"{link}, {name}: {len(spheres)} spheres\n"
                f"coverage {m.coverage:.3f}, protrusion p95 {m.protrusion_p95 * 1000:.1f} mm",
                fontsize=9,
            )
    fig.tight_layout()
    fig.savefig(path)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--robots", nargs="+", default=list(ROBOTS), choices=list(ROBOTS))
    ap.add_argument("--total", type=int, nargs="+", help="total spheres (default per robot)")
    ap.add_argument("--samples", type=int, default=20_000, help="metric samples per link")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument(
        "--repeat", type=int, default=2, help="timed runs of each fitter; the fastest counts"
    )
    ap.add_argument("--png", type=Path, help="also draw Panda links, ours beside MorphIt's")
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
    if args.png is not None:
        render_png(args.png, ["panda_link0", "panda_hand"], 57, args.seed, args.samples)
        return 0
    for name in args.robots:
        for total in args.total or ROBOTS[name][2]:
            for row in bench_robot(name, total, args.samples, args.seed, args.repeat):
                print(json.dumps(row), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
