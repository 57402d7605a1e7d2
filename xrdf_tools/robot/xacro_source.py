"""Expand xacro files with the ``xacro`` package, without a ROS installation.

``$(find pkg)`` is resolved through :class:`~xrdf_tools.robot.packages.PackageResolver`
(``--package-path NAME=DIR``, then directories holding a ``package.xml`` of that name near the
input, then a directory named like the package); ``$(arg x)`` takes the ``<xacro:arg>`` default
or ``--xacro-arg x:=v``. An unresolved package is a :class:`SourceError` naming it and the
directories searched.

**Security:** xacro evaluates Python expressions (``${...}``) and reads any file it is told to
include. Treat a xacro file like code: only expand files you trust. The top-level file is
checked like every input (a regular file within the size limit); files it includes (and
``load_yaml`` files) are opened by xacro itself, after the same check.
"""

from __future__ import annotations

import os
import re
import threading
from collections.abc import Iterator, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any
from xml.parsers.expat import ExpatError

from ..diagnostics import Diagnostic, Severity
from ..util.errors import SourceError, UrdfError, UrdfReadError, XrdfToolsError
from ..util.fileio import check_input_file, decode_utf8, read_input_bytes
from .packages import PackageResolver, absolute_package_paths
from .xacro_args import ReadArgs, unknown_packages, unread_arg_warnings, unset_args
from .xacro_child import out_of_memory
from .xacro_culprits import UNDEFINED_ARG, culprit_in
from .xacro_detect import uses_xacro
from .xacro_files import (
    file_arg_hint,
    located_in_includes,
    missing_include_error,
    not_utf8_error,
    os_error,
    shown_path,
)
from .xacro_hints import bad_macro_call, late_default_hint, unprefixed_hint
from .xacro_places import placed_in_includes
from .xacro_unresolved import PLACEHOLDER, error_for, settle

if TYPE_CHECKING:
    from .core import Robot
    from .packages import PackagePaths

__all__ = ["expand_xacro", "is_xacro", "load_robot", "parse_xacro_arg", "uses_xacro"]

_LOCK = threading.Lock()


def is_xacro(path: str | os.PathLike[str]) -> bool:
    """A ``.xacro`` file (``robot.xacro``, ``robot.urdf.xacro``) or a URDF that uses xacro."""
    p = Path(path)
    if p.suffix == ".xacro":
        return True
    try:
        data = read_input_bytes(p, what="robot file", error=SourceError)
    except XrdfToolsError:
        return False  # not readable: the URDF reader says why
    return uses_xacro(data)


def parse_xacro_arg(spec: str) -> tuple[str, str]:
    """``name:=value`` from the command line."""
    name, sep, value = spec.partition(":=")
    if not sep or not name:
        raise SourceError(f"--xacro-arg expects NAME:=VALUE, got '{spec}'")
    return name, value


#: The id of a warning xacro prints while expanding.
RULE_XACRO_WARNING = "xacro-warning"


@contextmanager
def _patched_xacro(
    resolver: PackageResolver,
    top: str,
    said: list[Diagnostic],
    unresolved: dict[str, SourceError],
) -> Iterator[None]:
    """Make xacro's ``$(find pkg)`` use ``resolver`` and its warnings (printed to stderr by
    xacro itself, past ``-q`` and ``--format``) land in ``said``, each once, at the file
    xacro was reading; a package that cannot be found gives a placeholder path and its
    located error in ``unresolved`` (see :mod:`.xacro_unresolved`). xacro keeps global
    state: serialise."""
    import xacro
    from xacro import substitution_args as sa

    def find(pkg: str) -> str:
        try:
            return str(resolver.find(pkg))
        except XrdfToolsError as e:
            if pkg not in unresolved:
                included = list(getattr(xacro, "all_includes", None) or ())
                unresolved[pkg] = _xacro_error(e, top, xacro.filestack, included)
            return PLACEHOLDER + pkg

    def warning(*args: Any, **_: Any) -> None:
        stack = [str(f) for f in getattr(xacro, "filestack", None) or () if f]
        text = " ".join(" ".join(str(a) for a in args).split())
        # a lazy property is evaluated in the file that uses it, not the one that writes it
        written = [stack[-1] if stack else top, *(getattr(xacro, "all_includes", None) or ())]
        where, line, col = culprit_in([str(f) for f in written], text)
        found = Diagnostic(
            where,
            line,
            col,
            RULE_XACRO_WARNING,
            Severity.WARNING,
            f"xacro: {text}",
        )
        if not any((d.path, d.message) == (found.path, found.message) for d in said):
            said.append(found)

    with _LOCK:
        old_find = sa._eval_find
        old_dict = sa._eval_dict.get("find")
        old_warning, old_location = xacro.warning, xacro.print_location
        sa._eval_find = find
        sa._eval_dict["find"] = find
        xacro.warning, xacro.print_location = warning, lambda: None
        xacro.open = _guarded_open  # the name xacro's own open() calls resolve to
        try:
            yield
        finally:
            sa._eval_find = old_find
            sa._eval_dict["find"] = old_dict
            xacro.warning, xacro.print_location = old_warning, old_location
            del xacro.open


