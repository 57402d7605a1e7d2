"""Geometry groups that clone each other: long chains lint in linear time, a cycle is one short
line."""

from __future__ import annotations

import time

import pytest

from xrdf_tools.util.errors import SchemaError


def _clone_chain(n: int, cycle: bool) -> str:
    lines = ["format: xrdf", "format_version: 2.0", "geometry:"]
    for i in range(n):
        last = i == n - 1
        clone = "[g0]" if last and cycle else f"[g{i + 1}]"
        spheres = "    spheres: {a: [{center: [0, 0, 0], radius: 0.1}]}"
        lines += [f"  g{i}:", spheres if last and not cycle else f"    clone: {clone}"]
    lines += ["world_collision:", "  geometry: g0"]
    return "\n".join(lines) + "\n"


@pytest.mark.parametrize("cycle", [False, True])
def test_long_clone_chains_lint_in_linear_time(cycle: bool) -> None:
    from xrdf_tools.lint import lint_text

    start = time.monotonic()
    diags = lint_text(_clone_chain(3000, cycle), "clones.xrdf")
    assert time.monotonic() - start < 15
    assert (sum(d.rule == "clone-cycle" for d in diags) == 3000) is cycle


def test_clone_cycle_message_is_one_short_line() -> None:
    from xrdf_tools.xrdf.io import parse_xrdf

    with pytest.raises(
        SchemaError,
        match=r"^clones.xrdf:\d+:\d+: world_collision.geometry: geometry groups clone each other: "
        r"g0 -> .* \(2993 more\) -> g2997 -> g2998 -> g2999 -> g0$",
    ):
        parse_xrdf(_clone_chain(3000, True), "clones.xrdf")
