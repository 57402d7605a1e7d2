"""Guarded reading and atomic writing: the one way xrdf-tools opens an input or writes an output.

Reading (:func:`read_input_bytes`, :func:`read_input_text`, :func:`check_input_file`):

* only a regular file is read: a directory, FIFO, device or socket is refused before a byte is
  read (reading ``/dev/zero`` or a FIFO would never end); ``-`` means standard input only where
  the caller allows it (``allow_stdin``);
* at most :func:`max_input_bytes` bytes (16 MiB; ``XRDF_TOOLS_MAX_INPUT_MB`` changes it; mesh
  files 16 times that, tables of configurations 4 times);
* text must be UTF-8: a bad byte is reported with its line and column.

Writing (:func:`write_atomic`, :func:`atomic_output`): the data goes to a temporary file in the
target's directory, is flushed to disk, then renamed over the target, so a reader never sees a
partial file. A symlink is kept (the file it points to is replaced); a directory, device, FIFO
or socket is refused; the temporary file is removed on every exit (errors, ``KeyboardInterrupt``,
``SystemExit``); every error is an :class:`~xrdf_tools.util.errors.OutputError` that names the path
the caller asked for, never the temporary file.
"""

from __future__ import annotations

import contextlib
import math
import os
import stat
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import BinaryIO

from .errors import InputError, OutputError, XrdfToolsError

__all__ = [
    "BINARY_STL_TRIANGLE_BYTES",
    "ENV_MAX_INPUT",
    "STDIN",
    "atomic_output",
    "check_input_file",
    "check_output_path",
    "file_kind",
    "is_file",
    "max_input_bytes",
    "mesh_bytes_limit",
    "mesh_triangle_limit",
    "read_input_bytes",
    "read_input_text",
    "write_atomic",
]

#: Environment variable: the input size limit in MiB.
ENV_MAX_INPUT = "XRDF_TOOLS_MAX_INPUT_MB"
DEFAULT_MAX_INPUT_MB = 16
#: The path that means standard input where a caller allows it.
STDIN = "-"

ErrorType = type[XrdfToolsError]
_OPEN_FLAGS = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0)
_CHUNK = 1 << 20
#: The temporary files of :func:`atomic_output` blocks under way in this process.
TEMPORARIES: set[Path] = set()


def max_input_bytes() -> int:
    """The largest input read, in bytes (``XRDF_TOOLS_MAX_INPUT_MB``, default 16 MiB)."""
    raw = os.environ.get(ENV_MAX_INPUT, "").strip()
    if not raw:
        return DEFAULT_MAX_INPUT_MB << 20
    try:
        mb = float(raw)
    except ValueError:
        mb = math.nan
    if not (math.isfinite(mb) and mb > 0):
        raise InputError(f"{ENV_MAX_INPUT}={raw!r} must be a positive number of MiB")
    return max(1, int(mb * (1 << 20)))


def mesh_bytes_limit() -> int:
    """The size limit of a mesh file: 16 times :func:`max_input_bytes` (256 MiB by default)."""
    return 16 * max_input_bytes()


#: Bytes a binary STL spends on one triangle (normal, three vertices, attribute count).
BINARY_STL_TRIANGLE_BYTES = 50


def mesh_triangle_limit() -> int:
    """The most triangles read from one mesh file: what a binary STL of
    :func:`mesh_bytes_limit` holds (5.4 million by default). Formats that pack triangles
    tighter (binary PLY, glTF) could otherwise bring three or four times as many within the
    size limit, and a mesh costs about 1 kB a triangle while it is prepared."""
    return mesh_bytes_limit() // BINARY_STL_TRIANGLE_BYTES


def file_kind(mode: int) -> str:
    """What a file of ``st_mode`` ``mode`` that is not a regular file is: ``a directory``,
    ``a FIFO (named pipe)``, ..."""
    if stat.S_ISDIR(mode):
        return "a directory"
    if stat.S_ISFIFO(mode):
        return "a FIFO (named pipe)"
    if stat.S_ISCHR(mode):
        return "a character device"
    if stat.S_ISBLK(mode):
        return "a block device"
    if stat.S_ISSOCK(mode):
        return "a socket"
    return "not a regular file"


def _mib(n: int) -> str:
    return f"{n / (1 << 20):.3g} MiB"


def _too_big(limit: int) -> str:
    return f"larger than the {_mib(limit)} input limit; set {ENV_MAX_INPUT} to read larger files"


