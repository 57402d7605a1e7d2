"""Run the ``xrdf`` CLI on thousands of mutated inputs and count what went wrong.

    python benchmarks/fuzz_cli.py                      # 10,000 runs, 2 workers, 20 s per run
    python benchmarks/fuzz_cli.py --runs 500 --seed 7  # another sample
    python benchmarks/fuzz_cli.py --case 1234          # replay one case, show its output
    python benchmarks/fuzz_cli.py --corpus crashes/    # keep the inputs of failing cases

Cases come from ``tests/fuzzing.py`` (seeded mutations of the files in ``fixtures/``, every
command). Each worker process runs cases in-process; the parent kills a worker whose case runs
longer than ``--timeout`` and counts a hang. Printed at the end: runs per exit code, tracebacks,
hangs, internal errors, changed inputs, errors without a location, and the failing cases (replay
them with ``--case``).
Exit status 1 when anything failed. See docs/security.md.
"""

from __future__ import annotations

import argparse
import multiprocessing as mp
import shutil
import sys
import tempfile
import time
from collections import Counter
from dataclasses import dataclass
from multiprocessing.connection import Connection, wait
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))

from tests.fuzzing import make_case, prepare, run_case  # noqa: E402

Result = tuple[int, int, list[str], str, float]  # case, exit code, problems, summary, seconds


def _worker(conn: Connection, base: str, run_seed: int) -> None:
    import warnings

    warnings.simplefilter("ignore")  # numpy overflow warnings etc. are not failures
    while True:
        number = conn.recv()
        if number is None:
            return
        case = make_case(number, run_seed)
        work = Path(tempfile.mkdtemp(dir=base))
        start = time.monotonic()
        try:
            outcome = run_case(case, work)
            result: Result = (
                number,
                outcome.exit_code,
                outcome.problems,
                outcome.summary(),
                time.monotonic() - start,
            )
        except Exception as e:  # the harness itself failed: report, keep going
            result = (number, -1, [f"harness error: {e!r}"], f"case {number}: harness error", 0.0)
        finally:
            shutil.rmtree(work, ignore_errors=True)
        conn.send(result)


@dataclass
class _Slot:
    proc: mp.process.BaseProcess
    conn: Connection
    case: int | None = None
    started: float = 0.0


def _start(ctx: mp.context.BaseContext, base: str, run_seed: int) -> _Slot:
    parent, child = ctx.Pipe()
    proc = ctx.Process(target=_worker, args=(child, base, run_seed), daemon=True)
    proc.start()
    child.close()
    return _Slot(proc, parent)


def run(runs: int, run_seed: int, jobs: int, timeout: float) -> tuple[Counter[str], list[str]]:
    """Run cases 0..runs-1; return counters and the summaries of failing cases."""
    ctx = mp.get_context("fork" if sys.platform.startswith("linux") else "spawn")
    base = tempfile.mkdtemp(prefix="xrdf-fuzz-")
    counts: Counter[str] = Counter()
    failures: list[str] = []
    todo = iter(range(runs))
    slots = [_start(ctx, base, run_seed) for _ in range(jobs)]
    done = 0
    t0 = time.monotonic()
    try:
        for s in slots:
            _feed(s, todo)
        while any(s.case is not None for s in slots):
            ready = wait([s.conn for s in slots if s.case is not None], timeout=0.5)
            now = time.monotonic()
            for i, s in enumerate(slots):
                if s.case is None:
                    continue
                if s.conn in ready:
                    try:
                        number, code, problems, summary, _ = s.conn.recv()
                    except EOFError:  # the worker died (a crash of the interpreter itself)
                        number, code, problems = s.case, -1, ["worker died"]
                        summary = f"case {number}: worker died"
                        slots[i] = s = _restart(s, ctx, base, run_seed)
                    counts[f"exit {code}"] += 1
                    for p in problems:
                        counts[p.split(":")[0]] += 1
                    if problems:
                        failures.append(summary)
                elif now - s.started > timeout:
                    counts["hang"] += 1
                    failures.append(f"case {s.case}: hang (over {timeout:g} s)")
                    slots[i] = s = _restart(s, ctx, base, run_seed)
                else:
                    continue
                done += 1
                s.case = None
                _feed(s, todo)
                if done % 500 == 0:
                    rate = done / (time.monotonic() - t0)
                    print(f"{done}/{runs} runs ({rate:.1f}/s), {len(failures)} failing", flush=True)
    finally:
        for s in slots:
            if s.proc.is_alive():
                s.conn.send(None)
                s.proc.join(5)
            if s.proc.is_alive():
                s.proc.kill()
        shutil.rmtree(base, ignore_errors=True)
    return counts, failures


def _feed(slot: _Slot, todo: object) -> None:
    number = next(todo, None)  # type: ignore[call-overload]
    if number is not None:
        slot.case = number
        slot.started = time.monotonic()
        slot.conn.send(number)


def _restart(slot: _Slot, ctx: mp.context.BaseContext, base: str, run_seed: int) -> _Slot:
    slot.proc.kill()  # a worker this script started, by its own handle
    slot.proc.join(5)
    fresh = _start(ctx, base, run_seed)
    fresh.case, fresh.started = slot.case, slot.started
    return fresh


def replay(number: int, run_seed: int) -> int:
    case = make_case(number, run_seed)
    with tempfile.TemporaryDirectory(prefix="xrdf-fuzz-case-") as d:
        outcome = run_case(case, Path(d))
    print(outcome.output, end="")
    print(f"--- {outcome.summary()}")
    return 1 if outcome.problems else 0


def keep(numbers: list[int], run_seed: int, corpus: Path) -> None:
    """Write the inputs and command line of each failing case under ``corpus/case-N``."""
    for n in numbers:
        dest = corpus / f"case-{n}"
        shutil.rmtree(dest, ignore_errors=True)
        dest.mkdir(parents=True)
        case = make_case(n, run_seed)
        if case.special is not None:
            (dest / "README").write_text(f"{case.kind} replaced by a {case.special}\n")
            continue
        args = prepare(case, dest)
        (dest / "command").write_text("xrdf " + " ".join(args) + "\n")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--runs", type=int, default=10_000)
    ap.add_argument("--seed", type=int, default=0, help="run seed (cases differ per seed)")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--timeout", type=float, default=20.0, help="seconds per run")
    ap.add_argument("--case", type=int, help="replay one case and print its output")
    ap.add_argument("--corpus", type=Path, help="keep the inputs of failing cases here")
    a = ap.parse_args()
    if a.case is not None:
        return replay(a.case, a.seed)
    t0 = time.monotonic()
    counts, failures = run(a.runs, a.seed, a.jobs, a.timeout)
    total = sum(v for k, v in counts.items() if k.startswith("exit ")) + counts["hang"]
    print(f"\n{total} runs in {time.monotonic() - t0:.0f} s (seed {a.seed})")
    for code in ("exit 0", "exit 1", "exit 2"):
        print(f"  {code}: {counts[code]}")
    for label in (
        "traceback",
        "hang",
        "internal-error finding",
        "an input file changed",
        "no location",
    ):
        print(f"  {label}: {counts[label]}")
    other = {k: v for k, v in counts.items() if k.startswith(("exit -", "exit code", "harness"))}
    for k, v in sorted(other.items()):
        print(f"  {k}: {v}")
    for f in failures[:50]:
        print("  " + f)
    if a.corpus is not None and failures:
        keep([int(f.split()[1].rstrip(":")) for f in failures], a.seed, a.corpus)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
