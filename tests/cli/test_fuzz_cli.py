"""Every command on seeded mutations of the real fixtures (``tests/fuzzing.py``): exit code 0, 1
or 2, never a traceback, a hang or an ``internal-error`` finding, and the inputs unchanged.

CI runs a fixed slice of the cases (about half a minute); ``benchmarks/fuzz_cli.py`` runs
10,000+ of them locally (docs/security.md). A failing case is replayed with
``python benchmarks/fuzz_cli.py --seed 0 --case N``; keep it as a regression test in
``tests/cli/test_cli_regressions.py``.
"""

from __future__ import annotations

import signal
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import pytest

from tests.fuzzing import SCENARIOS, make_case, run_case

#: The run seeds of the CI slices, their sizes, and how they are split (so ``-n 2`` shares
#: them): seed 0 in full, a second seed smaller (other cases of the same generators, among them
#: numbers pushed to extremes, huge ``-n`` and a faulty standard output).
CI_SEED = 0
CHUNKS = 8
PER_CHUNK = 30
SECOND_SEED = 1
SECOND_CHUNKS = 2
#: A run longer than this is a hang (the CLI's own budget is seconds).
DEADLINE_S = 20


@contextmanager
def _deadline(seconds: int) -> Iterator[None]:
    """Raise TimeoutError after ``seconds`` (POSIX main thread only; elsewhere no limit)."""
    usable = hasattr(signal, "setitimer") and threading.current_thread() is threading.main_thread()
    if not usable:
        yield
        return

    def expire(_signum: int, _frame: object) -> None:
        raise TimeoutError(f"run took more than {seconds} s")

    old = signal.signal(signal.SIGALRM, expire)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)


@pytest.mark.slow
@pytest.mark.filterwarnings("ignore::UserWarning")
@pytest.mark.parametrize(
    ("seed", "chunk"),
    [(CI_SEED, c) for c in range(CHUNKS)] + [(SECOND_SEED, c) for c in range(SECOND_CHUNKS)],
)
def test_cli_survives_mutated_inputs(seed: int, chunk: int, tmp_path: Path) -> None:
    failures = []
    for number in range(chunk * PER_CHUNK, (chunk + 1) * PER_CHUNK):
        case = make_case(number, seed, slow=False)
        work = tmp_path / f"case-{number}"
        work.mkdir()
        try:
            with _deadline(DEADLINE_S):
                outcome = run_case(case, work)
        except TimeoutError:
            failures.append(f"case {number}: hang ({case.scenario.name}, {'; '.join(case.ops)})")
            continue
        if outcome.problems:
            failures.append(outcome.summary())
    assert not failures, "\n".join(failures)


def test_cases_are_reproducible_and_cover_every_fast_scenario() -> None:
    a, b = make_case(17, 3), make_case(17, 3)
    assert (a.scenario, a.kind, a.ops, a.text) == (b.scenario, b.kind, b.ops, b.text)
    assert make_case(17, 4).text != a.text or make_case(17, 4).scenario != a.scenario
    cases = [make_case(n, CI_SEED, slow=False) for n in range(CHUNKS * PER_CHUNK)]
    assert {c.scenario.name for c in cases} == {s.name for s in SCENARIOS if not s.slow}
    ops = " ".join(op for c in cases for op in c.ops)
    assert "extreme " in ops and "-n " in ops and "standard output " in ops
