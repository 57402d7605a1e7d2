"""Run a xacro expansion in a child process bounded in wall time and memory.

xacro evaluates Python expressions: ``${9**9**9}`` computes for hours inside one C call that
no signal interrupts, ``${'a'*10**11}`` asks for 100 GB, a macro calling itself twice per
level fans out exponentially. So the expansion runs in a child process: this process waits
at most ``XRDF_XACRO_TIMEOUT`` seconds (default 60) and kills it past that; on Linux the
child's address space is limited to its size at start plus ``XRDF_XACRO_MEMORY`` MiB
(default 2048), so a bomb is a ``MemoryError`` there. Either is one :class:`SourceError`
naming the file and the variable that raises the limit. Real robots expand in well under a
second, in tens of MiB.

The child is a fork of this process when no other Python thread runs (Linux; nothing is
imported again: a few milliseconds); where another thread might hold a lock that ``fork``
would leave held forever, it is forked from multiprocessing's fork server (started once,
about 0.3 s), or spawned where there is none; such a child does not import the caller's
main script again. On Linux the child is killed with its parent, even one killed outright.
The value or the exception comes back pickled
through a pipe, so the caller gets what an expansion in this process would give. Both
variables ``0``: the expansion runs in this process, unbounded, as it does in a daemonic
multiprocessing worker (which may not start processes).
"""

from __future__ import annotations

import importlib
import math
import os
import signal
import sys
import threading
import time
import warnings
from collections.abc import Callable, Iterator
from contextlib import contextmanager, suppress
from dataclasses import dataclass
from pathlib import Path
from typing import Any, TypeVar

from ..util.errors import InputError, SourceError

__all__ = [
    "ENV_MEMORY",
    "ENV_TIMEOUT",
    "Bounds",
    "XacroBoundError",
    "bounds",
    "out_of_memory",
    "run_bounded",
    "stop_children",
]

ENV_TIMEOUT = "XRDF_XACRO_TIMEOUT"
ENV_MEMORY = "XRDF_XACRO_MEMORY"
DEFAULT_TIMEOUT_S = 60.0
DEFAULT_MEMORY_MIB = 2048.0
#: How long one wait for the child lasts: a signal handler runs only when a wait returns.
_POLL_S = 0.2
#: How long a child that has answered (or is past its time) may take to exit.
_EXIT_GRACE_S = 1.0
#: The exit code of a child that ran out of memory even to say so.
_EXIT_NO_MEMORY = 86
_BUDGET_HINT = "an expression such as ${SAMPLE} or a macro fan-out?"
#: The name of the expanding child (its preparation imports no main script).
_CHILD_NAME = "xrdf-xacro-expansion"
#: prctl(2): the signal a process receives when its parent ends.
_PR_SET_PDEATHSIG = 1

T = TypeVar("T")

#: The children expanding now (killed by :func:`stop_children`).
_LIVE: set[Any] = set()
_LIVE_LOCK = threading.Lock()


class XacroBoundError(SourceError):
    """A xacro expansion ran out of time or memory (no other reading of the file can do
    better)."""


@dataclass(frozen=True)
class Bounds:
    """The limits of one expansion: seconds of wall time and MiB beyond the child's size at
    start (None: unbounded)."""

    seconds: float | None
    mib: float | None


def bounds() -> Bounds:
    """The limits ``XRDF_XACRO_TIMEOUT`` (seconds) and ``XRDF_XACRO_MEMORY`` (MiB) set."""
    return Bounds(
        _limit(ENV_TIMEOUT, DEFAULT_TIMEOUT_S, "seconds"),
        _limit(ENV_MEMORY, DEFAULT_MEMORY_MIB, "MiB"),
    )


def _limit(name: str, default: float, unit: str) -> float | None:
    raw = os.environ.get(name, "").strip()
    if not raw:
        return default
    try:
        value = float(raw)
    except ValueError:
        value = math.nan
    if not (math.isfinite(value) and value >= 0):
        raise InputError(f"{name}={raw!r} must be a number of {unit} (0: no limit)")
    return value or None


