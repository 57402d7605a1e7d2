"""Start-up of ``xrdf edit`` on the Franka Panda: command start to a usable page in a browser.

Usage: ``python benchmarks/bench_edit_startup.py [--runs 3]``

Each run starts ``xrdf edit fixtures/panda/panda.xrdf --urdf <example-robot-data panda>
--no-browser`` as a fresh subprocess and measures (1) the time until it prints its address
(robot, meshes and the 3D scene loaded, server listening) and (2) the time until headless
Chromium (the system's, via Playwright) shows the page's controls. Prints one JSON line with
the medians in seconds and their ratio to the 5 s goal (at most 1 is the goal), with the
machine's load average (a loaded machine is slower).
"""

from __future__ import annotations

import argparse
import json
import os
import signal
import statistics
import subprocess
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))

from tests.browser import CHROMIUM_ARGS, free_port  # noqa: E402

GOAL_S = 5.0


def one_run(urdf: Path, browser: object) -> tuple[float, float]:
    port = free_port()
    cmd = [sys.executable, "-c", "from xrdf_tools.cli import main; main()", "edit"]
    cmd += [str(REPO / "fixtures" / "panda" / "panda.xrdf"), "--urdf", str(urdf)]
    cmd += ["--port", str(port), "--no-browser"]
    t0 = time.perf_counter()
    proc = subprocess.Popen(
        cmd,
        cwd=REPO,
        stderr=subprocess.PIPE,
        stdout=subprocess.DEVNULL,
        text=True,
        env={**os.environ, "PYTHONUNBUFFERED": "1"},
    )
    assert proc.stderr is not None
    while "Ctrl-C stops" not in proc.stderr.readline():
        if proc.poll() is not None:
            raise SystemExit(f"xrdf edit ended early: {proc.stderr.read()}")
    served = time.perf_counter() - t0
    page = browser.new_page()  # type: ignore[attr-defined]
    page.goto(f"http://127.0.0.1:{port}")
    page.get_by_text("Default pose").wait_for(timeout=60_000)
    usable = time.perf_counter() - t0
    page.close()
    proc.send_signal(signal.SIGINT)
    proc.communicate(timeout=30)
    return served, usable


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--chromium", default="/usr/bin/chromium")
    args = parser.parse_args()
    sys.path.insert(0, str(REPO))
    from playwright.sync_api import sync_playwright

    from tests.robots import robot_urdf

    urdf = robot_urdf("panda")
    with sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=args.chromium, args=CHROMIUM_ARGS)
        runs = [one_run(urdf, browser) for _ in range(args.runs)]
        browser.close()
    served = statistics.median(r[0] for r in runs)
    usable = statistics.median(r[1] for r in runs)
    print(
        json.dumps(
            {
                "robot": "panda",
                "runs": args.runs,
                "served_s": round(served, 3),
                "page_usable_s": round(usable, 3),
                "goal_s": GOAL_S,
                "ratio_to_goal": round(usable / GOAL_S, 3),
                "load_average": [round(x, 2) for x in os.getloadavg()],
            }
        )
    )


if __name__ == "__main__":
    main()
