"""A missing extra is one line saying how to install it, also inside a pre-commit hook, whose
environment ``pip install`` cannot reach."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

from xrdf_tools.util.errors import MissingDependencyError
from xrdf_tools.util.extras import extra_requirements, require

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - the tests run on 3.11+ in CI
    tomllib = pytest.importorskip("tomli")

PYPROJECT = Path(__file__).resolve().parents[2] / "pyproject.toml"


def _declared(extra: str) -> list[str]:
    """The extra's requirements as pyproject.toml declares them, included extras expanded."""
    extras = tomllib.loads(PYPROJECT.read_text())["project"]["optional-dependencies"]
    out: list[str] = []
    for spec in extras[extra]:
        if spec.startswith("xrdf-tools["):
            for sub in spec[len("xrdf-tools[") : -1].split(","):
                out += [s for s in _declared(sub) if s not in out]
        elif spec not in out:
            out.append(spec)
    return out


@pytest.mark.parametrize("extra", ["fit", "viz", "all"])
def test_the_requirements_of_an_extra_are_those_pyproject_declares(extra: str) -> None:
    # as packaging writes them: the installed metadata orders a specifier set (<1.2,>=1.1.1)
    from packaging.requirements import Requirement

    def normal(specs: list[str]) -> list[str]:
        return sorted(str(Requirement(s)) for s in specs)

    assert normal(extra_requirements(extra)) == normal(_declared(extra))


def test_in_a_pre_commit_hook_the_hint_names_the_additional_dependencies(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """pre-commit sets PRE_COMMIT=1 for its hooks: the `pip install "xrdf-tools[fit]"` hint
    sent users of an xrdf-convert-check hook with --fit-spheres to a command that cannot
    change the hook's environment."""
    monkeypatch.delenv("PRE_COMMIT", raising=False)
    with pytest.raises(MissingDependencyError) as plain:
        require(["no_such_module_for_xrdf"], "fit", "--fit-spheres")
    assert str(plain.value) == (
        "--fit-spheres needs the 'fit' extra (no_such_module_for_xrdf not installed): "
        'pip install "xrdf-tools[fit]"'
    )
    monkeypatch.setenv("PRE_COMMIT", "1")
    with pytest.raises(MissingDependencyError) as hook:
        require(["no_such_module_for_xrdf"], "fit", "--fit-spheres")
    assert str(hook.value) == (
        "--fit-spheres needs the 'fit' extra (no_such_module_for_xrdf not installed): in a "
        "pre-commit hook, add its packages to the hook's additional_dependencies: "
        f"[{', '.join(_declared('fit'))}]"
    )


def test_the_hook_example_of_the_lint_docs_lists_the_fit_extra() -> None:
    """docs/lint.md's xrdf-convert-check example with --fit-spheres left out pycollada, which
    the fit extra adds for COLLADA meshes: the hook's own hint (above) names it."""
    import re

    from packaging.requirements import Requirement

    docs = PYPROJECT.parent / "docs" / "lint.md"
    (listed,) = re.findall(r"additional_dependencies: \[([^\]]*)\]", docs.read_text())
    assert [p.strip() for p in listed.split(",")] == [Requirement(s).name for s in _declared("fit")]
