"""Lint configuration files that cannot be used: bytes that are not UTF-8, values of the wrong
shape; a usage error naming the file."""

from __future__ import annotations

from pathlib import Path

import pytest
from typer.testing import CliRunner

from tests.cli_checks import run_cli
from tests.paths import UR10E_XRDF


def test_non_utf8_pyproject_found_by_discovery(tmp_path: Path) -> None:
    from xrdf_tools.lint.config import ConfigError, discover_config

    (tmp_path / "pyproject.toml").write_bytes(b"[tool.xrdf.lint]\n# \xff\xfe\n")
    with pytest.raises(ConfigError, match="not UTF-8") as e:
        discover_config(tmp_path)
    assert e.value.line == 2


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("1: a\nfoo: b\n", "unknown configuration key '1'"),
        ("rules: [1]\n", "rules must be a mapping, not a list"),
        ("urdf: {'*.xrdf': [1]}\n", r"urdf.\*.xrdf must be a name, not a list"),
        ("options: {x: 1}\n", "1:1: unknown configuration key 'options'"),
        ("target: [curobo]\n", "target must be a name, not a list"),
        ("rules: {curobo-: {level: [1]}}\n", "rules.curobo-.level must be a level"),
    ],
)
def test_lint_config_shape_errors(
    runner: CliRunner, tmp_path: Path, text: str, message: str
) -> None:
    from xrdf_tools.lint.config import ConfigError, load_config

    p = tmp_path / ".xrdf-lint.yaml"
    p.write_text(text)
    with pytest.raises(ConfigError, match=message):
        load_config(p)
    code, out = run_cli(runner, "lint", "--config", str(p), str(UR10E_XRDF))
    assert code == 2 and f"{p}" in out
