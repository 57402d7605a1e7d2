"""The one XRDF shape description: the strict reader and lint agree with it, and the JSON Schema
generated from it (docs/xrdf.schema.json) is up to date and agrees with lint on the fixtures."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest
import yaml

from tests.paths import FIXTURES, REPO
from xrdf_tools.lint import lint_text
from xrdf_tools.util.errors import XrdfToolsError
from xrdf_tools.xrdf.io import TOP_LEVEL_ORDER, parse_xrdf
from xrdf_tools.xrdf.schema import json_schema, render
from xrdf_tools.xrdf.shape import DOCUMENT, GROUP, MODIFIERS, SPHERE, exists_in

SCHEMA = REPO / "docs" / "xrdf.schema.json"
#: Lint rules whose findings are departures from the shape.
SHAPE_RULES = {
    "wrong-type",
    "unknown-key",
    "required-key",
    "version-key",
    "format-key",
    "format-version",
    "sphere-center",
}


def test_schema_file_is_up_to_date() -> None:
    assert SCHEMA.read_text() == render(), (
        "docs/xrdf.schema.json is stale: run python -m xrdf_tools.xrdf.schema > "
        "docs/xrdf.schema.json"
    )


def test_writer_order_is_the_shape_order() -> None:
    assert tuple(DOCUMENT.fields) == TOP_LEVEL_ORDER


def test_version_keys() -> None:
    assert exists_in(DOCUMENT, "collision", "1.0")
    assert not exists_in(DOCUMENT, "collision", "2.0")
    assert exists_in(DOCUMENT, "world_collision", "2.0")
    assert not exists_in(GROUP, "clone", "1.0")
    assert MODIFIERS["remove_mimic_attributes"].versions == ("2.0",)


@pytest.mark.parametrize("key", SPHERE.required)
def test_reader_requires_what_the_shape_requires(key: str) -> None:
    text = (
        "format: xrdf\nformat_version: 2.0\ngeometry:\n  g:\n    spheres:\n      base:\n"
        "        - center: [0.0, 0.0, 0.0]\n          radius: 0.1\n"
    )
    lines = [ln for ln in text.splitlines() if not ln.strip(" -").startswith(key + ":")]
    if key == "center":
        lines = [ln.replace("          radius", "        - radius") for ln in lines]
    with pytest.raises(XrdfToolsError, match=f"missing required key '{key}'"):
        parse_xrdf("\n".join(lines) + "\n")


def _shape_clean(path: Path) -> bool:
    """Whether lint finds no departure from the shape (errors or warnings) in ``path``."""
    text = path.read_text()
    found = lint_text(text, str(path))
    return not any(d.rule in SHAPE_RULES and d.severity.value != "info" for d in found)


def _xrdf_files() -> list[Path]:
    """The fixtures, but those of ``reader-number``: PyYAML (which reads them here, as YAML
    1.1) reads their numbers differently, which is what that rule is about."""
    return sorted(
        p
        for p in FIXTURES.rglob("*.xrdf")
        if "fuzz" not in p.parts and "reader-number" not in p.parts
    )


def test_schema_agrees_with_lint_on_the_fixtures() -> None:
    """Files lint finds shape-clean validate; files with a shape error do not."""
    jsonschema = pytest.importorskip("jsonschema")
    validator = jsonschema.Draft202012Validator(json_schema())
    clean = failing = 0
    for path in _xrdf_files():
        try:
            data: Any = yaml.safe_load(path.read_text())
        except yaml.YAMLError:
            continue
        valid = validator.is_valid(data)
        if _shape_clean(path):
            assert valid, (path, next(iter(validator.iter_errors(data))).message)
            clean += 1
        elif path.parent.name in SHAPE_RULES and path.name.startswith("fail"):
            assert not valid, path
            failing += 1
    assert clean > 40 and failing > 5, (clean, failing)


def test_schema_is_valid_json_schema() -> None:
    jsonschema = pytest.importorskip("jsonschema")
    jsonschema.Draft202012Validator.check_schema(json.loads(SCHEMA.read_text()))
