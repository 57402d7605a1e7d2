"""What bounding xacro expansion in time and memory costs: an expansion in a child process
(fork, or the fork server when another Python thread runs) against the same expansion in
this process, as before the bound.

Usage: ``python benchmarks/bench_xacro_bound.py [--runs 21] [FILE.xacro]``

In one process, alternately (the same machine load for each): ``expand_xacro`` with the
default bounds from the main thread (a fork), from a second thread while one more runs (the
fork server, started by the warm-up), and with both bounds off (``XRDF_XACRO_TIMEOUT=0``,
``XRDF_XACRO_MEMORY=0``: the expansion in this process, the baseline). Then ``xrdf expand
FILE`` as fresh processes, bounded and unbounded, alternately: the whole command, the first
expansion's imports included. Prints one JSON line: medians in milliseconds and the
overheads. The default file is the bundled ``fixtures/fuzz/arm.urdf.xacro``; rtb-data's
Frankie (a mobile Panda in 7 files) is measured when installed.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import os
import statistics
import subprocess
import sys
import threading
import time
from collections.abc import Callable
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))

from xrdf_tools.robot.xacro_child import ENV_MEMORY, ENV_TIMEOUT  # noqa: E402
from xrdf_tools.robot.xacro_source import expand_xacro  # noqa: E402

FIXTURE = REPO / "fixtures" / "fuzz" / "arm.urdf.xacro"
FRANKIE = Path("xacro", "qut_frankie_description", "robots", "frankie_arm_hand.urdf.xacro")
UNBOUNDED = {ENV_TIMEOUT: "0", ENV_MEMORY: "0"}


def frankie() -> tuple[Path, dict[str, str]] | None:
    spec = importlib.util.find_spec("rtbdata")
    if spec is None or not spec.submodule_search_locations:
        return None
    root = Path(next(iter(spec.submodule_search_locations)))
    if not (root / FRANKIE).is_file():
        return None
    return root / FRANKIE, {"qut_frankie_description": str(root / FRANKIE.parents[1])}


def timed(fn: Callable[[], object]) -> float:
    start = time.perf_counter()
    fn()
    return time.perf_counter() - start


def in_thread(fn: Callable[[], object]) -> Callable[[], object]:
    """``fn`` run in a second thread while a third one waits: the fork server's case."""

    def run() -> object:
        stop = threading.Event()
        idle = threading.Thread(target=stop.wait)
        idle.start()
        out: list[object] = []
        worker = threading.Thread(target=lambda: out.append(fn()))
        worker.start()
        worker.join()
        stop.set()
        idle.join()
        return out[0]

    return run


def with_env(extra: dict[str, str], fn: Callable[[], object]) -> Callable[[], object]:
    def run() -> object:
        saved = {k: os.environ.get(k) for k in extra}
        os.environ.update(extra)
        try:
            return fn()
        finally:
            for k, v in saved.items():
                if v is None:
                    os.environ.pop(k, None)
                else:
                    os.environ[k] = v

    return run


def medians_ms(cases: dict[str, Callable[[], object]], runs: int) -> dict[str, float]:
    for fn in cases.values():  # warm-up: imports, the fork server, the file cache
        fn()
    times: dict[str, list[float]] = {name: [] for name in cases}
    for _ in range(runs):
        for name, fn in cases.items():
            times[name].append(timed(fn))
    return {name: round(statistics.median(t) * 1000, 1) for name, t in times.items()}


def library(path: Path, pkg: dict[str, str], runs: int) -> dict[str, float]:
    def expand() -> object:
        return expand_xacro(path, package_paths=pkg)

    base = with_env(UNBOUNDED, expand)
    if expand() != base():
        sys.exit(f"{path}: the bounded expansion differs from the one in this process")
    cases = {"in_process": base, "fork": expand, "fork_server": in_thread(expand)}
    out = medians_ms(cases, runs)
    out["fork_overhead_ms"] = round(out["fork"] - out["in_process"], 1)
    out["fork_server_overhead_ms"] = round(out["fork_server"] - out["in_process"], 1)
    return out


def command(path: Path, pkg: dict[str, str], runs: int) -> dict[str, float]:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(p for p in (str(REPO), env.get("PYTHONPATH")) if p)
    cmd = [sys.executable, "-m", "xrdf_tools", "expand", str(path)]
    for name, where in pkg.items():
        cmd += ["--package-path", f"{name}={where}"]

    def run(extra: dict[str, str]) -> Callable[[], object]:
        def go() -> object:
            done = subprocess.run(cmd, cwd=REPO, env={**env, **extra}, capture_output=True)
            if done.returncode != 0:
                sys.exit(f"xrdf expand failed: {done.stderr.decode().strip()}")
            return done

        return go

    out = medians_ms({"command_in_process": run(UNBOUNDED), "command_bounded": run({})}, runs)
    out["command_overhead_ms"] = round(out["command_bounded"] - out["command_in_process"], 1)
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("file", nargs="?", type=Path)
    ap.add_argument("--runs", type=int, default=21, help="timed runs of each case")
    args = ap.parse_args()
    robots: dict[str, tuple[Path, dict[str, str]]] = {}
    if args.file is not None:
        robots[args.file.name] = (args.file.resolve(), {})
    else:
        robots["arm"] = (FIXTURE, {})
        if (found := frankie()) is not None:
            robots["frankie"] = found
    for name, (path, pkg) in robots.items():
        out: dict[str, object] = {"benchmark": "xacro_bound", "robot": name, "runs": args.runs}
        out.update(library(path, pkg, args.runs))
        out.update(command(path, pkg, max(5, args.runs // 2)))
        print(json.dumps(out), flush=True)


if __name__ == "__main__":
    main()
