from __future__ import annotations

import math
from pathlib import Path

import pytest

from xrdf_tools.util.errors import SchemaError, YamlError
from xrdf_tools.xrdf.io import parse_xrdf
from xrdf_tools.yaml.io import YMap, YScalar, YSeq, load_yaml, parse_yaml, write_atomic

MINIMAL = """format: xrdf
format_version: 2.0
cspace:
  joint_names: [{name}]
  acceleration_limits: [1.0]
  jerk_limits: [10.0]
"""


def test_positions_are_one_based_for_every_node() -> None:
    doc = parse_yaml("a:\n  b: [1, 2]\n  c:\n    - x: 1\n")
    root = doc.root
    assert isinstance(root, YMap)
    a = root.get("a")
    assert isinstance(a, YMap) and (a.line, a.col) == (2, 3)
    b = a.get("b")
    assert isinstance(b, YSeq) and (b.line, b.col) == (2, 6)
    assert (b.items[1].line, b.items[1].col) == (2, 10)
    c = a.get("c")
    assert isinstance(c, YSeq)
    item = c.items[0]
    assert isinstance(item, YMap) and (item.line, item.col) == (4, 7)


@pytest.mark.parametrize("word", ["on", "off", "yes", "no", "y", "n", "Yes", "OFF", "Y"])
def test_yaml11_boolean_words_stay_strings(word: str) -> None:
    doc = parse_yaml(f"{word}: {word}\nlist: [{word}]\n")
    assert doc.root is not None
    assert doc.root.to_python() == {word: word, "list": [word]}  # type: ignore[attr-defined]


def test_yaml11_boolean_joint_name_loads_as_string_joint() -> None:
    x = parse_xrdf(MINIMAL.format(name="on") + "default_joint_positions:\n  on: 0.5\n")
    assert x.cspace is not None and x.cspace.joint_names == ("on",)
    assert x.default_joint_positions == {"on": 0.5}


def test_yaml12_scalars() -> None:
    doc = parse_yaml("a: 1e3\nb: true\nc: ~\nd: .inf\ne: 0o17\nf: '1'\ng: -.5\n")
    assert doc.root is not None
    data = doc.root.to_python()  # type: ignore[attr-defined]
    assert data["a"] == 1000.0 and isinstance(data["a"], float)
    assert data["b"] is True and data["c"] is None and data["d"] == math.inf
    assert data["e"] == 15 and data["f"] == "1" and data["g"] == -0.5


def test_duplicate_key_error_names_both_lines(tmp_path: Path) -> None:
    p = tmp_path / "dup.xrdf"
    p.write_text("format: xrdf\nformat_version: 2.0\ncspace: {}\nformat_version: 1.0\n")
    with pytest.raises(YamlError) as info:
        load_yaml(p)
    err = info.value
    assert (err.line, err.col) == (4, 1)
    assert "duplicate key 'format_version'" in str(err)
    assert "line 2" in str(err) and "line 4" in str(err)
    assert str(err).startswith(f"{p}:4:1:")


def test_duplicate_nested_key_is_recorded_with_key_path() -> None:
    doc = parse_yaml("geometry:\n  g:\n    spheres:\n      l1: []\n      l1: []\n")
    assert len(doc.duplicates) == 1
    d = doc.duplicates[0]
    assert (d.key, d.first_line, d.line, d.col) == ("l1", 4, 5, 7)
    assert d.key_path == "geometry.g.spheres.l1"


def test_syntax_error_has_position() -> None:
    with pytest.raises(YamlError) as info:
        parse_yaml("a: [1, 2\nb: 3\n", "f.xrdf")
    assert info.value.line == 2 and info.value.col is not None
    assert str(info.value).startswith("f.xrdf:2:")
    assert "syntax error" in str(info.value)


def test_non_mapping_root_is_one_clear_error() -> None:
    with pytest.raises(SchemaError) as info:
        parse_xrdf("- format: xrdf\n- format_version: 2.0\n", "list.xrdf")
    assert (
        str(info.value) == "list.xrdf:1:1: the top level of an XRDF must be a mapping, not a list"
    )


def test_wrong_type_center_scalar_points_at_value() -> None:
    text = MINIMAL.format(name="j") + (
        "geometry:\n  g:\n    spheres:\n      l:\n        - center: 0.1\n          radius: 0.1\n"
    )
    with pytest.raises(SchemaError) as info:
        parse_xrdf(text, "t.xrdf")
    assert (info.value.line, info.value.col) == (11, 19)
    assert "center must be a list, not the number 0.1" in str(info.value)


def test_scalar_node_flags_quoting() -> None:
    doc = parse_yaml("a: '2.0'\nb: 2.0\n")
    assert isinstance(doc.root, YMap)
    a, b = doc.root.get("a"), doc.root.get("b")
    assert isinstance(a, YScalar) and a.quoted and a.value == "2.0"
    assert isinstance(b, YScalar) and not b.quoted and b.value == 2.0


def test_missing_file_is_one_line_error(tmp_path: Path) -> None:
    with pytest.raises(YamlError, match="file not found"):
        load_yaml(tmp_path / "nope.xrdf")


def test_write_atomic_replaces_and_keeps_no_temp(tmp_path: Path) -> None:
    p = tmp_path / "out.xrdf"
    p.write_text("old")
    write_atomic(p, "new\n")
    assert p.read_text() == "new\n"
    assert [f.name for f in tmp_path.iterdir()] == ["out.xrdf"]


def test_the_characters_refused_are_those_pyyaml_refuses() -> None:
    """``_NON_PRINTABLE`` matches exactly what PyYAML's ``Reader.NON_PRINTABLE`` matches (the
    characters a YAML stream may not hold), though written as the short list of them, which
    compiles far faster than PyYAML's negated class of the allowed ones."""
    import yaml

    from xrdf_tools.yaml.io import _NON_PRINTABLE

    every = "".join(map(chr, range(0x110000)))
    assert _NON_PRINTABLE.findall(every) == yaml.reader.Reader.NON_PRINTABLE.findall(every)
