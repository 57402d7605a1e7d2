"""A key that cuRobo's XRDF loader requires is missing (or is a list where it needs a map).

cuRobo (and Isaac ROS cuMotion) raise while loading when ``tool_frames`` is missing or empty
(the first is taken as the end effector), when ``default_joint_positions`` is missing, when a
``collision`` section has no ``self_collision`` beside it, or when ``self_collision`` has no
``ignore`` (write ``ignore: {}`` for none). ``ignore: []`` (what cuRobo's own XRDF writer emits
when nothing is masked) makes its loader raise as well: it looks the frames up as map keys. A 1.0
file without ``collision`` does not load either: cuRobo's XRDF converter only logs that
collision avoidance is disabled, but its robot loader then fails on the missing
``collision_spheres`` (KeyError). The spec makes these keys optional, and the cuMotion library
loads such files; 11 of cuMotion's 20 example XRDFs have no ``tool_frames``.
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ...yaml.io import YMap, YSeq
from ..context import LintContext, Problem, Rule, is_null


def check(ctx: LintContext) -> Iterator[Problem]:
    if ctx.top is None or ctx.version is None:
        return
    tools = ctx.get("tool_frames")
    if not isinstance(tools, YSeq) or not len(tools):
        yield ctx.problem(
            tools,
            "no tool_frames: cuRobo's loader raises (it takes tool_frames[0] as the end effector)",
            "tool_frames",
        )
    if is_null(ctx.get("default_joint_positions")):
        yield ctx.problem(
            None,
            "no default_joint_positions: cuRobo's loader raises",
            "default_joint_positions",
        )
    yield from _collision(ctx)


def _collision(ctx: LintContext) -> Iterator[Problem]:
    world = ctx.get("collision")
    if ctx.version == "1.0" and not isinstance(world, YMap):
        yield ctx.problem(
            None,
            "no collision section: cuRobo's robot loader raises (KeyError 'collision_spheres'; "
            "its XRDF converter alone would load the robot with collision avoidance disabled)",
            "collision",
        )
        return
    if not isinstance(world, YMap):
        return  # a 2.0 file: curobo-format-version says what cuRobo does with it
    self_c = ctx.get("self_collision")
    if not isinstance(self_c, YMap):
        yield ctx.problem(
            ctx.top.key_node("collision") if ctx.top is not None else None,
            "collision without self_collision: cuRobo's loader raises ('self_collision key "
            "not found')",
            "self_collision",
        )
    elif "ignore" not in self_c:
        yield ctx.problem(
            ctx.top.key_node("self_collision") if ctx.top is not None else None,
            "self_collision has no ignore: cuRobo's loader raises ('ignore key not found'); "
            "write ignore: {} for none",
            "self_collision.ignore",
        )
    elif isinstance(self_c.get("ignore"), YSeq):
        yield ctx.problem(
            self_c.get("ignore"),
            "self_collision.ignore is a list: cuRobo's loader raises (it looks frames up as "
            "keys of a map); write ignore: {} for none",
            "self_collision.ignore",
        )


RULE = Rule("curobo-missing-key", Severity.WARNING, check, __doc__ or "", reader="curobo")