def _guarded_open(file: Any, *args: Any, **kwargs: Any) -> Any:
    """``open`` for the files xacro opens itself (includes, ``load_yaml``): a FIFO, a device,
    a directory or a file over the size limit is refused before it is opened (a FIFO would
    block forever); a name that does not exist is left to ``open`` and xacro's own message."""
    if isinstance(file, (str, os.PathLike)) and os.path.exists(file):
        check_input_file(file, what="file included by the xacro", error=SourceError)
    return open(file, *args, **kwargs)


def expand_xacro(
    path: str | os.PathLike[str],
    args: Mapping[str, str] | None = None,
    package_paths: PackagePaths | None = None,
    *,
    data: bytes | None = None,
    warnings: list[Diagnostic] | None = None,
    warn_unread_args: bool = True,
    includes: list[str] | None = None,
    read_elsewhere: frozenset[str] = frozenset(),
) -> str:
    """The URDF text of a xacro file. Raises :class:`SourceError` with a one-line reason.

    The file is read through the guarded reader (``data``: its bytes, when the caller has
    read them already) and decoded, so a bad byte is located; xacro then reads it itself.
    xacro's own warnings (an include's ignored body, a redefined symbol) are appended to
    ``warnings`` as ``xacro-warning`` diagnostics, never printed; so is an argument of ``args``
    the expansion never reads (``xacro-arg-unread``), unless ``warn_unread_args`` is false (an
    SRDF xacro given the robot's arguments) or another file of the same command reads it
    (``read_elsewhere``: the SRDF xacro's arguments). ``includes`` receives the files it
    included.

    The expansion runs in a child process bounded in time and memory
    (:mod:`.xacro_child`: ``XRDF_XACRO_TIMEOUT``, ``XRDF_XACRO_MEMORY``); past either bound
    it is a :class:`SourceError` naming the variable that raises it."""
    from .xacro_child import run_bounded

    said = warnings if warnings is not None else []
    known = list(said)  # xacro's warnings are said once: the child knows those said before
    warn = read_elsewhere if warn_unread_args else None
    expansion = (path, args, package_paths, data, known, warn)
    done = run_bounded(_expansion, expansion, path, preload=_PRELOAD)
    said.extend(done.warnings)
    if includes is not None:
        includes.extend(shown_path(Path(f)) for f in done.included)
    if done.error is not None:
        raise done.error
    return done.text


#: What every expansion imports (xacro's ``$(...)`` and YAML support; ``toprettyxml``'s escaping):
#: imported before the child starts, so no child imports them again.
_PRELOAD = ("xacro", "xacro.substitution_args", "xml.dom.expatbuilder", "xml.sax.saxutils")


@dataclass(frozen=True)
class _Expansion:
    """What an expansion gave: its text or its error, the warnings it added (before an error
    too, as in this process) and the files it included."""

    text: str
    error: XrdfToolsError | None
    warnings: list[Diagnostic]
    included: list[str]


def _expansion(
    path: str | os.PathLike[str],
    args: Mapping[str, str] | None,
    package_paths: PackagePaths | None,
    data: bytes | None,
    said: list[Diagnostic],
    warn_unread_args: frozenset[str] | None,
) -> _Expansion:
    """:func:`_expand_here` as one value (run in the child)."""
    before, included = len(said), list[str]()
    try:
        text = _expand_here(path, args, package_paths, data, said, warn_unread_args, included)
    except XrdfToolsError as e:
        return _Expansion("", e, said[before:], included)
    return _Expansion(text, None, said[before:], included)