def _check_stat(
    st: os.stat_result, path: str, what: str, error: ErrorType, limit: int, stdin_ok: bool
) -> None:
    if stat.S_ISDIR(st.st_mode):
        raise error(f"is a directory ({what} expected)", path=path)
    if not stat.S_ISREG(st.st_mode):
        hint = "; '-' reads standard input" if stdin_ok else ""
        raise error(
            f"is {file_kind(st.st_mode)}, not a regular file ({what} expected){hint}", path=path
        )
    if st.st_size > limit:
        raise error(f"{what} is {_mib(st.st_size)}, {_too_big(limit)}", path=path)


def _open_error(e: OSError, path: str, what: str, error: ErrorType) -> XrdfToolsError:
    if isinstance(e, FileNotFoundError):
        return error(f"{what} not found", path=path)
    if isinstance(e, IsADirectoryError):
        return error(f"is a directory ({what} expected)", path=path)
    return error(f"cannot read {what}: {e.strerror or e}", path=path)


def _read_capped(fh: BinaryIO, path: str, what: str, error: ErrorType, limit: int) -> bytes:
    chunks: list[bytes] = []
    size = 0
    while True:
        chunk = fh.read(min(_CHUNK, limit + 1 - size))
        if not chunk:
            return b"".join(chunks)
        chunks.append(chunk)
        size += len(chunk)
        if size > limit:
            raise error(f"{what} is {_too_big(limit)}", path=path)


def read_input_bytes(
    path: str | os.PathLike[str],
    *,
    what: str = "file",
    error: ErrorType = InputError,
    max_bytes: int | None = None,
    allow_stdin: bool = False,
) -> bytes:
    """The bytes of an input file, guarded as the module docstring says.

    ``what`` names the file in messages (``"URDF file"``); ``error`` is the exception class
    raised (one line, with the path). ``allow_stdin``: ``-`` reads standard input.
    """
    p = os.fspath(path)
    limit = max_input_bytes() if max_bytes is None else max_bytes
    if p == STDIN and allow_stdin:
        return _read_capped(sys.stdin.buffer, "<stdin>", what, error, limit)
    try:
        fd = os.open(p, _OPEN_FLAGS)
    except OSError as e:
        raise _open_error(e, p, what, error) from None
    try:
        _check_stat(os.fstat(fd), p, what, error, limit, allow_stdin)
        with os.fdopen(os.dup(fd), "rb") as fh:
            return _read_capped(fh, p, what, error, limit)
    except OSError as e:
        raise _open_error(e, p, what, error) from None
    finally:
        os.close(fd)


def decode_utf8(data: bytes, path: str, what: str, error: ErrorType) -> str:
    """``data`` as UTF-8 text; a bad byte is an error at its line and column."""
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as e:
        line = data.count(b"\n", 0, e.start) + 1
        col = e.start - (data.rfind(b"\n", 0, e.start) + 1) + 1
        raise error(
            f"{what} is not UTF-8 text (byte 0x{data[e.start]:02x}: {e.reason})",
            path=path,
            line=line,
            col=col,
        ) from None


def read_input_text(
    path: str | os.PathLike[str],
    *,
    what: str = "file",
    error: ErrorType = InputError,
    max_bytes: int | None = None,
    allow_stdin: bool = False,
) -> str:
    """The UTF-8 text of an input file (see :func:`read_input_bytes`)."""
    data = read_input_bytes(
        path, what=what, error=error, max_bytes=max_bytes, allow_stdin=allow_stdin
    )
    return decode_utf8(data, os.fspath(path), what, error)


def reread_text(path: str | os.PathLike[str], *, errors: str = "strict") -> str | None:
    """The text of a file read again to place a message (a file a library opened itself: a
    xacro include), through the guarded reader: None when it cannot be read (gone, a FIFO or
    device, over the size limit, not UTF-8 when ``errors`` is ``"strict"``)."""
    try:
        data = read_input_bytes(path)
    except XrdfToolsError:
        return None
    try:
        return data.decode("utf-8", errors=errors)
    except UnicodeDecodeError:
        return None


def is_file(path: str | os.PathLike[str]) -> bool:
    """``path`` is a regular file (or a link to one); False, never an exception, for a name
    the system cannot look at (too long, a NUL byte, a link loop on the way)."""
    try:
        return os.path.isfile(path)
    except (OSError, ValueError):
        return False


def check_input_file(
    path: str | os.PathLike[str],
    *,
    what: str = "file",
    error: ErrorType = InputError,
    max_bytes: int | None = None,
) -> None:
    """Check, without reading it, that ``path`` is a regular file within the size limit
    (for inputs that a third-party library opens itself: xacro, ``.npy``)."""
    p = os.fspath(path)
    limit = max_input_bytes() if max_bytes is None else max_bytes
    try:
        st = os.stat(p)
    except OSError as e:
        raise _open_error(e, p, what, error) from None
    _check_stat(st, p, what, error, limit, False)


