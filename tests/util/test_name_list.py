"""Names in one-line messages: a few shown, the rest counted."""

from __future__ import annotations

from xrdf_tools.util.text import name_list


def test_short_lists_are_shown_whole() -> None:
    assert name_list(["a", "b", "c"], 3) == "a, b, c"
    assert name_list([], 3) == ""


def test_long_lists_show_the_first_names_and_count_the_rest() -> None:
    names = [f"j{i}" for i in range(3000)]
    text = name_list(names, 4)
    assert text == "j0, j1, j2, j3 and 2996 more"


def test_any_iterable_of_printable_values() -> None:
    assert name_list((repr(n) for n in ["x", "y"]), 1) == "'x' and 1 more"