def _expand_here(
    path: str | os.PathLike[str],
    args: Mapping[str, str] | None,
    package_paths: PackagePaths | None,
    data: bytes | None,
    said: list[Diagnostic],
    warn_unread_args: frozenset[str] | None,
    includes: list[str],
) -> str:
    """:func:`expand_xacro` in this process (xacro's globals held under a lock). A
    ``MemoryError``, which xacro wraps in its own exception, is raised as one.
    ``warn_unread_args``: None, or the arguments other files read (not warned about)."""
    import xacro

    p = Path(path)
    if data is None:
        data = read_input_bytes(p, what="xacro file", error=SourceError)
    decode_utf8(data, str(p), "xacro file", SourceError)
    resolver = PackageResolver(p, dict(package_paths or {}))
    mappings = {str(k): str(v) for k, v in (args or {}).items()}
    values = ReadArgs(mappings)  # xacro adds the defaults of the arguments it meets to it
    unresolved: dict[str, SourceError] = {}
    # xacro's module globals (its file and macro stacks, the included files) are read and
    # reset inside the lock _patched_xacro holds: another thread may be expanding next
    failure: _Failure | None = None
    with _patched_xacro(resolver, str(p), said, unresolved):
        try:
            xacro.all_includes = []
            doc = xacro.process_file(str(p), mappings=values)
            text: str = doc.toprettyxml(indent="  ")
            includes.extend(dict.fromkeys(str(f) for f in xacro.all_includes))
        except Exception as e:  # xacro's XacroException, ArgException, NameError, OSError…
            if out_of_memory(e):
                raise MemoryError from None
            filestack = getattr(xacro, "filestack", None)
            failure = _Failure(
                e,
                list(filestack) if filestack is not None else None,
                list(xacro.all_includes),
                _innermost_macro(getattr(xacro, "macrostack", None)),
            )
        finally:
            xacro.filestack = None
            xacro.macrostack = None
    if failure is not None:
        if (placeholder := error_for(failure.error, unresolved)) is not None:  # no package
            raise _naming_the_others(placeholder, p, resolver, mappings) from None
        error = _xacro_error(
            failure.error,
            str(p),
            failure.filestack,
            failure.included,
            mappings,
            values,
            failure.macro,
        )
        raise _naming_the_others(error, p, resolver, mappings) from None
    if warn_unread_args is not None:
        values.asked |= warn_unread_args
        said.extend(unread_arg_warnings(str(p), mappings, values))
    return settle(doc, text, unresolved, said)


@dataclass(frozen=True)
class _Failure:
    """An expansion that raised, with xacro's state at that moment (copied under the lock)."""

    error: Exception
    filestack: list[Any] | None
    included: list[Any]
    macro: str | None


_EXPAT_WHERE = re.compile(r":\s*line \d+, column \d+$")


def _naming_the_others(
    error: SourceError, top: Path, resolver: PackageResolver, given: Mapping[str, str]
) -> SourceError:
    """``error`` about one argument without a value, naming the others the files use
    without a default, or about one package that cannot be found, naming the others the
    files name, so that one run finds them all."""
    if m := UNDEFINED_ARG.search(error.message):
        others = [a for a in unset_args(top, resolver, given) if a != m.group(1)]
        more = " ".join(f"--xacro-arg {a}:=VALUE" for a in others)
        what = "used without a default too"
    elif m := _UNKNOWN_PACKAGE.search(error.message):
        others = [n for n in unknown_packages(top, resolver) if n != m.group(1)]
        more = " ".join(f"--package-path {n}=DIR" for n in others)
        what = "the files name these packages that cannot be found either (a part the "
        what += "expansion skips may be the one naming some)"
    else:
        return error
    if not others:
        return error
    return SourceError(
        f"{error.message}; {what}: {more}", path=error.path, line=error.line, col=error.col
    )


_UNKNOWN_PACKAGE = re.compile(r"cannot find ROS package '([^']+)'")


def _innermost_macro(macrostack: Any) -> str | None:
    """The name of the macro xacro was calling when it failed (None outside a macro)."""
    try:
        name = macrostack[-1].body.getAttribute("name")
    except (AttributeError, IndexError, TypeError):
        return None
    return name if isinstance(name, str) and name else None


def _xacro_error(
    e: BaseException,
    top: str,
    filestack: Any,
    included: Sequence[str] = (),
    given: Mapping[str, str] | None = None,
    values: Mapping[str, str] | None = None,
    macro: str | None = None,
) -> SourceError:
    """One located error for a failed expansion: an XML syntax error (expat) at its line and
    column in the file xacro was reading (the top file or an include), anything else where
    the text it quotes is written: the file being processed, else the first include that
    writes it (a macro's body fails where the macro is called)."""
    stack = [str(f) for f in filestack or () if f]
    where = stack[-1] if stack else top
    inner: Any = getattr(e, "exc", None) or e
    line, offset = getattr(inner, "lineno", None), getattr(inner, "offset", None)
    if isinstance(inner, ExpatError) and isinstance(line, int) and isinstance(offset, int):
        what = _EXPAT_WHERE.sub("", " ".join(str(inner).split()))
        return SourceError(
            f"xacro failed: not valid XML: {what}", path=where, line=line, col=offset + 1
        )
    if (undecoded := not_utf8_error(e, where)) is not None:
        return undecoded
    unread = os_error(e)
    missing = unread.filename if unread is not None else None
    if isinstance(missing, str) and unread is inner:
        return missing_include_error(missing, where, included, given or {}, values or {})
    message = _xacro_message(e)
    if unread is not None and isinstance(missing, str):  # an expression's xacro.load_yaml()
        said = "does not exist" if isinstance(unread, FileNotFoundError) else "cannot be read"
        message = message.replace(str(unread), f"the file {missing} {said}")
        message += file_arg_hint(missing, top, given or {}, values or {})
    if (call := bad_macro_call(message, macro, [where, *included])) is not None:
        return SourceError(call[0], path=call[1], line=call[2], col=call[3])
    where, line, col = culprit_in([where, *included], message)
    hint = unprefixed_hint(message, [where, *included]) + late_default_hint(message, where, line)
    return SourceError(message + hint, path=where, line=line, col=col)