# --------------------------------------------------------------------------------------------
# Writing
# --------------------------------------------------------------------------------------------
def _write_error(e: OSError, user: str) -> OutputError:
    reason = e.strerror or str(e)
    return OutputError(f"cannot write: {reason}", path=user, errno=e.errno, strerror=reason)


def check_output_path(path: str | os.PathLike[str]) -> Path:
    """The file a write to ``path`` replaces: a symlink is followed (and kept); a directory,
    device, FIFO or socket is refused with :class:`OutputError`, and so is a file nobody may
    write (``chmod a-w``: its owner protected it; the rename of an atomic write would replace
    it anyway, even for root, and drop that protection without a word)."""
    user = os.fspath(path)
    target = Path(os.path.realpath(user)) if os.path.islink(user) else Path(user)
    try:
        st = os.stat(target)
    except FileNotFoundError:
        if user.endswith(("/", os.sep)):  # Path() drops the slash: 'new/' would make a file
            raise OutputError(
                "names a directory (it ends with '/'), which does not exist; give a file name",
                path=user,
            ) from None
        return target
    except OSError as e:
        raise _write_error(e, user) from None
    if stat.S_ISDIR(st.st_mode):
        raise OutputError("is a directory; give a file name", path=user)
    if not stat.S_ISREG(st.st_mode):
        raise OutputError(
            f"is {file_kind(st.st_mode)}, not a regular file; refusing to replace it (choose a "
            "file path)",
            path=user,
        )
    if not st.st_mode & 0o222:
        raise OutputError(
            "is read-only (no write permission): refusing to replace it; make it writable "
            "(chmod u+w) or write another file",
            path=user,
        )
    return target


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def _finish(tmp: Path, target: Path) -> None:
    """Flush ``tmp`` to disk, give it the target's mode, rename it over the target."""
    fd = os.open(tmp, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)
    try:
        mode = stat.S_IMODE(os.stat(target).st_mode)
    except FileNotFoundError:
        mode = 0o666 & ~_umask()
    os.chmod(tmp, mode)
    os.replace(tmp, target)


@contextlib.contextmanager
def atomic_output(path: str | os.PathLike[str], *, create_parents: bool = True) -> Iterator[Path]:
    """A temporary path beside the target of ``path``; renamed over it when the block ends
    without an exception, removed in every case (see the module docstring).

    ``create_parents``: create a missing output directory (else it is an error).
    """
    user = os.fspath(path)
    target = check_output_path(user)
    directory = target.parent
    if create_parents:
        try:
            directory.mkdir(parents=True, exist_ok=True)
        except OSError as e:
            raise _write_error(e, user) from None
    elif not directory.is_dir():
        raise OutputError(f"output directory does not exist: {directory}", path=user)
    import tempfile  # here: only writers need it (xrdf lint starts without it)

    try:
        fd, name = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=directory)
        os.close(fd)
    except OSError as e:
        raise _write_error(e, user) from None
    tmp = Path(name)
    TEMPORARIES.add(tmp)
    try:
        yield tmp
        _finish(tmp, target)
    except OutputError:
        raise
    except OSError as e:
        raise _write_error(e, user) from None
    finally:
        with contextlib.suppress(OSError):
            tmp.unlink()
        TEMPORARIES.discard(tmp)


def remove_temporaries() -> None:
    """Remove the temporary files of the writes under way (for a process that must exit at
    once, without unwinding: see :func:`xrdf_tools.cli.main`)."""
    for tmp in list(TEMPORARIES):
        with contextlib.suppress(OSError):
            tmp.unlink()


def write_atomic(path: str | os.PathLike[str], data: str | bytes) -> None:
    """Write ``data`` (``str`` as UTF-8) to ``path`` atomically (see :func:`atomic_output`)."""
    raw = data.encode("utf-8") if isinstance(data, str) else data
    with atomic_output(path) as tmp, open(tmp, "wb") as fh:
        fh.write(raw)


def write_output_file(path: str | os.PathLike[str], data: str | bytes) -> None:
    """:func:`write_atomic`, with any failure an :class:`XrdfToolsError` that names ``path``
    (``PATH: cannot write: reason``), never the temporary file."""
    try:
        write_atomic(path, data)
    except XrdfToolsError:
        raise
    except OSError as e:
        raise XrdfToolsError(f"{os.fspath(path)}: cannot write: {e.strerror or e}") from None
