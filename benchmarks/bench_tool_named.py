"""What ranking the tool-like frames fixed below a link costs with thousands of them.

``convert`` ranks the frames fixed below the tool frame by their names
(:func:`~xrdf_tools.robot.tool_frame.tool_named`): for the default guess and, with an SRDF, for
the note on an end effector's parent link. Each rank's hits were checked against a set of the
frames ranked so far built anew for every hit: quadratic, 17 s of a 22 s ``convert --srdf`` of
a robot with 20,000 frames named like tool frames below its wrist. The set is now kept.

Prints one JSON line per frame count: the seconds of today's function and of the former one
(copied here, run in this process on the same frames), and that both rank alike.

Usage: ``python benchmarks/bench_tool_named.py [--frames 2000,20000]``
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from xrdf_tools.robot.names import TOOL_RANKS, name_words, says_sensor
from xrdf_tools.robot.tool_frame import tool_named

WORDS = ("tool", "tcp", "ee", "flange", "grasp", "eef", "end_effector", "camera_tool")


def former(below: list[tuple[str, int]]) -> list[tuple[str, str]]:
    """tool_named before the kept set (the baseline)."""
    out = [(n, "tool0") for n, _ in below if n == "tool0"]
    for rank, words in TOOL_RANKS:
        hits = sorted(
            (d, n)
            for n, d in below
            if n != "tool0" and set(name_words(n)) & words and not says_sensor(n)
        )
        out += [(n, rank) for _, n in hits if n not in {f for f, _ in out}]
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--frames", default="2000,20000")
    args = parser.parse_args()
    for n in (int(v) for v in args.frames.split(",")):
        below = [("wrist", 0), *((f"{WORDS[i % len(WORDS)]}_{i}", 1 + i % 3) for i in range(n))]
        figures = {}
        for name, fn in (("today", tool_named), ("former", former)):
            start = time.perf_counter()
            ranked = fn(below)
            figures[name] = (round(time.perf_counter() - start, 3), ranked)
        same = figures["today"][1] == figures["former"][1]
        row = {"frames": n, "s": figures["today"][0], "former_s": figures["former"][0]}
        print(json.dumps({**row, "same_ranking": same}))


if __name__ == "__main__":
    main()