def _xacro_message(e: BaseException) -> str:
    if isinstance(e, XrdfToolsError):  # ours: a $(find) of a package that cannot be found
        return e.message
    name = type(e).__name__
    if name == "ArgException":
        return f"xacro argument {e} is not set; pass --xacro-arg {e}:=VALUE"
    # Unwrap nested exceptions (xacro wraps the real cause in XacroException.exc)
    inner: Any = getattr(e, "exc", None)
    if isinstance(inner, XrdfToolsError):
        return inner.message
    msg = _CLASS_PREFIX.sub("", " ".join(str(e).split())) or name
    inner_text = " ".join(str(inner).split()) if inner is not None else ""
    if inner_text and inner_text not in msg:
        msg = f"{msg} {inner_text}"
    twice = f"{inner_text} {inner_text}"
    while inner_text and twice in msg:  # xacro repeats its cause after its own text
        msg = msg.replace(twice, inner_text)
    if (m := UNDEFINED_ARG.search(msg)) is not None:
        return f"xacro failed: {msg} (pass --xacro-arg {m.group(1)}:=VALUE)"
    return f"xacro failed: {msg}"


#: "<class 'xacro.substitution_args.SubstitutionException'>: " before some xacro messages
_CLASS_PREFIX = re.compile(r"^<class '[\w.]+'>:\s*")


def load_robot(
    path: str | os.PathLike[str],
    *,
    xacro_args: Mapping[str, str] | None = None,
    package_paths: PackagePaths | None = None,
    srdf: str | os.PathLike[str] | None = None,
) -> Robot:
    """Load a URDF or expand and load a xacro file (meshes are never loaded): the one loader
    of a robot file. For xacro input :attr:`Robot.xacro_text` is the expanded URDF text.
    A URDF file is read once: the bytes that tell it is no xacro are the bytes parsed.
    ``srdf``: the SRDF the command expands with the same ``xacro_args`` (an SRDF xacro): an
    argument only it reads is no ``xacro-arg-unread``.
    """
    from .urdf_source import parse_robot, read_robot, read_urdf_bytes

    pkg = absolute_package_paths(package_paths)
    data: bytes | None = None
    if Path(path).suffix != ".xacro":
        try:
            data = read_urdf_bytes(path)
        except UrdfReadError:
            if xacro_args:  # a file that cannot be read is no xacro file (as is_xacro says)
                raise SourceError(_NOT_XACRO, path=str(path)) from None
            raise
    if data is None or uses_xacro(data):
        said: list[Diagnostic] = []
        included: list[str] = []
        elsewhere = _read_by(srdf, pkg) if xacro_args and srdf is not None else frozenset()
        text = expand_xacro(
            path,
            xacro_args,
            pkg,
            data=data,
            warnings=said,
            includes=included,
            read_elsewhere=elsewhere,
        )
        try:
            robot = parse_robot(
                text, os.fspath(path), package_paths=pkg, expanded=True, xacro_args=xacro_args
            )
        except UrdfError as e:
            raise located_in_includes(e, os.fspath(path), included) from None
        robot = replace(robot, warnings=(*said, *robot.warnings), included_files=tuple(included))
        return placed_in_includes(robot)
    if xacro_args:
        raise SourceError(_NOT_XACRO, path=str(path))
    return read_robot(path, package_paths=pkg, data=data)


_NOT_XACRO = "--xacro-arg given but the robot file is not a xacro file"


def _read_by(srdf: str | os.PathLike[str], package_paths: PackagePaths) -> frozenset[str]:
    """The xacro arguments an SRDF (xacro) declares or uses."""
    from .xacro_args import args_named

    return args_named(Path(srdf), PackageResolver(Path(srdf), dict(package_paths)))
