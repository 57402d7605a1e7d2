"""The YAML reader agrees with the reference: the one-pass builder on libyaml's events, the same
builder on PyYAML's events, and PyYAML's composer with a plain conversion give the same tree
(values, positions, quoting, duplicate keys) or the same one-line error.

``parse_yaml`` reads with the one-pass builder of ``xrdf_tools.yaml.build`` (libyaml's events
when PyYAML has it, else PyYAML's; aliases included). Each test reads its inputs three ways:
``libyaml`` (skipped when PyYAML has no libyaml), ``pyyaml`` (libyaml turned off: the
fallback) and ``reference`` (``tests/yaml_reference.py``: PyYAML's composer and a per-node
conversion, the reader before the one-pass builder).
"""

from __future__ import annotations

import contextlib
import math
import pickle
import random
from array import array
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
import yaml

from tests.fuzzing import _YAML_SNIPPETS, SEEDS, _mutate_text
from tests.paths import UR10E_XRDF
from tests.yaml_reference import compose_document
from xrdf_tools.util.errors import XrdfToolsError, YamlError
from xrdf_tools.xrdf.io import load_xrdf, parse_xrdf
from xrdf_tools.yaml import build as yaml_build
from xrdf_tools.yaml import io as yaml_io
from xrdf_tools.yaml.io import YMap, YScalar, YSeq, load_yaml, parse_yaml, to_python
from xrdf_tools.yaml.positions import NodePositions, node_positions, positions_of
from xrdf_tools.yaml.rules import Resolver12, plain_value, scalar_value
from xrdf_tools.yaml.tree import YNode, YPlainSeq, new_plain_seq, pack_position

MODES = ("libyaml", "pyyaml", "reference")
needs_libyaml = pytest.mark.skipif(not yaml_build.HAVE_LIBYAML, reason="PyYAML without libyaml")


def _to_reference(source: str | bytes, path: str, **_: Any) -> Any:
    return compose_document(source if isinstance(source, str) else source.decode("utf-8"), path)


@contextlib.contextmanager
def reading(mode: str) -> Iterator[None]:
    """Make ``parse_yaml`` read the way ``mode`` says."""
    saved = yaml_build.HAVE_LIBYAML, yaml_io.read_document
    try:
        if mode == "libyaml" and not yaml_build.HAVE_LIBYAML:
            pytest.skip("PyYAML without libyaml")
        yaml_build.HAVE_LIBYAML = mode == "libyaml"
        if mode == "reference":
            yaml_io.read_document = _to_reference  # type: ignore[assignment]
        yield
    finally:
        yaml_build.HAVE_LIBYAML, yaml_io.read_document = saved


def dump(node: YNode | None) -> Any:
    """Everything a node holds, for comparison (NaN compared by its text)."""
    if node is None:
        return None
    if isinstance(node, YScalar):
        v = node.value
        shown = hex(v) if type(v) is int else repr(v)  # repr: ints of at most 4300 digits
        return ("scalar", node.line, node.col, type(v).__name__, shown, node.quoted)
    if isinstance(node, YSeq):
        return ("seq", node.line, node.col, node.flow, [dump(i) for i in node.items])
    assert isinstance(node, YMap)
    return ("map", node.line, node.col, node.flow, [(dump(k), dump(v)) for k, v in node.pairs])


def outcome(text: str, mode: str) -> Any:
    with reading(mode):
        try:
            doc = parse_yaml(text, "f.yaml")
        except YamlError as e:
            return ("error", str(e))
    return ("ok", dump(doc.root), doc.duplicates)


def assert_same(text: str) -> Any:
    """The outcome of ``text``, the same for every available reader."""
    ref = outcome(text, "reference")
    assert outcome(text, "pyyaml") == ref, text
    if yaml_build.HAVE_LIBYAML:
        assert outcome(text, "libyaml") == ref, text
    return ref


