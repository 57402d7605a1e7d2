"""Forward-kinematics throughput: xrdf_tools batched FK vs a per-configuration yourdfpy loop.

Usage: ``python benchmarks/bench_fk.py [--batch 4096] [--chunks 50] [--naive 200]``

Prints one JSON line: configurations per second for ``fk`` (4x4 output), ``fk_rt`` and
``fk_batch_last`` with a reused output buffer, all frames of the example-robot-data Panda at
the given batch size, and for yourdfpy (``update_cfg`` + ``get_transform`` of every frame,
one configuration at a time) on a smaller sample, plus the speed-up.
"""

from __future__ import annotations

import argparse
import importlib.metadata
import json
import logging
import platform
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

from xrdf_tools.robot.kinematics import build_kinematic_model, fk, fk_batch_last, fk_rt
from xrdf_tools.robot.urdf_source import load_urdf

PANDA = Path("cmeel.prefix/share/example-robot-data/robots/panda_description/urdf/panda.urdf")


def panda_path() -> Path:
    dist = importlib.metadata.distribution("example-robot-data")
    return Path(str(dist.locate_file(PANDA)))


def rate(fn: Callable[[], object], configs_per_call: int, calls: int) -> float:
    fn()  # warm up
    start = time.perf_counter()
    for _ in range(calls):
        fn()
    return configs_per_call * calls / (time.perf_counter() - start)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--batch", type=int, default=4096)
    ap.add_argument("--chunks", type=int, default=50, help="batches timed per variant")
    ap.add_argument("--naive", type=int, default=200, help="configurations for yourdfpy")
    args = ap.parse_args()
    logging.getLogger("yourdfpy").setLevel(logging.ERROR)

    urdf = load_urdf(panda_path(), build_scene_graph=True)
    model, _ = build_kinematic_model(urdf)
    rng = np.random.default_rng(0)
    q = rng.uniform(model.lower, model.upper, size=(args.batch, model.n_actuated))
    B, F = args.batch, model.n_frames
    buf = (np.empty((F, 3, 3, B)), np.empty((F, 3, B)))

    fk_rate = rate(lambda: fk(model, q), B, args.chunks)
    rt_rate = rate(lambda: fk_rt(model, q), B, args.chunks)
    bl_rate = rate(lambda: fk_batch_last(model, q, out=buf), B, args.chunks)

    names = model.actuated_joints
    frames = model.frame_names
    qn = q[: args.naive]

    def naive() -> None:
        for row in qn:
            urdf.update_cfg(dict(zip(names, row.tolist(), strict=True)))
            for f in frames:
                urdf.get_transform(f)

    naive_rate = rate(naive, len(qn), 1)
    print(
        json.dumps(
            {
                "benchmark": "fk",
                "robot": "panda (example-robot-data)",
                "frames": F,
                "actuated_joints": model.n_actuated,
                "batch": B,
                "fk_configs_per_s": round(fk_rate),
                "fk_rt_configs_per_s": round(rt_rate),
                "fk_batch_last_out_configs_per_s": round(bl_rate),
                "yourdfpy_loop_configs_per_s": round(naive_rate),
                "yourdfpy_configs": len(qn),
                "speedup_fk_vs_yourdfpy": round(fk_rate / naive_rate, 1),
                "numpy": np.__version__,
                "python": platform.python_version(),
            }
        )
    )


if __name__ == "__main__":
    main()
