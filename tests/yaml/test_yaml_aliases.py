"""Documents with aliases read the same by every reader: the one-pass builder (aliases shared,
their bounds checked by ``xrdf_tools.yaml.aliases``) on libyaml's and on PyYAML's events, and
the reference (PyYAML's composer and a plain conversion, ``tests/yaml_reference.py``) give the
same tree, repeated keys and message (see ``tests/yaml/test_yaml_readers.py`` for the ways)."""

from __future__ import annotations

import random

import pytest

from tests.yaml.test_yaml_readers import assert_same
from xrdf_tools.yaml.io import YMap, YSeq, parse_yaml, to_python


def _bomb(first: str = "[x, x, x, x, x, x, x, x, x, x]", levels: int = 9) -> str:
    """Nested anchors, each aliasing the one before ten times ("billion laughs")."""
    lines = [f"a0: &a0 {first}\n"]
    lines += [f"a{i}: &a{i} [{', '.join([f'*a{i - 1}'] * 10)}]\n" for i in range(1, levels)]
    return "".join(lines)


# Documents with aliases: shared nodes, keys, repeated keys under aliases, the bounds.
ALIAS_CASES = [
    "base: &b {radius: 0.1}\nothers: [*b, *b, *b]\n",
    "a: [1, &x 2, 3]\nb: [*x, *x]\n",  # an anchored item in a list of plain scalars
    "- &a [1, 2]\n- &b [*a, *a, 3]\n- [*b, *b]\n- *a\n",
    "a: &x\nb: *x\n",
    "a: &x 1\n*x : 2\n",  # an alias as a key
    "a: &x ~\nb: {*x : 1, null: 2}\n",
    "a: &x {b: 1}\n? *x\n: 2\n",  # an alias of a mapping or a list as a key
    "a: &x [1]\n? *x\n: 2\n",
    "a: &x {k: 1, k: 2}\nb: {m: 1, m: 2}\nc: *x\n",  # repeated keys once per alias
    "a: &x [{k: 1, k: 2}]\nb: {c: *x, d: [*x]}\n",
    "a: !!int &x zz\nb: [*x, 1]\n",  # a bad scalar, anchored
    "a: &x !!int zz\nb: [1, *x]\n",
    "a: &a [&b [*b, *a]]\n",  # aliases inside their own anchors
    "a: &a [1, *a]\nb: &b [*b]\n",
    "a: &a {x: *a}\n",
    "&r [*r]\n",
    "a: &a " + "[" * 99 + "]" * 99 + "\nb: " + "[" * 3 + "*a" + "]" * 3 + "\n",  # nesting
    "a: &a " + "[" * 95 + "]" * 95 + "\nb: " + "[" * 6 + "*a" + "]" * 6 + "\nc: !!int q\n",
    "c: !!int q\na: &a " + "[" * 95 + "]" * 95 + "\nb: " + "[" * 6 + "*a" + "]" * 6 + "\n",
    _bomb(),  # the expansion bound: the same node and figure
    _bomb("{a: x, b: x, c: x, d: x, e: x, f: x, g: x, h: x, i: x, j: x}"),
    _bomb() + "z: &z [*z]\n",
    "z: &z [*z]\n" + _bomb(),
    _bomb(levels=5) + "b: *a4\n",
]


@pytest.mark.parametrize("text", ALIAS_CASES, ids=range(len(ALIAS_CASES)))
def test_aliases_read_the_same_by_every_reader(text: str) -> None:
    assert_same(text)


def _alias_document(rng: random.Random) -> str:
    """A small random document with anchors, aliases (some undefined, some inside their own
    anchor), tags, keys that are collections and repeated keys."""
    names: list[str] = []

    def node(depth: int) -> str:
        anchor = ""
        if rng.random() < 0.3:
            names.append(f"{rng.choice('abcd')}{len(names)}")
            anchor = f"&{names[-1]} "
        r = rng.random()
        if depth > 3 or r < 0.3:
            if names and rng.random() < 0.4:
                return "*" + rng.choice(names)
            return anchor + rng.choice(["1", "x", "'q'", "!!int z", "~", "k", "2.5", "[]", "{}"])
        if r < 0.65:
            return anchor + "[" + ", ".join(node(depth + 1) for _ in range(rng.randint(0, 4))) + "]"
        pairs = []
        for _ in range(rng.randint(0, 4)):
            key = node(depth + 1) if rng.random() < 0.2 else rng.choice("kkmn")
            pairs.append(f"? {key} : {node(depth + 1)}")
        return anchor + "{" + ", ".join(pairs) + "}"

    return f"r: {node(0)}\ns: {node(0)}\n"


@pytest.mark.parametrize("seed", range(2))
def test_random_alias_documents_read_the_same_by_every_reader(seed: int) -> None:
    rng = random.Random(seed)
    outcomes: dict[str, int] = {}
    for _ in range(300):
        kind, *rest = assert_same(_alias_document(rng))
        message = "ok" if kind == "ok" else str(rest[0]).split(": ", 2)[-1][:30]
        outcomes[message] = outcomes.get(message, 0) + 1
    assert outcomes["ok"] > 30 and len(outcomes) >= 5, outcomes


def test_an_alias_is_its_anchors_node() -> None:
    doc = parse_yaml("a: &x {b: [1, {c: 2}]}\nd: [*x, *x]\n")
    assert isinstance(doc.root, YMap)
    d = doc.root.get("d")
    assert isinstance(d, YSeq) and d.items[0] is d.items[1] is doc.root.get("a")
    assert to_python(doc.root)["d"][1] == {"b": [1, {"c": 2}]}