# Where libyaml and PyYAML's scanner read differently, and the bounds: every reader must give
# the reference answer (libyaml is skipped for the first group, whatever it would say).
EDGE_CASES = [
    "a:\tb\n",  # tab between tokens: PyYAML refuses it
    "a: [1,\t2]\n",
    "a: 1\t# c\n",
    "\ufeffa: 1\n",  # byte-order mark at the start (skipped by both)
    "a: x\ufeffy\nb: [1, 2]\n",  # ... and later: libyaml skips it, PyYAML keeps it
    "a: [x?y, z]\n",  # '?' and ':' inside flow plain scalars
    "a: [x:y, z]\n",
    "a: [x:, z]\n",
    "a: {b: , c: 1}\n",  # empty values inside flow collections
    "a: [b: , c]\n",
    "a: [? b : ]\n",
    "a: [!x,y z]\n",  # tags take a following ',' in PyYAML
    "a: !!str 1\nb: !degrees 90\nc: !!int x\n",
    "a: >#c\n  x\n",  # block scalar header with a comment and no space
    "a: |\n  x\n  y\nb: 1\n",
    "? a\n? ",  # no line break at the end: an empty value read at the end
    "a: 1\nb:",
    "a: &x 1\nb: &x 2\n",  # repeated anchor
    "a: &x [1, 2]\nb: *x\nc: *y\n",
    "a: &a [1, *a]\n",
    "%YAML 1.2\n---\na: 1\n",
    "%YAML 1.3\n---\na: 1\n",
    "a: 1\n---\nb: 2\n",
    'a: "\\ud800"\n',
    'a: "\\/\\x41\\u00e9\\U0001F600"\n',
    "a: b\u2028c: d\n",
    "a: 1\x85b: [2, 3]\n",
    "a: 1\rb: [2, 3]\r\n",
    "é: [1, 2]\n😀: {x: [3, 4]}\n",
    "a: b\n  c\n",
    "[a, b]: 1\n",
    "? {a: 1}\n: 2\n",
    "{x: 1, x: 2}: 3\n",
    "a: {x: 1, x: 2}\nb: [{y: 1, y: 2}, 3]\na: 4\n",
    "{1: a, 1.0: b, true: c}\n",
    "{.nan: 1, .nan: 2}\n",
    "{null: 1, ~: 2, '': 3}\n",
    "a.b: 1\na: {b: 2}\n",
    "a: [0x1F, 0o17, 1e3, -.5, .inf, -.Inf, .NaN, 1_000, +1, 99999999999999999999999]\n",
    "a: [true, True, on, yes, y, Null, ~, '', \"1\"]\n",
    "a: [1, '2', [3], {b: 4}, 5]\n",
    "- 1\n- - 2\n  - 3\n- x: 4\n",
    *(f"x: {'[' * n}{']' * n}\n" for n in (99, 100)),  # nesting: the limit is 100 levels
    *(f"x: {'{a: ' * n}1{'}' * n}\n" for n in (99, 100)),
    "a: &a " + "[" * 60 + "]" * 60 + "\nb: " + "[" * 60 + "*a" + "]" * 60 + "\n",
    "a: [" + ", ".join(["*x"] * 3) + "]\n",
    "",
    "# only a comment\n",
    "---\n",
    "a: [1, 2\nb: 3\n",
    "a: 'x\n",
    "k: " + "x" * 1100 + ": 1\n",
    "a: " + "9" * 5000 + "\n",  # more digits than Python converts to an int
    "a: [1, -" + "9" * 5000 + "]\nb: !!int x\n",
    "? " + "9" * 5000 + "\n: 1\n",
    "a: 0x" + "f" * 5000 + "\nb: 1." + "9" * 5000 + "\n",
    *_YAML_SNIPPETS,  # the fuzzer's hostile snippets
]


@pytest.mark.parametrize("text", EDGE_CASES, ids=range(len(EDGE_CASES)))
def test_edge_cases_read_the_same_by_every_reader(text: str) -> None:
    assert_same(text)


@pytest.mark.parametrize("mode", ["libyaml", "pyyaml"])
def test_bytes_read_as_their_text(mode: str) -> None:
    """load_yaml hands the file's bytes to the reader (libyaml reads them as they are)."""
    for text in [*EDGE_CASES, "a: 1\n\u2028", "a: [1]\u0085", "a: x\u2029", "\ufeffa: [1, 2]\n"]:
        with reading(mode):
            try:
                expected = ("ok", dump(parse_yaml(text, "f.yaml").root))
            except YamlError as e:
                expected = ("error", str(e))
            try:
                got = ("ok", dump(parse_yaml(text.encode(), "f.yaml").root))
            except YamlError as e:
                got = ("error", str(e))
        assert got == expected, text