def out_of_memory(e: BaseException) -> bool:
    """Whether ``e`` is, wraps or was raised while handling a ``MemoryError`` (xacro wraps an
    expression's exception in its own; a conditional drops it, keeping it as the context)."""
    seen: set[int] = set()
    todo: list[BaseException | None] = [e]
    while todo:
        err = todo.pop()
        if err is None or id(err) in seen:
            continue
        if isinstance(err, MemoryError):
            return True
        seen.add(id(err))
        inner = getattr(err, "exc", None)
        todo += [
            err.__cause__,
            err.__context__,
            inner if isinstance(inner, BaseException) else None,
        ]
    return False


def run_bounded(
    fn: Callable[..., T],
    args: tuple[Any, ...],
    path: str | os.PathLike[str],
    preload: tuple[str, ...] = (),
) -> T:
    """``fn(*args)`` (the expansion of the xacro file ``path``) within :func:`bounds`: its value,
    or the exception it raised; :class:`XacroBoundError` at ``path`` when it runs out of time
    or memory. ``fn`` and ``args`` are pickled unless the child is a fork. The modules of
    ``preload`` are imported before the child starts (here, or in the fork server), so that
    no child imports them again."""
    import multiprocessing

    limits = bounds()
    unbounded = limits.seconds is None and limits.mib is None
    if unbounded or multiprocessing.current_process().daemon:
        try:
            return fn(*args)
        except MemoryError:
            raise XacroBoundError(_no_memory(None), path=os.fspath(path)) from None
    try:
        kind, value = _in_child(fn, args, limits, preload)
    except SourceError as e:  # no process could be started: said at the file it was for
        if e.path is None:
            e.path = os.fspath(path)
        raise
    if kind == "value":
        return value  # type: ignore[no-any-return]
    if kind == "raised":
        raise value
    if kind == "died":
        raise SourceError(value, path=os.fspath(path))
    message = _no_time(limits.seconds) if kind == "time" else _no_memory(limits.mib)
    raise XacroBoundError(message, path=os.fspath(path))


def _no_time(seconds: float | None) -> str:
    hint = _BUDGET_HINT.replace("SAMPLE", "9**9**9")
    return (
        f"xacro expansion did not finish in {seconds:g} s ({hint}); "
        f"raise the limit with {ENV_TIMEOUT}=SECONDS"
    )


def _no_memory(mib: float | None) -> str:
    hint = _BUDGET_HINT.replace("SAMPLE", "'a'*10**11")
    if mib is None:
        return f"xacro expansion ran out of memory ({hint})"
    return (
        f"xacro expansion needed more than {mib:g} MiB of memory ({hint}); "
        f"raise the limit with {ENV_MEMORY}=MIB"
    )


def _in_child(
    fn: Callable[..., Any], args: tuple[Any, ...], limits: Bounds, preload: tuple[str, ...]
) -> tuple[str, Any]:
    """What the child says: ("value", v), ("raised", e), ("memory", None), ("time", None)
    or ("died", why)."""
    import multiprocessing

    from ..util.processes import sigint_held

    method = _start_method()
    ctx = multiprocessing.get_context(method)
    preload = (*preload, "ctypes")  # _end_with_parent's
    if method == "fork":
        for name in preload:
            importlib.import_module(name)
    else:
        _without_main_module()
    if method == "forkserver":
        ctx.set_forkserver_preload([fn.__module__, *preload])
    receive, send = ctx.Pipe(duplex=False)
    answered = False
    # a forked child shares this process's directory and environment; another is given them
    here = None if method == "fork" else (_working_directory(), dict(os.environ))
    parent = os.getpid() if method != "forkserver" else None
    child: Any = ctx.Process(  # type: ignore[attr-defined]
        target=_child,
        args=(send, fn, args, limits, here, parent),
        daemon=True,
        name=_CHILD_NAME,
    )
    try:
        try:
            with sigint_held(start_tracker=method != "fork"), _quiet_fork(method):
                child.start()
        except OSError as e:  # no process can be started (a process limit, a sandbox)
            raise SourceError(
                f"cannot start the process that expands xacro ({e.strerror or e}); set "
                f"{ENV_TIMEOUT}=0 and {ENV_MEMORY}=0 to expand in this process, unbounded"
            ) from None
        with _LIVE_LOCK:
            _LIVE.add(child)
        send.close()
        said = _wait(receive, child, limits.seconds)
        answered = said[0] != "time"
        return said
    finally:
        send.close()
        _stop(child, _EXIT_GRACE_S if answered else 0.0)
        receive.close()


