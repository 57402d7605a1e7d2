"""Fixtures shared by every test module."""

from __future__ import annotations

import pytest
from typer.testing import CliRunner


@pytest.fixture(scope="session")
def runner() -> CliRunner:
    """The in-process runner of the ``xrdf`` CLI (``runner.invoke(app, [...])``): standard
    output and standard error kept apart (``result.stdout``, ``result.stderr``)."""
    return CliRunner()
