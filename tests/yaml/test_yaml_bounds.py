"""The YAML reader's bounds on hostile input: control characters, alias bombs, nesting depth,
collections as keys, values that would break the one-line message."""

from __future__ import annotations

import time
from pathlib import Path

import pytest
from typer.testing import CliRunner

from tests.cli_checks import run_cli, yaml_laughs
from tests.paths import UR10E_URDF, UR10E_XRDF
from xrdf_tools.util.errors import SchemaError, YamlError
from xrdf_tools.yaml.io import parse_yaml, to_python


@pytest.mark.parametrize(("char", "col"), [("\x01", 5), ("\uffff", 5), ("\x1b", 5), ("\ufffe", 5)])
def test_control_characters_are_errors_with_a_position(char: str, col: int) -> None:
    with pytest.raises(YamlError, match=f"U\\+{ord(char):04X} is not allowed") as e:
        parse_yaml(f"a: 1\nb: a{char}b\n", "x.yaml")
    assert str(e.value).startswith(f"x.yaml:2:{col}: ")


def test_control_character_in_cli_input_is_one_line(runner: CliRunner, tmp_path: Path) -> None:
    p = tmp_path / "robot.xrdf"
    p.write_text('format: xrdf\nformat_version: 2.0\nx: "a\x01b"\n')
    for args in (["lint", str(p)], ["diff", str(p), str(UR10E_XRDF)]):
        code, out = run_cli(runner, *args)
        assert f"{p}:3:" in out and "U+0001" in out and code in (1, 2)


def test_billion_laughs_fails_fast() -> None:
    text = yaml_laughs()
    assert len(text) < 1024
    start = time.monotonic()
    with pytest.raises(YamlError, match="aliases expand this document beyond"):
        parse_yaml(text, "bomb.yaml")
    assert time.monotonic() - start < 2


@pytest.mark.parametrize("command", ["lint", "diff", "convert"])
def test_billion_laughs_through_the_cli(runner: CliRunner, tmp_path: Path, command: str) -> None:
    bomb = tmp_path / "bomb.yml"
    bomb.write_text(yaml_laughs())
    args = {
        "lint": ["lint", str(bomb)],
        "diff": ["diff", str(bomb), str(UR10E_XRDF)],
        "convert": ["convert", str(UR10E_URDF), "--curobo", str(bomb)],
    }[command]
    start = time.monotonic()
    code, out = run_cli(runner, *args)
    assert code in (1, 2) and "aliases expand" in out
    assert time.monotonic() - start < 10


def test_a_few_aliases_still_work() -> None:
    doc = parse_yaml("base: &b {radius: 0.1}\nothers: [*b, *b, *b]\n")
    assert to_python(doc.root)["others"][2] == {"radius": 0.1}


def test_too_many_aliases() -> None:
    text = "a: &a 1\nb: [" + ", ".join(["*a"] * 10_001) + "]\n"
    with pytest.raises(YamlError, match="more than 10000 aliases"):
        parse_yaml(text)


def test_recursive_alias_is_an_error() -> None:
    with pytest.raises(YamlError, match="refers to a node that contains it"):
        parse_yaml("a: &a [1, *a]\n")


@pytest.mark.parametrize(
    "text",
    [
        "x: " + "[" * 1000 + "]" * 1000 + "\n",
        "x: " + "{a: " * 1000 + "1" + "}" * 1000 + "\n",
        "".join("  " * i + f"k{i}:\n" for i in range(1000)),
        "a: &a " + "[" * 60 + "]" * 60 + "\nb: " + "[" * 60 + "*a" + "]" * 60 + "\n",
    ],
)
def test_deep_nesting_is_an_error_not_a_recursion_error(text: str) -> None:
    with pytest.raises(YamlError, match="nesting deeper than 100 levels"):
        parse_yaml(text, "deep.yaml")


def test_deep_nesting_through_lint_is_a_finding(runner: CliRunner, tmp_path: Path) -> None:
    p = tmp_path / "deep.xrdf"
    p.write_text("x: " + "[" * 1000 + "]" * 1000 + "\n")
    code, out = run_cli(runner, "lint", str(p))
    assert code == 1 and "yaml-syntax" in out and "nesting deeper" in out


@pytest.mark.parametrize(
    ("text", "kind"), [("? {a: 1}\n: 2\n", "mapping"), ("? [1]\n: 2\n", "list")]
)
def test_a_collection_as_a_mapping_key_is_an_error(text: str, kind: str) -> None:
    with pytest.raises(YamlError, match=f"a {kind} is used as a mapping key") as e:
        parse_yaml(text, "k.yaml")
    assert e.value.line == 1


def test_values_with_newlines_are_not_echoed_raw(tmp_path: Path) -> None:
    p = tmp_path / "robot.xrdf"
    p.write_text(UR10E_XRDF.read_text().replace("tool_frames: [tool0]", 'tool_frames: "a\\nb"'))
    from xrdf_tools.xrdf.io import load_xrdf

    with pytest.raises(SchemaError) as e:
        load_xrdf(p)
    assert "\n" not in str(e.value) and "a\\nb" in str(e.value)