@contextmanager
def _quiet_fork(method: str) -> Iterator[None]:
    """Python 3.12+ warns of any fork while a native thread runs (a BLAS pool); with no other
    Python thread (see :func:`_one_thread`) that warning is not for this fork, and changing
    the warning filters is safe."""
    if method != "fork":
        yield
        return
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", "This process .* is multi-threaded", DeprecationWarning)
        yield


def _wait(receive: Any, child: Any, seconds: float | None) -> tuple[str, Any]:
    """The child's message, or ("time", None) when none came within ``seconds``."""
    end = None if seconds is None else time.monotonic() + seconds
    while not receive.poll(_POLL_S):
        if end is not None and time.monotonic() >= end:
            return "time", None
    try:
        said: tuple[str, Any] = receive.recv()
    except EOFError:  # it ended without a word
        child.join()
        return _death(child.exitcode)
    return said


def _death(code: int | None) -> tuple[str, Any]:
    """What the exit code of a child that sent nothing means."""
    signum = -code if code is not None and code < 0 else None
    if code == _EXIT_NO_MEMORY or signum == getattr(signal, "SIGKILL", None):  # the OOM killer
        return "memory", None
    if signum == getattr(signal, "SIGXCPU", None):  # its CPU-time backstop
        return "time", None
    why = f"signal {signal.Signals(-code).name}" if code and code < 0 else f"exit code {code}"
    return "died", f"xacro expansion stopped without a result (its process ended by {why})"


def _stop(child: Any, grace: float) -> None:
    """The child ended: killed after ``grace`` seconds (a child that has answered is let
    finish exiting, its output flushed)."""
    with _LIVE_LOCK:
        _LIVE.discard(child)
    with suppress(Exception):
        child.join(grace)
        if child.is_alive():
            child.kill()
        child.join()


def stop_children() -> None:
    """Kill every expansion under way (for a process about to exit at once, without
    unwinding)."""
    with _LIVE_LOCK:
        live = list(_LIVE)
    for child in live:
        with suppress(Exception):
            child.kill()


def _start_method() -> str:
    """``fork`` on Linux in a process with one thread, else the fork server where there is one,
    else ``spawn``."""
    import multiprocessing

    methods = multiprocessing.get_all_start_methods()
    if "fork" in methods and sys.platform.startswith("linux") and _one_thread():
        return "fork"
    return "forkserver" if "forkserver" in methods else "spawn"


def _one_thread() -> bool:
    """Whether this process runs no other Python thread. A library's idle native pool (numpy's
    BLAS threads, waiting for work) is not counted: the child never calls it, and OpenBLAS
    readies itself for a fork."""
    return threading.active_count() == 1


