"""A mapping repeats a key.

YAML requires unique keys, but common loaders silently keep the last value, so a repeated
default joint position, buffer distance or sphere frame quietly loses data. cuMotion rejects
repeated keys in ``default_joint_positions``, ``buffer_distance`` and ``spheres``. (One public
cuMotion test file named "valid" repeats a sphere frame while its twin named "invalid" does the
same; we follow the stricter loader.) Merge the entries into one key.
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ..context import LintContext, Problem, Rule


def check(ctx: LintContext) -> Iterator[Problem]:
    if ctx.doc is None:
        return
    for d in ctx.doc.duplicates:
        yield Problem(
            d.line,
            d.col,
            f"duplicate key '{d.key}' (first defined on line {d.first_line}); keys must be "
            "unique, merge the entries",
            d.key_path,
        )


RULE = Rule("duplicate-key", Severity.ERROR, check, __doc__ or "")
