"""`xrdf lint` — minimal until the lint issue lands: checks that each file loads as an XRDF."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from ..diagnostics import Diagnostic, Severity
from ..errors import XrdfToolsError
from .common import EXIT_FINDINGS, OutputFormat, has_failures, render_diagnostics


def command(
    files: Annotated[list[Path], typer.Argument(help="XRDF files to check.", show_default=False)],
    output_format: Annotated[
        OutputFormat, typer.Option("--format", "-f", help="Output format.")
    ] = OutputFormat.text,
) -> None:
    """Check XRDF files and report problems as path:line:col: severity rule message."""
    from ..xrdf_io import load_xrdf

    diagnostics: list[Diagnostic] = []
    for f in files:
        try:
            load_xrdf(f)
        except XrdfToolsError as exc:
            diagnostics.append(
                Diagnostic(str(f), exc.line, exc.col, "load-error", Severity.ERROR, exc.message)
            )
    text = render_diagnostics(diagnostics, output_format)
    if text:
        typer.echo(text, nl=False)
    if has_failures(diagnostics, strict=False):
        raise typer.Exit(EXIT_FINDINGS)
