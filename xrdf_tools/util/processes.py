"""Starting child processes that a Ctrl-C at the terminal does not reach."""

from __future__ import annotations

import signal
from collections.abc import Iterator
from contextlib import contextmanager

__all__ = ["sigint_held"]


@contextmanager
def sigint_held(*, start_tracker: bool = True) -> Iterator[None]:
    """SIGINT held back in this thread while child processes start: a process or thread started
    meanwhile inherits the mask, so a Ctrl-C at the terminal, which reaches the whole process
    group, never prints a child's traceback; a Ctrl-C meanwhile is raised when the block
    ends. (multiprocessing's resource tracker, which unblocks SIGINT after starting, is
    started before, unless ``start_tracker`` is false: children forked with a pipe, which
    start no tracker.)"""
    if not hasattr(signal, "pthread_sigmask"):  # not on POSIX
        yield
        return
    if start_tracker:
        from multiprocessing import resource_tracker

        resource_tracker.ensure_running()
    old = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    try:
        yield
    finally:
        held = signal.SIGINT in signal.sigpending()
        signal.pthread_sigmask(signal.SIG_SETMASK, old)
        if held:
            signal.raise_signal(signal.SIGINT)
