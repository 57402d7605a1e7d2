"""A frame appears more than once in ``tool_frames``.

Each tool frame is one end of the robot a planner reaches for, the first the end effector; a
repeated name adds nothing but a second, identical goal (``--tool-frame tool0 --tool-frame
tool0``). Remove the repeat.
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ...yaml.io import YSeq
from ..context import LintContext, Problem, Rule, name
from ._repeats import repeats


def check(ctx: LintContext) -> Iterator[Problem]:
    tools = ctx.get("tool_frames")
    if not isinstance(tools, YSeq):
        return
    named = ((n, (i, item)) for i, item in enumerate(tools.items) if (n := name(item)) is not None)
    for n, (i, item), (first, _) in repeats(named):
        yield ctx.problem(
            item,
            f"tool frame '{n}' is already tool_frames[{first}]; each frame may appear once",
            f"tool_frames[{i}]",
        )


RULE = Rule("repeated-tool-frame", Severity.WARNING, check, __doc__ or "")
