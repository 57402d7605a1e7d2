"""How ``xrdf convert`` ends once the robot is converted: its findings shown, the exit
they call for (errors: nothing written; ``--strict``: a value guessed), then ``--check``'s
comparison with the file or the write."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

from ...diagnostics import Diagnostic, Severity
from ...util.errors import XrdfToolsError
from .plain import EXIT_FINDINGS, OutputFormat, check_robot_overwrite, has_failures
from .typer_common import echo_diagnostics, fail, note, write_output

if TYPE_CHECKING:
    from ...convert.pipeline import ConvertResult
    from ...xrdf.model import Xrdf

__all__ = ["check_against", "report_findings", "write_result"]


def report_findings(
    result: ConvertResult, fmt: OutputFormat, fit_spheres: bool, strict: bool
) -> None:
    """Show the conversion's diagnostics and lint's findings; exit 1 on an error among them
    or, with ``strict``, on any value guessed or dropped."""
    diags, lint_diags = list(result.diagnostics), list(result.lint)
    echo_diagnostics([*diags, *lint_diags], fmt)
    _fail_on_errors(diags, lint_diags, fit_spheres)
    if strict and has_failures(diags, strict=True):
        n = sum(1 for d in diags if d.severity is not Severity.INFO)
        fail(f"--strict: {n} value(s) were guessed or dropped (listed above)", EXIT_FINDINGS)


def write_result(result: ConvertResult, output: Path | None) -> None:
    """Write the XRDF to ``output`` (standard output: None or '-'), unless that would
    overwrite an input of the robot (a xacro file its macros came from, a mesh of a link)."""
    try:
        check_robot_overwrite(output, result.robot)
    except XrdfToolsError as e:
        fail(e)
    write_output(result.text, output)


def check_against(output: Path, x: Xrdf, root_frame: str) -> None:
    """``--check``: exit 1 with the semantic differences when ``output`` is not ``x``."""
    from dataclasses import replace

    from ...diff import diff_xrdf
    from ...xrdf.io import load_xrdf

    if not output.exists():
        fail(f"{output}: does not exist; run without --check to create it", EXIT_FINDINGS)
    try:
        existing = load_xrdf(output)
    except XrdfToolsError as e:
        fail(e, EXIT_FINDINGS)
    result = diff_xrdf(existing, x, root_frame=root_frame)
    # the side converted now has no file: name it by what it is, not '<document>'
    result = replace(result, b=replace(result.b, path="(converted from the sources now)"))
    if result.is_equal:
        note(f"{output}: up to date")
        return
    write_output(_render_diff(result), None)
    fail(
        f"{output}: out of date ({len(result.changes)} semantic difference(s) listed above); "
        "re-run without --check to write it anew, which replaces any edit made to the file "
        "by hand: keep such edits in the sources or the convert options instead",
        EXIT_FINDINGS,
    )


def _at_unwritten_lines(errors: list[Diagnostic]) -> str:
    """What the lines of findings in the converted XRDF mean when it is not written (to its
    file or to stdout): the file named there does not exist, or holds something else."""
    if not any(d.line is not None for d in errors):
        return ""
    return "; nothing was written: their lines are those of the XRDF convert would write"


def _render_diff(result: Any) -> str:
    from ...diff.render import render_text

    return render_text(result)


def _fail_on_errors(
    diags: list[Diagnostic], lint_diags: list[Diagnostic], fit_spheres: bool
) -> None:
    """Exit 1 when the conversion or the lint of its result has an error (nothing written)."""
    from ...convert.targets import RULE_STOPPED

    if any(d.rule == "convert-no-spheres" and d.severity is Severity.ERROR for d in diags):
        fail(
            "--fit-spheres fitted no sphere: no link has collision geometry it could read "
            "(listed above); make the meshes reachable (--package-path) or fit the visual "
            "meshes (--from visual)",
            EXIT_FINDINGS,
        )
    unfitted = [d for d in diags if d.severity is Severity.ERROR]
    if unfitted:
        fail(
            f"{len(unfitted)} link(s) with geometry got no spheres or only some (listed "
            "above); a planner would not see what is missing. Fix or replace those meshes",
            EXIT_FINDINGS,
        )
    # the stop before fitting says that these errors were found: it is not one of them
    errors = [d for d in lint_diags if d.severity is Severity.ERROR and d.rule != RULE_STOPPED]
    if errors:
        bare = sum(1 for d in errors if d.rule == "mesh-without-spheres")
        remedy = "fix what each one names, in the inputs or with a value on the command line"
        if bare and not fit_spheres:
            remedy = (
                f"{bare} of them are moving links with collision geometry and no spheres "
                "(--fit-spheres fits spheres to the links the inputs leave without); " + remedy
            )
        if not fit_spheres and any(d.rule == "empty-collision-group" for d in errors):
            # (a fit that fitted nothing stopped above, as convert-no-spheres)
            remedy = (
                "the XRDF has no collision spheres at all: --fit-spheres fits them to the "
                "links' collision geometry; " + remedy
            )
        if any(d.rule == "convert-empty-cspace" for d in diags):
            remedy = (
                "the c-space is empty: choose its joints with --joints, --chain or --srdf; "
                + (remedy)
            )
        fail(
            f"the converted XRDF has {len(errors)} lint error(s) against the URDF (listed "
            f"above{_at_unwritten_lines(errors)}); {remedy}",
            EXIT_FINDINGS,
        )
