"""A mapping repeats a key.

YAML requires unique keys, but common loaders silently keep the last value, so a repeated
default joint position, buffer distance or sphere frame quietly loses data. cuMotion rejects
repeated keys in ``default_joint_positions``, ``buffer_distance`` and ``spheres``. (One public
cuMotion test file named "valid" repeats a sphere frame while its twin named "invalid" does the
same; we follow the stricter loader.) Merge the entries into one key.

With ``--target curobo`` a repeat that loses nothing is a warning: cuRobo's YAML reader keeps
the last entry, so when that entry holds everything the earlier ones do (the same value, or a
list with all their items, as the ``self_collision.ignore`` of Isaac ROS cuMotion's
``ur5e_robotiq_2f_140.xrdf`` repeats five links), cuRobo builds the robot the author meant.
The other commands of xrdf-tools still stop at the repeated key: merge the entries.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

from ...diagnostics import Severity
from ...yaml.io import YMap, YNode, YSeq
from ...yaml.tree import DuplicateKey, to_python
from ..context import LintContext, Problem, Rule


def check(ctx: LintContext) -> Iterator[Problem]:
    if ctx.doc is None:
        return
    lossless = _kept_by_last(ctx.doc.root, ctx.doc.duplicates) if ctx.target == "curobo" else set()
    for d in ctx.doc.duplicates:
        message = (
            f"duplicate key '{d.key}' (first defined on line {d.first_line}); keys must be "
            "unique, merge the entries"
        )
        if (d.line, d.col) in lossless:
            message += (
                "; cuRobo keeps the last entry, which holds everything the earlier ones do, "
                "so it loads the robot as meant"
            )
            yield Problem(d.line, d.col, message, d.key_path, Severity.WARNING)
        else:
            yield Problem(d.line, d.col, message, d.key_path)


def _kept_by_last(root: YNode | None, dups: tuple[DuplicateKey, ...]) -> set[tuple[int, int]]:
    """Positions of the repeated keys whose earlier values the last value of their key holds."""
    wanted = {(d.line, d.col) for d in dups}
    out: set[tuple[int, int]] = set()
    for node in _maps(root):
        keys = [k for k, _ in node.pairs]
        if not any((k.line, k.col) in wanted for k in keys):
            continue
        values: dict[Any, list[Any]] = {}
        for k, v in node.pairs:
            values.setdefault(getattr(k, "value", None), []).append(to_python(v))
        for k in keys:
            if (k.line, k.col) in wanted:
                *earlier, last = values[getattr(k, "value", None)]
                if all(_holds(last, e) for e in earlier):
                    out.add((k.line, k.col))
    return out


def _holds(last: Any, earlier: Any) -> bool:
    """Whether keeping ``last`` loses nothing of ``earlier``."""
    if last == earlier:
        return True
    if isinstance(last, list) and isinstance(earlier, list):
        return all(item in last for item in earlier)
    return False


def _maps(node: YNode | None) -> Iterator[YMap]:
    stack = [node]
    while stack:
        n = stack.pop()
        if isinstance(n, YMap):
            yield n
            stack.extend(v for _, v in n.pairs)
        elif isinstance(n, YSeq):
            stack.extend(n.items)


RULE = Rule("duplicate-key", Severity.ERROR, check, __doc__ or "")
