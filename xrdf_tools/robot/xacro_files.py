"""The files of a xacro robot in its error messages: a file that an expression reads
(``xacro.load_yaml``) and that is not there (the OSError xacro wrapped, and what to pass
instead), and an error of the expansion located in the included file that writes it.

ROS launch files hand such files to xacro as full paths through an ``<xacro:arg>`` whose
default is a bare name (MELFA's ``initial_positions_file``); expanded without ROS, xacro looks
for that name beside the file it is processing. The hint names the argument and, when a file
of that name lies in the robot's package, where it is.
"""

from __future__ import annotations

import os
import re
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from ..util.errors import SourceError, UrdfError, XrdfToolsError
from ..util.fileio import decode_utf8, is_file, read_input_bytes, reread_text
from ..util.textpos import line_col
from .packages import _is_dir

__all__ = [
    "file_arg_hint",
    "located_in_includes",
    "missing_include_error",
    "not_utf8_error",
    "os_error",
    "shown_path",
]

#: How far up from the xacro file a package.xml is looked for, how deep below it the file.
_UP, _DEPTH = 4, 3
#: At most this many folders are listed per level (a package, not a workspace).
_WIDTH = 500


def os_error(e: BaseException) -> OSError | None:
    """The OSError at the bottom of xacro's wrapped exceptions (``XacroException.exc``,
    nested once per expression being evaluated), if any."""
    seen: list[BaseException] = []
    x: Any = e
    while isinstance(x, BaseException) and all(x is not y for y in seen):
        if isinstance(x, OSError):
            return x
        seen.append(x)
        x = getattr(x, "exc", None)
    return None


def not_utf8_error(e: BaseException, path: str) -> SourceError | None:
    """The located error for a xacro file that is not UTF-8 text, when ``e`` (xacro's error,
    its cause in ``exc``) is a decoding error and ``path``, the file xacro was reading, is
    not UTF-8: an include written in a legacy encoding (a Fusion 360 export's GBK comments)
    gets its line and column, as the top file does, instead of Python's byte offset."""
    inner: Any = getattr(e, "exc", None) or e
    if not isinstance(inner, UnicodeDecodeError):
        return None
    try:
        decode_utf8(read_input_bytes(path), path, "xacro file", SourceError)
    except SourceError as located:
        return located
    except XrdfToolsError:  # gone or unreadable now: the generic message stands
        return None
    return None  # the file decodes: something else xacro read (a YAML file) did not


def file_arg_hint(
    missing: str, top: str, given: Mapping[str, str], values: Mapping[str, str]
) -> str:
    """What to pass when the file ``missing`` is named by an ``$(arg X)`` the user did not
    give (``values``: the arguments xacro read, with their defaults), else ""."""
    wanted = missing.replace("\\", "/")
    for arg, value in values.items():
        if arg in given or not value or not wanted.endswith(value.replace("\\", "/")):
            continue
        found = _in_package(Path(value).name, Path(top))
        there = f"; a file of that name: {', '.join(found)}" if found else ""
        return (
            f" (the file name is $(arg {arg}), not given, so {value!r}, read beside the xacro "
            f"file being processed; a launch file passes a full path: pass --xacro-arg "
            f"{arg}:=PATH{there})"
        )
    return ""


def _in_package(name: str, top: Path) -> list[str]:
    """Files called ``name`` in the package of ``top`` (the nearest folder above it with a
    package.xml, else its own folder), at most three levels down, in sorted order: shown
    relative to the current directory when below it."""
    folder = top.resolve().parent
    root = next((d for d in [folder, *folder.parents][:_UP] if is_file(d / "package.xml")), folder)
    out: list[str] = []
    frontier = [root]
    for _ in range(_DEPTH + 1):
        nxt: list[Path] = []
        for d in frontier:
            if is_file(d / name):
                out.append(shown_path(d / name))
            try:
                nxt.extend(c for c in sorted(d.iterdir()) if _is_dir(c) and c.name[:1] != ".")
            except OSError:
                continue
        frontier = nxt[:_WIDTH]
    return out[:3]


def shown_path(path: Path) -> str:
    """``path`` as a message names it: relative to the current directory when below it (a
    file a ``$(find pkg)`` include reached is found by its absolute path), else as it is;
    either without the ``dir/..`` a relative include writes (``robots/../model/hand.xacro``)."""
    try:
        full = Path(os.path.abspath(path))
        return os.path.relpath(full) if full.is_relative_to(Path.cwd()) else os.path.normpath(path)
    except (OSError, ValueError):
        return str(path)


def located_in_includes(e: UrdfError, top: str, included: Sequence[str]) -> UrdfError:
    """``e``, an error of the expansion that the top file does not locate, located in the
    first included file that writes what it quotes: an element that a macro of that file made
    (HEBI's omnibase.xacro: a wheel joint to a link no macro makes); last, a link or joint
    defined twice that no file writes as it is, at the name template that makes it."""
    from .urdf_source import _quoted_value_line, template_line

    if e.line is not None or e.path != top:
        return e
    for find, files in ((_quoted_value_line, included), (template_line, [top, *included])):
        for path in files:
            text = reread_text(path, errors="replace")
            if text is None:
                continue
            if (line := find(text, e.message)) is not None:
                e.path, e.line = os.path.normpath(path), line
                return e
    return e


#: ``$(arg NAME)`` in an attribute: the group is the name.
_ARG_USE = re.compile(r"\$\(arg\s+([^\s)]+)\s*\)")
#: ``<xacro:include filename="...">``: the group is the file name as written.
_INCLUDE = re.compile(r"<xacro:include\b[^>]*?\bfilename\s*=\s*([\"'])(.*?)\1", re.DOTALL)
#: A substitution (``$(...)``) or an expression (``${...}``) inside an attribute.
_SUBSTITUTION = re.compile(r"\$\([^)]*\)|\$\{[^}]*\}")


def missing_include_error(
    missing: str,
    where: str,
    included: Sequence[str],
    given: Mapping[str, str],
    values: Mapping[str, str],
) -> SourceError:
    """A file that an ``<xacro:include>`` names and that does not exist, located at the
    include whose ``filename`` (substitutions as wildcards) gives that path, the one with the
    most literal text when several do; when the name is made from an ``$(arg X)`` the user
    did not pass (``given``), the hint names the argument and the default it took
    (``values``)."""
    message = f"xacro failed: the included file {missing} does not exist"
    best: tuple[int, str, str, re.Match[str]] | None = None
    for path in dict.fromkeys([where, *included]):
        text = reread_text(path)
        if text is None:
            continue
        for m in _INCLUDE.finditer(text):
            literal = _SUBSTITUTION.split(m.group(2))
            pattern = r"(?:.*/)?" + ".*".join(re.escape(t) for t in literal)
            score = sum(len(t) for t in literal)
            if re.fullmatch(pattern, missing, re.DOTALL) and (best is None or score > best[0]):
                best = (score, path, text, m)
    if best is None:
        return SourceError(message, path=where)
    _, path, text, m = best
    unset = [a for a in _ARG_USE.findall(m.group(2)) if a not in given]
    hint = "".join(
        f" (the name uses $(arg {a}), not given, so {values.get(a, '')!r}: pass "
        f"--xacro-arg {a}:=VALUE)"
        for a in dict.fromkeys(unset)
    )
    line, col = line_col(text, m.start(2))
    return SourceError(message + hint, path=path, line=line, col=col)
