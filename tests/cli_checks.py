"""Helpers of the bad-input tests: run ``xrdf`` in process and fail on a traceback, copy an
input with one edit, hostile YAML."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from typer.testing import CliRunner

from tests.paths import FIXTURES
from xrdf_tools.cli import app
from xrdf_tools.util.errors import XrdfToolsError

posix_only = pytest.mark.skipif(os.name != "posix", reason="FIFOs and /dev/zero are POSIX")
MIMIC_URDF = FIXTURES / "urdf" / "three_link_mimic.urdf"
MIMIC_XRDF = FIXTURES / "fuzz" / "three_link_mimic.xrdf"
CUROBO_CLASSIC = FIXTURES / "curobo_classic" / "ur10e_classic.yml"


def run_cli(runner: CliRunner, *args: str) -> tuple[int, str]:
    """Exit code and output of ``xrdf ARGS``; fails on a traceback."""
    res = runner.invoke(app, list(args))
    exc = res.exception
    if exc is not None and not isinstance(exc, SystemExit):
        if isinstance(exc, XrdfToolsError):  # cli.main prints these, exit 2
            return 2, res.output + f"error: {exc}\n"
        raise AssertionError(f"traceback: {exc!r}\n{res.output}") from exc
    assert "Traceback" not in res.output
    return res.exit_code, res.output


def copy_replacing(src: Path, dest: Path, old: str, new: str) -> Path:
    """``src`` written to ``dest`` with the first ``old`` replaced by ``new`` (which must occur)."""
    text = src.read_text(encoding="utf-8")
    assert old in text, old
    dest.write_text(text.replace(old, new, 1), encoding="utf-8")
    return dest


def yaml_laughs(levels: int = 9) -> str:
    """A YAML "billion laughs": under 1 KB, 10**levels nodes once its aliases are expanded."""
    lines = ["a0: &a0 [x, x, x, x, x, x, x, x, x, x]"]
    lines += [f"a{i}: &a{i} [{', '.join([f'*a{i - 1}'] * 10)}]" for i in range(1, levels)]
    return "\n".join(lines) + "\n"
