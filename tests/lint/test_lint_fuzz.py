"""Lint never raises: thousands of mutated XRDF documents end in diagnostics or a clean result.

Mutations start from valid files (bundled fixtures and per-rule passing fixtures): keys deleted,
values replaced by other types, numbers negated/zeroed/made infinite, lists emptied, names
changed, the text cut short. The same seeds run every time (derandomized).
"""

from __future__ import annotations

import copy
from typing import Any
from unittest import mock

import pytest
import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tests.paths import FIXTURES, SEED_XRDF, UR10E_XRDF
from xrdf_tools.lint import INTERNAL_ERROR, lint_text, schema

SOURCES = [
    UR10E_XRDF,
    SEED_XRDF,
    FIXTURES / "panda" / "panda.xrdf",
    *sorted((FIXTURES / "lint").glob("*/pass*.xrdf")),
]
DOCS = [yaml.safe_load(p.read_text()) for p in SOURCES]
TEXTS = [p.read_text() for p in SOURCES]
REPLACEMENTS: list[Any] = [
    None,
    0,
    1,
    -1,
    0.0,
    -0.5,
    float("inf"),
    float("nan"),
    "",
    "x",
    "link1",
    True,
    [],
    {},
    [1, 2],
    ["a"],
    {"a": 1},
    [[0.0, 0.0, 0.0]],
    {"center": [0, 0], "radius": -1},
]


def _paths(node: Any, prefix: tuple[Any, ...] = ()) -> list[tuple[Any, ...]]:
    out = [prefix]
    if isinstance(node, dict):
        for k, v in node.items():
            out += _paths(v, (*prefix, k))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            out += _paths(v, (*prefix, i))
    return out


def _mutate(doc: Any, path: tuple[Any, ...], op: int, value: Any) -> Any:
    doc = copy.deepcopy(doc)
    if not path:
        return value
    parent = doc
    for k in path[:-1]:
        parent = parent[k]
    key = path[-1]
    if op == 0:
        del parent[key]
    elif op == 1:
        parent[key] = value
    elif op == 2 and isinstance(parent, dict):
        parent[f"{key}_x"] = parent.pop(key)  # rename the key
    elif op == 3 and isinstance(parent[key], (int, float)) and not isinstance(parent[key], bool):
        parent[key] = -parent[key] if parent[key] else -1.0
    else:
        parent[key] = [parent[key]] if op % 2 else {"k": parent[key]}
    return doc


@st.composite
def mutated(draw: st.DrawFn) -> str:
    i = draw(st.integers(0, len(DOCS) - 1))
    if draw(st.integers(0, 9)) == 0:  # raw text damage
        text = TEXTS[i]
        cut = draw(st.integers(0, len(text)))
        return text[:cut] + draw(st.sampled_from(["", ":", "[", "- ", "\t", "{a: ", "&x *x"]))
    doc = DOCS[i]
    for _ in range(draw(st.integers(1, 3))):
        paths = _paths(doc)
        path = draw(st.sampled_from(paths))
        doc = _mutate(doc, path, draw(st.integers(0, 4)), draw(st.sampled_from(REPLACEMENTS)))
    return yaml.safe_dump(doc, sort_keys=False)


#: Every run draws the same examples, however long they take.
FIXED = settings(
    derandomize=True,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
    database=None,
)


@pytest.mark.slow
@settings(FIXED, max_examples=1000)
@given(mutated())
def test_lint_never_raises_on_mutated_documents(text: str) -> None:
    diags = lint_text(text, "fuzz.xrdf")
    assert not [d for d in diags if d.rule == INTERNAL_ERROR], diags


def test_mutations_do_find_problems() -> None:
    """The fuzz corpus is not trivially clean: deleting cspace or a radius is reported."""
    doc = DOCS[0]
    no_cspace = yaml.safe_dump(_mutate(doc, ("cspace",), 0, None), sort_keys=False)
    assert any(d.rule == "required-key" for d in lint_text(no_cspace))


@settings(FIXED, max_examples=300)
@given(mutated())
def test_the_schema_walk_shortcuts_change_no_finding(text: str) -> None:
    """The schema walk skips items it can tell are fine from their values (lists of plain
    numbers, spheres): the findings are those of the walk that visits every item."""
    fast = lint_text(text, "fuzz.xrdf")
    with (
        mock.patch.object(schema, "_quiet", lambda node, shape: False),
        mock.patch.object(schema, "_plain_items_fit", lambda node, shape: False),
    ):
        slow = lint_text(text, "fuzz.xrdf")
    assert fast == slow
