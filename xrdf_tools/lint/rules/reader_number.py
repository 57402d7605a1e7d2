"""A value that cuRobo's YAML reader reads differently from the YAML 1.2 written here.

cuRobo (and Isaac ROS cuMotion through it) loads an XRDF with PyYAML, which reads YAML 1.1:
``017`` is the octal 15 there (17 here), ``0o17`` the string ``'0o17'`` (15 here), ``1:30`` the
sexagesimal 90 (a string here), ``1e-3`` and ``1.0e3`` strings (numbers here: YAML 1.1 wants a
``.`` and a signed exponent), ``1_000`` the integer 1000, ``yes``/``no``/``on``/``off`` booleans
(strings here). The file then means one thing to ``xrdf`` and another to the planner. Each such
plain value is reported with both readings; write it so both read it alike (``17.0``,
``1.0e-03``, ``"yes"``). ``xrdf export`` and ``xrdf convert`` always write numbers that way.
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterator
from typing import Any

from ...diagnostics import Severity
from ...yaml.io import YMap, YNode, YScalar, YSeq
from ..context import LintContext, Problem, Rule

#: Text that may read differently in YAML 1.1 (a cheap scan before the tree is walked).
_SUSPECT = re.compile(
    r"(?<![\w.])[-+]?(?:0[0-9_ob]|[0-9][0-9_]*(?:_|:[0-5]?[0-9]|[eE]))"
    r"|[0-9.][eE][0-9]"
    r"|(?<![\w.])(?:yes|Yes|YES|no|No|NO|on|On|ON|off|Off|OFF)(?![\w.])"
)
_END = re.compile(r"[,\]}\s#]")


def check(ctx: LintContext) -> Iterator[Problem]:
    if ctx.root is None:
        return
    lines = ctx.text.splitlines()
    suspect = {ctx.text.count("\n", 0, m.start()) + 1 for m in _SUSPECT.finditer(ctx.text)}
    if not suspect:
        return
    for node, key_path in _plain_scalars(ctx.root, suspect):
        token = _token(lines, node)
        if token is None:
            continue
        theirs = _yaml11(token)
        if _same(node.value, theirs):
            continue
        yield ctx.problem(
            node,
            f"{key_path or 'value'} '{token}' is {_shown(node.value)} here (YAML 1.2) but "
            f"{_shown(theirs)} for cuRobo (PyYAML reads YAML 1.1); write {_advice(node.value)}",
            key_path,
        )


def _plain_scalars(root: YNode, lines: set[int]) -> Iterator[tuple[YScalar, str]]:
    """Unquoted scalars on ``lines``, with their key paths (values and keys alike)."""
    last = max(lines)
    stack: list[tuple[YNode, str]] = [(root, "")]
    while stack:
        node, kp = stack.pop()
        if node.line is not None and node.line > last:
            continue
        if isinstance(node, YScalar):
            if not node.quoted and node.line in lines:
                yield node, kp
        elif isinstance(node, YMap):
            for k, v in reversed(node.pairs):
                name = k.value if isinstance(k, YScalar) else "?"
                stack.append((v, f"{kp}.{name}" if kp else str(name)))
                stack.append((k, kp))
        elif isinstance(node, YSeq):
            stack.extend((item, f"{kp}[{i}]") for i, item in reversed(list(enumerate(node.items))))


def _token(lines: list[str], node: YScalar) -> str | None:
    """The text of a one-line plain scalar at the node's position, or None."""
    if node.line is None or node.col is None or node.line > len(lines):
        return None
    text = lines[node.line - 1][node.col - 1 :]
    m = _END.search(text)
    token = text[: m.start()] if m else text
    if isinstance(node.value, str) and token != node.value:
        return None  # a plain string of several words, or one spanning lines
    return token or None


def _yaml11(token: str) -> Any:
    import yaml

    try:
        return yaml.safe_load(token)
    except yaml.YAMLError:
        return token


def _same(ours: Any, theirs: Any) -> bool:
    if type(ours) is not type(theirs):
        return (
            isinstance(ours, (int, float))
            and isinstance(theirs, (int, float))
            and not (isinstance(ours, bool) or isinstance(theirs, bool))
            and float(ours) == float(theirs)
        )
    if isinstance(ours, float) and math.isnan(ours):
        return math.isnan(theirs)
    return bool(ours == theirs)


def _shown(value: Any) -> str:
    if isinstance(value, str):
        return f"the string '{value}'"
    if isinstance(value, bool):
        return f"the boolean {str(value).lower()}"
    return f"the number {value!r}"


def _advice(value: Any) -> str:
    if isinstance(value, bool) or value is None:
        return str(value).lower()
    if isinstance(value, (int, float)):
        from ...xrdf.write import format_float

        return format_float(float(value))
    return f'"{value}" (quoted)'


RULE = Rule("reader-number", Severity.WARNING, check, __doc__ or "", reader="curobo")
