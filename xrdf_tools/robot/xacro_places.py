"""Where a xacro robot's macro-made links and joints are written.

An expanded xacro file locates the ``<link>``/``<joint>`` elements it writes literally (see
``urdf_source.relocate_expansion``); the ones a macro of an included file makes
(``<link name="${prefix}link_3">`` in ``kr6_macro.xacro``) have no line in it. Such a name is
placed at the element of an included file whose ``name`` template it fits: the template's
``${…}`` and ``$(…)`` stand for any text, and of the templates that fit, the one with the
most literal text wins (``${prefix}link_3`` over ``${prefix}${name}``); a template without
literal text fits nothing. Messages about the link then point where the user would edit it.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

from ..util.fileio import reread_text
from ..util.frozen import FrozenMap
from ..util.textpos import line_col

if TYPE_CHECKING:
    from ..diagnostics import Diagnostic
    from ..util.errors import UrdfError
    from .core import Robot

__all__ = [
    "Place",
    "included_places",
    "located_at_elements",
    "located_error",
    "placed_in_includes",
    "template_offset",
]

#: ``(kind, name)`` -> ``(file, line)``
Place = tuple[str, int]

_ELEMENT = re.compile(r"<(link|joint)\b[^>]*?\bname\s*=\s*(?:\"([^\"]*)\"|'([^']*)')", re.S)
_EXPRESSION = re.compile(r"\$\{[^}]*\}|\$\([^)]*\)")
_ABOUT = re.compile(r"(link|joint) '([^']+)'")
#: Templates read per file at most (a generated file of thousands of elements is no macro).
_MAX_TEMPLATES = 5000


@dataclass(frozen=True)
class _Template:
    literal: int  # characters of literal text: more is a closer fit
    path: str
    line: int
    pattern: re.Pattern[str]


def placed_in_includes(robot: Robot) -> Robot:
    """``robot`` (an expanded xacro file) with its macro-made links and joints placed in the
    files that write them (the xacro file itself first, then :attr:`Robot.included_files`)."""
    unplaced = {
        kind: [n for e in robot.document.findall(kind) if (n := e.get("name")) and n not in lines]
        for kind, lines in (("link", robot.link_lines), ("joint", robot.joint_lines))
    }
    places = included_places(unplaced, [robot.path, *robot.included_files])
    return replace(robot, include_places=FrozenMap(places)) if places else robot


def included_places(
    unplaced: Mapping[str, Iterable[str]], files: Sequence[str]
) -> dict[tuple[str, str], Place]:
    """``(kind, name) -> (file, line)`` for the names of ``unplaced`` (``{"link": names,
    "joint": names}``) that fit an element template of one of ``files`` (in include order:
    on a tie the first file, then the first line, wins)."""
    wanted = {kind: list(names) for kind, names in unplaced.items() if names}
    if not wanted:
        return {}
    templates: dict[str, list[_Template]] = {kind: [] for kind in wanted}
    for path in dict.fromkeys(files):
        for kind, template in _templates(path):
            if kind in templates:
                templates[kind].append(template)
    for found in templates.values():  # the closest fit first; stable: file, then line order
        found.sort(key=lambda t: -t.literal)
    out: dict[tuple[str, str], Place] = {}
    for kind, names in wanted.items():
        for name in names:
            fit = next((t for t in templates[kind] if t.pattern.fullmatch(name)), None)
            if fit is not None:
                out[(kind, name)] = (fit.path, fit.line)
    return out


def _templates(path: str) -> list[tuple[str, _Template]]:
    text = reread_text(path, errors="replace")
    if text is None:
        return []
    out: list[tuple[str, _Template]] = []
    for kind, start, literal, pattern in _name_templates(text):
        if literal:  # a template without literal text fits every name
            out.append((kind, _Template(literal, path, line_col(text, start)[0], pattern)))
            if len(out) >= _MAX_TEMPLATES:
                break
    return out


def _name_templates(text: str) -> Iterator[tuple[str, int, int, re.Pattern[str]]]:
    """``(kind, offset, literal characters, pattern)`` of each ``<link>``/``<joint>`` of
    ``text`` whose name holds an expression (literal names are the top file's to place)."""
    for m in _ELEMENT.finditer(text):
        value = m.group(2) if m.group(2) is not None else m.group(3)
        if "$" not in value:
            continue
        pieces = _EXPRESSION.split(value)
        pattern = re.compile(".*?".join(re.escape(p) for p in pieces), re.S)
        yield m.group(1), m.start(), sum(len(p) for p in pieces), pattern


def template_offset(text: str, kind: str, name: str) -> int | None:
    """Where in the xacro ``text`` a ``<link>``/``<joint>`` (``kind``) whose name template
    fits ``name`` starts, the one with the most literal text first; here a name that is one
    expression (``name="${nan}"``) fits too: for a name no text writes as it is."""
    fits = [
        (-literal, start)
        for k, start, literal, pattern in _name_templates(text)
        if k == kind and pattern.fullmatch(name)
    ]
    return min(fits)[1] if fits else None


def located_error(
    error: UrdfError, path: str, places: Mapping[tuple[str, str], Place]
) -> UrdfError:
    """``error``, when it is about one link or joint (``joint 'X' …``) of the robot file
    ``path`` and has no line, moved to where ``places`` says that element is written."""
    m = _ABOUT.match(error.message) if error.path == path and error.line is None else None
    place = places.get((m.group(1), m.group(2))) if m else None
    if place is None:
        return error
    return type(error)(error.message, path=place[0], line=place[1])


def located_at_elements(
    diagnostics: Iterable[Diagnostic], path: str, places: Mapping[tuple[str, str], Place]
) -> list[Diagnostic]:
    """``diagnostics``, those about one link or joint (``link 'X' …``) of the robot file
    ``path`` that have no line moved to where ``places`` says that element is written."""
    out = []
    for d in diagnostics:
        m = _ABOUT.match(d.message) if places and d.path == path and d.line is None else None
        place = places.get((m.group(1), m.group(2))) if m else None
        out.append(d if place is None else replace(d, path=place[0], line=place[1]))
    return out
