"""Locations of test inputs: bundled fixtures, the optional shared/ reference tree."""

from __future__ import annotations

from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parent.parent
FIXTURES = REPO / "fixtures"
#: Expected outputs the tests compare with (output pins, diff goldens).
TEST_DATA = REPO / "tests" / "data"
SHARED = REPO.parent / "shared"
SEED_XRDF = FIXTURES / "seed" / "ur10e_seed.xrdf"
UR10E_URDF = FIXTURES / "ur10e" / "ur10e.urdf"
UR10E_XRDF = FIXTURES / "ur10e" / "ur10e.xrdf"


def shared_file(*parts: str) -> Path:
    """A file under ../shared, or skip the test when shared/ is not beside the checkout."""
    p = SHARED.joinpath(*parts)
    if not p.exists():
        pytest.skip(f"{p} not available")
    return p


def shared_xrdfs() -> list[Path]:
    return sorted(SHARED.rglob("*.xrdf")) if SHARED.exists() else []


def shared_xrdf_params() -> list[object]:
    """``shared_xrdfs()`` as parameters; one skipped case when shared/ is absent (a
    parametrised test that collects nothing fails: ``empty_parameter_set_mark``)."""
    found = shared_xrdfs()
    if found:
        return [pytest.param(p, id=p.name) for p in found]
    return [pytest.param(None, id="shared", marks=pytest.mark.skip(reason=f"{SHARED} absent"))]
