"""No pair of sphere frames is left for cuRobo's self-collision check.

cuRobo's loader sets up self-collision between the spheres of every two frames that
``self_collision.ignore`` does not mask, and it divides by the number of such pairs: when there
is none -- every pair masked, or spheres on a single frame -- it raises (ZeroDivisionError)
before any planning. cuRobo has no switch in the robot description to turn self-collision off;
leave the pairs that can collide unmasked (``xrdf report --write-mask`` masks only pairs that
never collide), or turn self-collision checking off in cuRobo's planner configuration and keep
at least one pair here.
"""

from __future__ import annotations

from collections.abc import Iterator

from ...diagnostics import Severity
from ...yaml.io import YMap, YSeq
from ..context import LintContext, Problem, Rule, name


def _masked(ctx: LintContext) -> set[frozenset[str]]:
    section = ctx.get("self_collision")
    mask = section.get("ignore") if isinstance(section, YMap) else None
    out: set[frozenset[str]] = set()
    if isinstance(mask, YMap):
        for k, v in mask.pairs:
            a = name(k)
            items = v.items if isinstance(v, YSeq) else []
            out.update(frozenset((a, b)) for i in items if a and (b := name(i)) and b != a)
    return out


def check(ctx: LintContext) -> Iterator[Problem]:
    world = ctx.get(ctx.world_key())
    group = ctx.group_name(world) if isinstance(world, YMap) else None
    if group is None or group not in ctx.groups or not (ctx.sphere_frames(group) or ()):
        return
    frames = sorted({s.frame for s in ctx.resolved_spheres(group) or ()})
    pairs = {frozenset((a, b)) for i, a in enumerate(frames) for b in frames[i + 1 :]}
    if pairs - _masked(ctx):
        return
    if len(frames) < 2:
        what, fix = f"spheres on {len(frames)} frame(s) only", "give a second frame spheres"
    else:
        what = f"all {len(pairs)} pairs of its {len(frames)} sphere frames are masked"
        fix = "leave a pair that can collide unmasked"
    yield ctx.problem(
        ctx.get("self_collision") or world,
        f"no pair of sphere frames is left to check for self-collision ({what}): cuRobo's "
        f"loader raises (ZeroDivisionError) when there is none; {fix}",
        "self_collision.ignore",
    )


RULE = Rule("curobo-no-pair", Severity.WARNING, check, __doc__ or "", reader="curobo")
