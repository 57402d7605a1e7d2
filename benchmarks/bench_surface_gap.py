"""What the default count's surface criterion (:mod:`xrdf_tools.spheres.surface_gap`) costs.

Fits each robot's links by default count twice per round in one process, with the criterion
(``CountPolicy()``) and without it (``CountPolicy(reach_surface=False)``: the volume target
alone, the count before the criterion), alternating which goes first, from solids loaded once;
each time is the fastest of ``--repeat`` rounds, so that a moment of load on a shared machine
does not decide the ratio. Prints one JSON line per robot: the times, their ratio, the links
whose spheres differ and their metrics both ways (lengths in mm).

Run: ``python benchmarks/bench_surface_gap.py [--robots panda ur5] [--repeat 3]``; threads are
pinned to one.
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import json  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402
from typing import Any  # noqa: E402

#: robot -> URDF below example-robot-data's robots/
ROBOTS = {
    "panda": "panda_description/urdf/panda.urdf",
    "ur5": "ur_description/urdf/ur5_robot.urdf",
    "kinova": "kinova_description/robots/kinova.urdf",
    "z1": "z1_description/urdf/z1.urdf",
}


def _robots() -> Path:
    import trimesh

    return (
        Path(trimesh.__file__).resolve().parents[1] / "cmeel.prefix/share/example-robot-data/robots"
    )


def _fit(geoms: Any, reach: bool) -> tuple[Any, float]:
    from xrdf_tools.spheres.count_policy import CountPolicy
    from xrdf_tools.spheres.robot_fit import fit_robot

    t0 = time.perf_counter()
    result = fit_robot("", geometry=geoms, counts=CountPolicy(reach_surface=reach))
    return result, time.perf_counter() - t0


def _metrics(geoms: Any, spheres: Any) -> dict[str, float]:
    from xrdf_tools.spheres.metrics import sphere_metrics

    m = sphere_metrics(geoms.solid, spheres, samples=20000)
    return {
        "spheres": m.sphere_count,
        "coverage": round(m.coverage, 4),
        "protrusion_p95": round(m.protrusion_p95 * 1000, 2),
        "surface_gap_p95": round(m.surface_gap_p95 * 1000, 2),
        "max_uncovered_gap": round(m.max_uncovered_gap * 1000, 2),
    }


def run(robot: str, repeat: int) -> dict[str, Any]:
    from xrdf_tools.spheres.robot_fit import fit_robot

    loaded = fit_robot(_robots() / ROBOTS[robot], counts=_policy_one(), visual_check="off")
    geoms = loaded.geometry
    best = {False: float("inf"), True: float("inf")}
    results: dict[bool, Any] = {}
    for r in range(repeat):
        for reach in (r % 2 == 0, r % 2 != 0):
            results[reach], seconds = _fit(geoms, reach)
            best[reach] = min(best[reach], seconds)
    changed = [n for n in geoms if results[True].spheres[n] != results[False].spheres[n]]
    return {
        "robot": robot,
        "links": len(geoms),
        "fit_s_volume_only": round(best[False], 3),
        "fit_s_with_surface": round(best[True], 3),
        "ratio": round(best[True] / best[False], 3),
        "changed": {
            n: {
                "before": _metrics(geoms[n], results[False].spheres[n]),
                "after": _metrics(geoms[n], results[True].spheres[n]),
            }
            for n in changed
        },
    }


def _policy_one() -> Any:
    """One sphere per link: the quickest fit that loads every link's solid."""
    from xrdf_tools.spheres.count_policy import CountPolicy

    return CountPolicy(per_link=1, refine=False)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--robots", nargs="+", default=["panda", "ur5"], choices=sorted(ROBOTS))
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    for robot in args.robots:
        print(json.dumps(run(robot, args.repeat)), flush=True)


if __name__ == "__main__":
    main()