def _without_main_module() -> None:
    """A spawned or fork-server child of this module does not import the caller's main script
    again, as multiprocessing's children do: the expansion needs none of it, and a script
    without an ``if __name__ == "__main__"`` guard would run again in the child (and fail
    there, starting a process while it is being imported). Installed once; it changes only
    the children named :data:`_CHILD_NAME`."""
    from multiprocessing import spawn

    prepare = spawn.get_preparation_data
    if getattr(prepare, "_xrdf_without_main", False):
        return

    def get_preparation_data(name: str) -> dict[str, Any]:
        data: dict[str, Any] = prepare(name)
        if name == _CHILD_NAME:
            data.pop("init_main_from_name", None)
            data.pop("init_main_from_path", None)
        return data

    get_preparation_data._xrdf_without_main = True  # type: ignore[attr-defined]
    spawn.get_preparation_data = get_preparation_data


def _working_directory() -> str | None:
    try:
        return os.getcwd()
    except OSError:
        return None


def _child(
    send: Any,
    fn: Callable[..., Any],
    args: tuple[Any, ...],
    limits: Bounds,
    here: tuple[str | None, dict[str, str]] | None,
    parent: int | None,
) -> None:
    """The child: it ends with its parent; a terminal's signals are the parent's to handle;
    the limits set; ``fn`` run and what came of it sent."""
    _end_with_parent(parent)
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    for name in ("SIGTERM", "SIGHUP"):  # not the parent's handler: no second message
        if (sig := getattr(signal, name, None)) is not None:
            signal.signal(sig, signal.SIG_DFL)
    if here is not None:
        cwd, environ = here
        os.environ.clear()
        os.environ.update(environ)
        if cwd is not None:
            os.chdir(cwd)
    _limit_resources(limits)
    try:
        outcome: tuple[str, Any] = ("value", fn(*args))
    except MemoryError:
        outcome = ("memory", None)
    except Exception as e:
        outcome = ("raised", e)
    try:
        send.send(outcome)
    except MemoryError:
        os._exit(_EXIT_NO_MEMORY)
    except Exception as e:  # an exception that cannot be pickled: a bug, said as one line
        with suppress(Exception):
            send.send(("raised", RuntimeError(f"{type(e).__name__}: {e}")))


def _end_with_parent(parent: int | None) -> None:
    """Linux: this child is killed when its parent ends, even killed outright (SIGKILL, the
    OOM killer), so that no expansion computes on, holding the caller's output pipes, after
    the command is gone. ``parent``: the process that started it (None: the fork server,
    which ends with the process it serves); already gone, the child ends at once."""
    if not sys.platform.startswith("linux"):
        return
    try:
        import ctypes

        prctl = ctypes.CDLL(None, use_errno=True).prctl
    except (OSError, AttributeError):  # no C library to ask: the CPU-time backstop stays
        return
    prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
    if parent is not None and os.getppid() != parent:
        os._exit(1)


def _limit_resources(limits: Bounds) -> None:
    """Memory: the address space, on Linux (other systems do not enforce it). Time: CPU time a
    second past the wall-time limit, so that a child left behind by a parent killed outright
    still ends; no core file."""
    try:
        import resource
    except ImportError:  # not on POSIX
        return
    if limits.mib is not None and sys.platform.startswith("linux"):
        _lower(resource.RLIMIT_AS, _address_space() + int(limits.mib * (1 << 20)))
    if limits.seconds is not None:
        _lower(resource.RLIMIT_CPU, math.ceil(limits.seconds) + 1)
        _lower(resource.RLIMIT_CORE, 0)


def _lower(which: int, value: int) -> None:
    """Set the soft limit ``which`` to ``value`` unless it is lower already."""
    import resource

    soft, hard = resource.getrlimit(which)
    if hard != resource.RLIM_INFINITY:
        value = min(value, hard)
    if soft != resource.RLIM_INFINITY and soft <= value:
        return
    with suppress(ValueError, OSError):
        resource.setrlimit(which, (value, hard))


def _address_space() -> int:
    """This process's virtual size in bytes (/proc/self/statm: pages)."""
    try:
        pages = int(Path("/proc/self/statm").read_text().split()[0])
    except (OSError, ValueError, IndexError):
        return 0
    return pages * os.sysconf("SC_PAGE_SIZE")