def _corpus(n: int, seed: int) -> Iterator[str]:
    """Mutated windows of the YAML fixtures, ``n`` of them."""
    tokens = [
        "\t",
        ":",
        "-",
        "?",
        "[",
        "]",
        "{",
        "}",
        "#",
        "&a ",
        "*a",
        "!",
        "|",
        ">",
        "'",
        '"',
        ",",
        "\ufeff",
        "\u2028",
        " ",
        "\n",
        "\r",
        "é",
        "---",
        ": ",
        "- ",
        "? ",
        "!!str ",
        "! ",
        "x: 1\n",
        "  x: 2\n",
        "[a:]",
        "{a: }",
        "[a?b]",
        "{x: 1, x: 2}",
        ".nan",
        "0o17",
        "~",
    ]
    texts = [p.read_text() for kind in ("xrdf", "curobo", "limits", "config") for p in SEEDS[kind]]
    rng = random.Random(seed)
    for _ in range(n):
        text = rng.choice(texts)
        if len(text) > 1200:
            start = text.rfind("\n", 0, rng.randrange(len(text) - 800)) + 1
            text = text[start : start + 800]
        for _ in range(rng.randint(1, 4)):
            if rng.random() < 0.3:
                text = _mutate_text(text, "yaml", rng)[0]
            else:
                at = rng.randrange(len(text) + 1)
                text = text[:at] + rng.choice(tokens) + text[at:]
        yield text


@pytest.mark.parametrize("seed", range(4))
def test_mutated_documents_read_the_same_by_every_reader(seed: int) -> None:
    outcomes = {"ok": 0, "error": 0}
    for text in _corpus(150, seed):
        outcomes[assert_same(text)[0]] += 1
    assert min(outcomes.values()) > 10  # both kinds of outcome are exercised


@pytest.mark.parametrize("mode", MODES)
def test_hardening_through_each_reader(mode: str) -> None:
    bomb = "a0: &a0 [x, x, x, x, x, x, x, x, x, x]\n" + "".join(
        f"a{i}: &a{i} [{', '.join([f'*a{i - 1}'] * 10)}]\n" for i in range(1, 9)
    )
    cases = [
        (bomb, "aliases expand this document beyond"),
        ("a: &a 1\nb: [" + ", ".join(["*a"] * 10_001) + "]\n", "more than 10000 aliases"),
        ("x: " + "[" * 1000 + "]" * 1000 + "\n", "x.yaml:1:103: nesting deeper than 100 levels"),
        ("".join("  " * i + f"k{i}:\n" for i in range(200)), "x.yaml:100:199: nesting deeper"),
        ("a: 1\nb: a\x00b\n", "x.yaml:2:5: control character U+0000"),
        ("a: 1\nb: a\uffffb\n", "x.yaml:2:5: character U+FFFF"),
        ("a: 1\nb:\n  c: 1\n  c: 2\n", None),
    ]
    with reading(mode):
        for text, message in cases:
            if message is None:
                doc = parse_yaml(text, "x.yaml")
                assert [(d.key_path, d.line, d.col) for d in doc.duplicates] == [("b.c", 4, 3)]
                continue
            with pytest.raises(YamlError) as e:
                parse_yaml(text, "x.yaml")
            assert message in str(e.value)


@pytest.mark.parametrize("mode", MODES)
def test_files_through_each_reader(mode: str, tmp_path: Path) -> None:
    bad = tmp_path / "bad.xrdf"
    bad.write_bytes(b"format: xrdf\nname: caf\xe9\n")
    dup = tmp_path / "dup.xrdf"
    dup.write_text("format: xrdf\nformat_version: 2.0\ncspace: {}\nformat_version: 1.0\n")
    with reading(mode):
        with pytest.raises(YamlError, match="not UTF-8") as e:
            load_yaml(bad)
        assert (e.value.line, e.value.col) == (2, 10)
        with pytest.raises(YamlError, match="duplicate key 'format_version'") as e:
            load_yaml(dup)
        assert str(e.value).startswith(f"{dup}:4:1:")
        x = load_xrdf(UR10E_XRDF)
        assert x.geometry is not None and x.source.position("geometry") == (53, 3)


