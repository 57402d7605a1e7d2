"""Names with a namespace prefix the URDF never declares (``<sensor:camera>`` without
``xmlns:sensor``).

ROS reads past them: tinyxml knows no namespaces, and a prefixed name is not URDF. So does the
loader, with a located warning per name (``urdf-prefix-undeclared``), except for two prefixes:
``xacro:`` (a xacro file that does not declare xacro, which nothing can read: an error) and
``drake:`` (Drake's parser also matches the prefix as written, so Drake reads an undeclared
``drake:acceleration`` or ``<drake:collision_filter_group>``: the loader moves them into a
namespace of their own, where :mod:`xrdf_tools.robot.drake` reads them as Drake does).
"""

from __future__ import annotations

import re
from typing import Any

from ..diagnostics import Diagnostic, Severity
from ..util.errors import UrdfError
from ..util.safe_xml import XmlSyntaxError
from .drake import DRAKE_NS, UNDECLARED_DRAKE
from .urdf_check import RULE_PREFIX_UNDECLARED, XACRO_NS

__all__ = ["drop_prefixed_names", "undeclared_prefix_warning"]

#: libxml2's words for a prefix without its declaration.
_UNDECLARED_PREFIX = re.compile(r"Namespace prefix (\S+) ")


def undeclared_prefix_warning(error: XmlSyntaxError, path: str) -> Diagnostic:
    """The located warning for one undeclared prefix; raises for a ``xacro:`` one."""
    prefix = _UNDECLARED_PREFIX.match(error.reason)
    name = prefix.group(1) if prefix else "..."
    if name == "xacro":
        raise UrdfError(
            f"malformed XML: {error.reason}: a xacro file must declare "
            f'xmlns:xacro="{XACRO_NS}" on <robot>',
            path=path,
            line=error.line,
            col=error.col,
        )
    if name == "drake":
        how = "ROS ignores it, Drake reads it (its parser matches the prefix as written): read "
        how += f'as Drake\'s; declare xmlns:drake="{DRAKE_NS}" on <robot>'
    else:
        how = "read on as ROS does: a prefixed name is not URDF and is ignored"
    message = f"{error.reason} (no xmlns:{name}); {how}"
    return Diagnostic(
        path, error.line, error.col, RULE_PREFIX_UNDECLARED, Severity.WARNING, message
    )


def drop_prefixed_names(root: Any) -> None:
    """Remove the elements and attributes whose prefix was never declared (names that keep a
    ``prefix:``, which no lxml name API accepts): none of them is URDF. Drake's move into
    :data:`~xrdf_tools.robot.drake.UNDECLARED_DRAKE` instead (see the module doc)."""
    for el in list(root.iter()):
        if _undeclared(el.tag):
            if el.tag.startswith("drake:"):
                el.tag = f"{{{UNDECLARED_DRAKE}}}{el.tag[len('drake:') :]}"
            else:
                parent = el.getparent()
                if parent is not None:
                    parent.remove(el)
                continue
        for key in [k for k in el.attrib if _undeclared(k)]:
            value = el.attrib.pop(key)
            if key.startswith("drake:"):
                el.set(f"{{{UNDECLARED_DRAKE}}}{key[len('drake:') :]}", value)


def _undeclared(name: Any) -> bool:
    return isinstance(name, str) and ":" in name and not name.startswith("{")
