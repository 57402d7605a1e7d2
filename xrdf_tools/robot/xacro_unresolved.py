"""``$(find PKG)`` of a package that cannot be found, in parts no command reads.

ROS 2 descriptions name their simulation and control packages in ``<gazebo>`` plugin
parameters and ``<ros2_control>`` blocks (Reachy: ``$(find reachy_gazebo)/config/...``); a
user who has only the description package cannot find them, and no command of xrdf-tools
reads those parts. While expanding, such a ``$(find)`` gives a placeholder path; afterwards
the placeholder is allowed only inside those parts, where it is written back as
``$(find PKG)`` with a located warning. Anywhere else (a mesh, an include, a ``load_yaml``)
the located error of the ``$(find)`` is raised, as before.
"""

from __future__ import annotations

import re
from collections.abc import Iterator, Mapping
from typing import Any

from ..diagnostics import Diagnostic, Severity
from ..util.errors import SourceError

__all__ = ["PLACEHOLDER", "RULE_UNUSED_PACKAGE", "UNUSED_PARTS", "error_for", "settle"]

#: What an unresolved ``$(find PKG)`` gives while expanding: PLACEHOLDER + PKG.
PLACEHOLDER = "/__xrdf_unresolved_package__/"
#: Top-level elements of a robot that no command reads.
UNUSED_PARTS = frozenset({"gazebo", "ros2_control", "transmission"})
RULE_UNUSED_PACKAGE = "xacro-package-unused"

_NAMED = re.compile(re.escape(PLACEHOLDER) + r"([^/\s'\"<>]+)")


def error_for(e: BaseException, unresolved: Mapping[str, SourceError]) -> SourceError | None:
    """The located error of the ``$(find)`` whose placeholder made ``e`` (an include or a
    file that cannot be opened at the placeholder path), else None."""
    text = f"{e} {getattr(e, 'filename', '') or ''} {getattr(e, 'exc', '') or ''}"
    m = _NAMED.search(text)
    return unresolved.get(m.group(1)) if m is not None else None


def settle(
    doc: Any, text: str, unresolved: Mapping[str, SourceError], warnings: list[Diagnostic]
) -> str:
    """``text`` (the expansion of ``doc``, a minidom document) with each placeholder written
    back as ``$(find PKG)`` and a warning per package, when every placeholder lies inside
    :data:`UNUSED_PARTS`; else the located error of the first package used elsewhere."""
    if not unresolved or PLACEHOLDER not in text:
        return text
    parts: dict[str, set[str]] = {}
    for node, value in _values(doc.documentElement):
        for pkg in _NAMED.findall(value):
            part = _unused_part(node, doc.documentElement)
            if part is None:
                raise unresolved[pkg]
            parts.setdefault(pkg, set()).add(part)
    for pkg, where in parts.items():
        e = unresolved[pkg]
        warnings.append(
            Diagnostic(
                e.path or "",
                e.line,
                e.col,
                RULE_UNUSED_PACKAGE,
                Severity.WARNING,
                f"{e.message}; it is named only in {', '.join(f'<{p}>' for p in sorted(where))}, "
                f"which no command reads: left as $(find {pkg})",
            )
        )
    return _NAMED.sub(lambda m: f"$(find {m.group(1)})", text)


def _values(node: Any) -> Iterator[tuple[Any, str]]:
    """Every attribute value and text of the elements below ``node``, with its element."""
    for child in node.childNodes:
        if child.nodeType == child.ELEMENT_NODE:
            for value in child.attributes.values():
                yield child, value.value
            yield from _values(child)
        elif child.nodeType in (child.TEXT_NODE, child.CDATA_SECTION_NODE):
            yield node, child.data


def _unused_part(node: Any, root: Any) -> str | None:
    """The tag of the top-level element of :data:`UNUSED_PARTS` that holds ``node``."""
    while node is not None and node.parentNode is not None and node.parentNode is not root:
        node = node.parentNode
    tag = getattr(node, "tagName", None)
    return tag if tag in UNUSED_PARTS else None