@needs_libyaml
def test_a_plain_document_is_read_by_libyaml(monkeypatch: pytest.MonkeyPatch) -> None:
    class Refused(yaml_build.PyParser):
        def __init__(self, stream: str) -> None:
            raise AssertionError("read by PyYAML's parser")

    monkeypatch.setattr(yaml_build, "PyParser", Refused)
    doc = parse_yaml("a: [1, 2.5, x]\nb: {c: 'd'}\n")
    assert to_python(doc.root) == {"a": [1, 2.5, "x"], "b": {"c": "d"}}
    with pytest.raises(AssertionError, match="PyYAML's parser"):
        parse_yaml("a:\t1\n")  # a tab: PyYAML's parser reads it


def test_without_libyaml_pyyaml_reads_everything(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(yaml_build, "CParser", None)
    monkeypatch.setattr(yaml_build, "HAVE_LIBYAML", False)
    doc = parse_yaml("a: [1, 2.5, x]\nb: {c: 'd'}\n")
    assert to_python(doc.root) == {"a": [1, 2.5, "x"], "b": {"c": "d"}}
    with pytest.raises(YamlError, match=r"f.yaml:1:4: YAML syntax error: found character '\\t'"):
        parse_yaml("a: \t1\n", "f.yaml")


def test_lists_of_plain_scalars_are_kept_compactly() -> None:
    doc = parse_yaml("a: [1, 2.5, x, null]\nb:\n  - 3\n  - 'q'\nc: []\n")
    assert isinstance(doc.root, YMap)
    a, b, c = (doc.root.get(k) for k in "abc")
    assert isinstance(a, YPlainSeq) and a.values == (1, 2.5, "x", None)
    assert not isinstance(b, YPlainSeq) and isinstance(b, YSeq)  # a quoted item
    assert isinstance(c, YSeq) and len(c) == 0
    plain = YSeq(
        1,
        4,
        tuple(YScalar(1, col, v) for col, v in ((5, 1), (8, 2.5), (13, "x"), (16, None))),
        True,
    )
    assert a == plain and plain == a and hash(a) == hash(plain)
    assert (a != plain) is False and a != YSeq(1, 4, plain.items[:3], True)
    assert a.items == plain.items and list(a) == list(plain) and len(a) == 4
    assert a.item(2) == YScalar(1, 13, "x") and a.to_python() == [1, 2.5, "x", None]
    assert pickle.loads(pickle.dumps(a)) == plain
    positions = array("Q", [pack_position(70_000, 3), pack_position(70_001, 3)]).tobytes()
    far = new_plain_seq(70_000, 1, (1.0, 2.0), positions, False)
    assert [(i.line, i.col) for i in far.items] == [(70_000, 3), (70_001, 3)]


def test_a_long_list_of_numbers() -> None:
    numbers = [i / 7 for i in range(50_000)]
    text = "format: xrdf\nformat_version: 2.0\ndata: [" + ", ".join(map(repr, numbers)) + "]\n"
    x = parse_xrdf(text, "n.xrdf")
    assert x.extra["data"] == numbers
    block = "data:\n" + "".join(f"  - {n!r}\n" for n in numbers[:1000])
    doc = parse_yaml(block)
    data = doc.root.get("data")  # type: ignore[union-attr]
    assert isinstance(data, YPlainSeq) and data.item(999) == YScalar(1001, 5, numbers[999])


POSITION_TREES = [
    "a:\n  b: [1, {c: 2}]\n  d:\n    - e: 3\n      f: [4, 5]\ng: x\n",
    "- a: 1\n- [2, 3]\n- b:\n    c: 4\n",
    "a: 1\n",
    "7",
    "a.b: 1\na: {b: 2}\n",  # keys that make paths ambiguous: indexed in full
    "1: a\n'1': b\n",
    "a: 1\na: 2\n",
    "a: {x#key: 1, x: 2}\n",
    "'[0]': 1\nb: [2]\n",
    "keys: {" + ", ".join(f"k{i}: [{i}, {i}]" for i in range(40)) + "}\n",
]


@pytest.mark.parametrize("text", POSITION_TREES, ids=range(len(POSITION_TREES)))
def test_positions_on_demand_equal_the_full_index(text: str) -> None:
    doc = parse_yaml(text)
    full = node_positions(doc.root)
    lazy = positions_of(doc)
    probes = [*full, "", ".", "[0]", "a.", "a..b", "a[00]", "a[0]#key", "zz", "a#keys", "[0]x"]
    probes += [p + s for p in list(full) for s in (".x", "[9]", "#key", "]", "[0]")]
    for kp in probes:
        assert (kp in lazy) == (kp in full), kp
        if kp in full:
            assert lazy[kp] == full[kp], kp
    assert dict(lazy) == full and len(lazy) == len(full)
    assert NodePositions(None, True).get("") is None


def test_numbers_in_the_model_are_the_same_through_each_reader() -> None:
    text = UR10E_XRDF.read_text()
    text += "extra_numbers: [1, -2.5e-3, .inf, 0x10]\n"
    models = []
    for mode in MODES:
        with reading(mode):
            models.append(parse_xrdf(text, "u.xrdf"))
    assert models[0] == models[1] == models[2]
    assert models[0].extra["extra_numbers"][2] == math.inf


SPHERES = [
    "{center: [0.1, -2, 3e-1], radius: 0.05}",
    "{radius: 5, center: [0, 0, 0]}",
    "{center: [0, 0, 0], radius: 0.05, color: red}",
    "{center: [0, 0], radius: 0.05}",
    "{center: [0, 0, 0, 0], radius: 0.05}",
    "{center: [0, 0, '0'], radius: 0.05}",
    "{center: [0, 0, true], radius: 0.05}",
    "{center: [0, 0, .nan], radius: 0.05}",
    "{center: [0, 0, 2e6], radius: 0.05}",
    "{center: [0, 0, -1e6], radius: 1000000}",
    "{center: [0, 0, 0], radius: .inf}",
    "{center: [0, 0, 0], radius: '0.1'}",
    "{center: [0, 0, 0], radius: null}",
    "{center: [0, 0, 0], radius: [1]}",
    "{center: [0, 0, [1]], radius: 1}",
    "{center: 1, radius: 1}",
    "{center: [0, 0, 0]}",
    "{center: [0, 0, 0], center: [1, 1, 1]}",
    "[0, 0, 0]",
    "{}",
]


@pytest.mark.parametrize("sphere", SPHERES, ids=range(len(SPHERES)))
def test_spheres_read_the_same_from_compact_lists(sphere: str) -> None:
    """Lists of plain numbers are read from their values (YPlainSeq) by the fast paths of
    the XRDF reader; the reference's YSeq takes the item-by-item checks: the same
    model or message."""
    text = (
        "format: xrdf\nformat_version: 2.0\n"
        "cspace: {joint_names: [j], acceleration_limits: [1], jerk_limits: [2.5]}\n"
        f"geometry:\n  g:\n    spheres:\n      l: [{sphere}, {{center: [1, 2, 3], radius: 4}}]\n"
    )
    results = []
    for mode in MODES:
        with reading(mode):
            try:
                results.append(parse_xrdf(text, "s.xrdf"))
            except XrdfToolsError as e:
                results.append(f"{type(e).__name__}: {e}")
    assert results[0] == results[1] == results[2], results


def test_plain_scalars_resolve_as_the_resolver_and_scalar_value_do() -> None:
    """``plain_value`` (numbers read without the patterns) against PyYAML's resolver with the
    YAML 1.2 table, then ``scalar_value``, on random short texts of number-like characters."""
    resolver = Resolver12()

    def shown(value: object) -> tuple[str, str]:
        return type(value).__name__, hex(value) if type(value) is int else repr(value)

    rng = random.Random(7)
    chars = "0123456789.eE+-" * 3 + "xo_ aINFnNtTrue~"
    texts = ["", "9" * 5000, "-" + "9" * 4301, "9" * 4300, "0x" + "f" * 5000, ".NaN", "Null"]
    texts += ["".join(rng.choice(chars) for _ in range(rng.randint(1, 7))) for _ in range(20_000)]
    for text in texts:
        tag = resolver.resolve(yaml.ScalarNode, text, (True, False))
        try:
            expected = shown(scalar_value(tag, text, "p", 1, 1))
        except YamlError:
            expected = ("error", "")
        try:
            got = shown(plain_value(text))
        except ValueError:
            got = ("error", "")
        assert got == expected, text
