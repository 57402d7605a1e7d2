"""Where the elements of an expanded xacro file that a macro makes are written.

An expanded xacro file locates the elements it writes literally (see
``urdf_source.relocate_expansion``); the ones a macro of an included file makes
(``<link name="${prefix}link_3">`` in ``kr6_macro.xacro``, ``<group name="ur_manipulator">``
in UR's ``ur_macro.srdf.xacro``) have no line in it. Such an element is placed at the element
of an included file whose identifying attributes (a link's ``name``, a group state's ``name``
and ``group``, a ``disable_collisions``' ``link1`` and ``link2``: :data:`URDF_KEYS`,
``SRDF_KEYS`` in the SRDF reader) it fits: a template's ``${…}`` and ``$(…)`` stand for any
text, and of the templates that fit, the one with the most literal text wins
(``${prefix}link_3`` over ``${prefix}${name}``). A template that is expressions only
(``name="${name}"``) fits no name by itself: the element is then placed at the macro call that
makes it, the call whose arguments (or the macro's defaults) give that name. Messages about the
element then point where the user would edit it. One implementation for the URDF's links and
joints and the SRDF's groups, states, end effectors and collision pairs.
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
    "URDF_KEYS",
    "ElementKey",
    "Place",
    "included_places",
    "located_at_elements",
    "located_error",
    "placed_in_includes",
    "template_offset",
]

#: ``(file, line)`` where an element is written.
Place = tuple[str, int]
#: An element: its tag, then the values of the attributes that tell it apart (``("joint",
#: "j1")``, ``("disable_collisions", "a", "b")``).
ElementKey = tuple[str, ...]
#: The attributes that tell a URDF's links and joints apart.
URDF_KEYS: Mapping[str, tuple[str, ...]] = FrozenMap({"link": ("name",), "joint": ("name",)})

_ATTRIBUTE = re.compile(r"([\w:.-]+)\s*=\s*(?:\"([^\"]*)\"|'([^']*)')")
_EXPRESSION = re.compile(r"\$\{[^}]*\}|\$\([^)]*\)")
_PARAMETER = re.compile(r"\$\{\s*([A-Za-z_]\w*)\s*\}")
_MACRO = re.compile(r"<xacro:macro\b([^>]*)>(.*?)</xacro:macro\s*>", re.S)
_ABOUT = re.compile(r"(link|joint) '([^']+)'")
#: Templates read per file at most (a generated file of thousands of elements is no macro).
_MAX_TEMPLATES = 5000


@dataclass(frozen=True)
class _Template:
    literal: int  # characters of literal text: more is a closer fit
    path: str
    line: int
    patterns: tuple[re.Pattern[str], ...]
    values: tuple[str, ...]  # the attribute values as written
    offset: int


def placed_in_includes(robot: Robot) -> Robot:
    """``robot`` (an expanded xacro file) with its macro-made links and joints placed in the
    files that write them (the xacro file itself first, then :attr:`Robot.included_files`)."""
    unplaced = [
        (kind, n)
        for kind, lines in (("link", robot.link_lines), ("joint", robot.joint_lines))
        for e in robot.document.findall(kind)
        if (n := e.get("name")) and n not in lines
    ]
    places = included_places(unplaced, [robot.path, *robot.included_files], URDF_KEYS)
    named = FrozenMap(((k[0], k[1]), place) for k, place in places.items())
    return replace(robot, include_places=named) if places else robot


def included_places(
    unplaced: Iterable[ElementKey],
    files: Sequence[str],
    keys: Mapping[str, tuple[str, ...]],
) -> dict[ElementKey, Place]:
    """``key -> (file, line)`` for the elements ``unplaced`` (keys of the tags of ``keys``,
    which names the identifying attributes of each tag) that fit an element template of one
    of ``files`` (in include order: on a tie the first file, then the first line, wins), else
    that a macro call of those files makes from a template of expressions only."""
    wanted = list(dict.fromkeys(k for k in unplaced if k and k[0] in keys))
    if not wanted:
        return {}
    texts = {
        path: text
        for path in dict.fromkeys(files)
        if (text := reread_text(path, errors="replace")) is not None
    }
    templates: dict[str, list[_Template]] = {tag: [] for tag in keys}
    for path, text in texts.items():
        for tag, template in _templates(path, text, keys):
            templates[tag].append(template)
    for found in templates.values():  # the closest fit first; stable: file, then line order
        found.sort(key=lambda t: -t.literal)
    made, made_in_macros = _call_places(templates, texts)
    out: dict[ElementKey, Place] = {}
    for key in wanted:
        fit = next((t for t in templates[key[0]] if t.literal and _fits(t, key)), None)
        if fit is None:  # a call inside another macro: name="robot_${prefix}/base_link"
            fit = next((t for t in made_in_macros[key[0]] if t.literal and _fits(t, key)), None)
        place = (fit.path, fit.line) if fit else made.get(key)
        if place is not None:
            out[key] = place
    return out


def _fits(template: _Template, key: ElementKey) -> bool:
    return all(p.fullmatch(v) for p, v in zip(template.patterns, key[1:], strict=True))


def _templates(
    path: str, text: str, keys: Mapping[str, tuple[str, ...]]
) -> list[tuple[str, _Template]]:
    out: list[tuple[str, _Template]] = []
    for tag, start, literal, patterns, values in _element_templates(text, keys):
        line = line_col(text, start)[0]
        out.append((tag, _Template(literal, path, line, patterns, values, start)))
        if len(out) >= _MAX_TEMPLATES:
            break
    return out


def _element_templates(
    text: str, keys: Mapping[str, tuple[str, ...]]
) -> Iterator[tuple[str, int, int, tuple[re.Pattern[str], ...], tuple[str, ...]]]:
    """``(tag, offset, literal characters, patterns, values)`` of each start tag of ``text``
    of a tag of ``keys`` that has its identifying attributes (one pattern per attribute; a
    missing attribute is the empty text). A self-closing ``<group name="x"/>`` is a subgroup
    named inside a group, not one written there."""
    tags = "|".join(re.escape(t) for t in keys)
    for m in re.finditer(rf"<({tags})\b((?:[^>\"']|\"[^\"]*\"|'[^']*')*?)(/?)>", text):
        tag, attributes = m.group(1), _attributes(m.group(2))
        if tag == "group" and m.group(3):
            continue
        values = tuple(attributes.get(a, "").strip() for a in keys[tag])
        if not any(values):
            continue
        pieces = [_EXPRESSION.split(v) for v in values]
        patterns = tuple(re.compile(".*?".join(re.escape(p) for p in ps), re.S) for ps in pieces)
        yield tag, m.start(), sum(len(p) for ps in pieces for p in ps), patterns, values


def _attributes(text: str) -> dict[str, str]:
    return {
        a.group(1): a.group(2) if a.group(2) is not None else a.group(3)
        for a in _ATTRIBUTE.finditer(text)
    }


def _call_places(
    templates: Mapping[str, Sequence[_Template]], texts: Mapping[str, str]
) -> tuple[dict[ElementKey, Place], dict[str, list[_Template]]]:
    """``key -> (file, line)`` of the macro calls that make an element from a template of
    expressions only: each ``${param}`` replaced by the call's argument, or the macro's
    default, gives the element's values. The first template, then file, then call wins.
    Second, per tag, the calls whose arguments are templates themselves (a call inside
    another macro: ``<xacro:cylinder_link name="robot_${prefix}/base_link"/>``), as templates
    placed at the call, the one with the most literal text first."""
    macros = {path: _macros(text) for path, text in texts.items()}
    calls: dict[str, list[tuple[Place, dict[str, str]]]] = {}
    out: dict[ElementKey, Place] = {}
    in_macros: dict[str, list[_Template]] = {tag: [] for tag in templates}
    for tag, found in templates.items():
        for t in found:
            if t.literal or not all(_PARAMETER.fullmatch(p) for v in t.values for p in _parts(v)):
                continue
            macro = next((m for m in macros[t.path] if m[0] <= t.offset < m[1]), None)
            if macro is None:
                continue
            if macro[2] not in calls:
                calls[macro[2]] = list(_calls(macro[2], texts))
            for place, given in calls[macro[2]]:
                values = _made(t.values, {**macro[3], **given})
                if values is None:
                    continue
                if any("$" in v for v in values):
                    in_macros[tag].append(_call_template(place, values))
                else:
                    out.setdefault((tag, *values), place)
    for found in in_macros.values():
        found.sort(key=lambda t: -t.literal)
    return out, in_macros


def _call_template(place: Place, values: tuple[str, ...]) -> _Template:
    """A template of the element values a call inside a macro gives, placed at the call."""
    pieces = [_EXPRESSION.split(v) for v in values]
    patterns = tuple(re.compile(".*?".join(re.escape(p) for p in ps), re.S) for ps in pieces)
    literal = sum(len(p) for ps in pieces for p in ps)
    return _Template(literal, place[0], place[1], patterns, values, 0)


def _calls(name: str, texts: Mapping[str, str]) -> Iterator[tuple[Place, dict[str, str]]]:
    """Each call of the macro ``name`` in ``texts`` (file, then line order) and its
    arguments."""
    for path, text in texts.items():
        for call in re.finditer(rf"<xacro:{re.escape(name)}\b([^>]*)>", text):
            yield (path, line_col(text, call.start())[0]), _attributes(call.group(1))


def _parts(value: str) -> list[str]:
    """The expressions of ``value`` (a template without literal text)."""
    return _EXPRESSION.findall(value)


def _made(values: tuple[str, ...], given: Mapping[str, str]) -> tuple[str, ...] | None:
    """``values`` with each ``${param}`` replaced by its argument, which may hold
    expressions itself (None when one has no value)."""
    out = []
    for value in values:
        made = value
        for expression in _parts(value):
            param = _PARAMETER.fullmatch(expression)
            arg = given.get(param.group(1)) if param else None
            if arg is None:
                return None
            made = made.replace(expression, arg, 1)
        out.append(made)
    return tuple(out)


def _macros(text: str) -> list[tuple[int, int, str, dict[str, str]]]:
    """The ``<xacro:macro>`` definitions of ``text``: where each body starts and ends, the
    macro's name and the defaults of its parameters (``prefix:=''`` → ``{"prefix": ""}``)."""
    out = []
    for m in _MACRO.finditer(text):
        head = _attributes(m.group(1))
        out.append((m.start(2), m.end(2), head.get("name", ""), _defaults(head.get("params", ""))))
    return out


def _defaults(params: str) -> dict[str, str]:
    out: dict[str, str] = {}
    for word in re.findall(r"[^\s=:]+:?=(?:'[^']*'|\"[^\"]*\"|\S*)", params):
        name, _, value = word.partition("=")
        value = value.removeprefix("^|").removeprefix("^")
        out[name.rstrip(":").lstrip("*")] = value.strip("'\"")
    return out


def template_offset(text: str, kind: str, name: str) -> int | None:
    """Where in the xacro ``text`` a ``<link>``/``<joint>`` (``kind``) whose name template
    fits ``name`` starts, the one with the most literal text first; here a name that is one
    expression (``name="${nan}"``) fits too: for a name no text writes as it is."""
    fits = [
        (-literal, start)
        for k, start, literal, (pattern,), _ in _element_templates(text, URDF_KEYS)
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
