"""``xrdf report``: self-collision report over sampled (or given) configurations.

Exit codes: 0 no finding; 1 a finding of severity error (an unmasked pair always colliding or
colliding at the default pose, a given configuration in collision) or, with ``--strict``, a
warning (mask hides collisions, unknown mask frame); 2 usage or input error.
"""

from __future__ import annotations

import sys
from enum import Enum
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from ..errors import XrdfToolsError
from .common import (
    EXIT_FINDINGS,
    PackagePathOption,
    XacroArgOption,
    fail,
    has_failures,
    load_robot_option,
    refuse_input_overwrite,
    refuse_output_clash,
)

if TYPE_CHECKING:
    from ..report import ProgressFn


class ReportFormat(str, Enum):
    text = "text"
    json = "json"
    markdown = "markdown"
    html = "html"


class MaskPolicy(str, Enum):
    proven = "proven"
    sampled = "sampled"


class ReportPart(str, Enum):
    all = "all"
    pairs = "pairs"
    findings = "findings"


class SamplerChoice(str, Enum):
    uniform = "uniform"
    halton = "halton"


def _progress_bar(total_label: str) -> tuple[ProgressFn, object]:
    """A rich progress bar on stderr; returns the callback and the bar (to stop it)."""
    from rich.console import Console
    from rich.progress import BarColumn, Progress, TextColumn, TimeRemainingColumn

    bar = Progress(
        TextColumn(total_label),
        BarColumn(),
        TextColumn("{task.completed:,}/{task.total:,}"),
        TimeRemainingColumn(),
        console=Console(stderr=True),
        transient=True,
    )
    task = None

    def update(done: int, total: int) -> None:
        nonlocal task
        if task is None:
            bar.start()
            task = bar.add_task("", total=total)
        bar.update(task, completed=done)

    return update, bar


def command(
    xrdf_file: Annotated[Path, typer.Argument(help="The XRDF to check.", show_default=False)],
    urdf: Annotated[
        Path, typer.Option("--urdf", help="The robot's URDF (or xacro).", show_default=False)
    ],
    samples: Annotated[
        int, typer.Option("--samples", "-n", min=1, help="Configurations to sample.")
    ] = 100_000,
    seed: Annotated[int, typer.Option("--seed", min=0, help="Random seed of the sampler.")] = 0,
    sampler: Annotated[
        SamplerChoice,
        typer.Option(
            "--sampler",
            help="uniform: independent samples (the 'never' confidence holds); halton: "
            "scrambled low-discrepancy points (better coverage, bound indicative).",
        ),
    ] = SamplerChoice.uniform,
    configs: Annotated[
        Path | None,
        typer.Option(
            "--configs",
            help="Check these configurations instead of sampling: .npy or .csv, one joint "
            "vector per row in c-space order (a CSV header of joint names is matched by name).",
        ),
    ] = None,
    output_format: Annotated[
        ReportFormat, typer.Option("--format", "-f", help="Output format.")
    ] = ReportFormat.text,
    output: Annotated[
        Path | None, typer.Option("--output", "-o", help="Write the report here (atomically).")
    ] = None,
    plot: Annotated[
        Path | None, typer.Option("--plot", help="Write a collision-matrix heatmap PNG.")
    ] = None,
    write_mask: Annotated[
        Path | None,
        typer.Option("--write-mask", help="Write the XRDF with the recommended ignore list."),
    ] = None,
    clearance_margin: Annotated[
        float,
        typer.Option(
            "--clearance-margin",
            min=0.0,
            help="Minimum clearances below this (metres) are exact; above, lower bounds.",
        ),
    ] = 0.01,
    coverage: Annotated[
        bool, typer.Option("--coverage", help="Add sphere coverage metrics (reads meshes).")
    ] = False,
    jobs: Annotated[
        int | None,
        typer.Option(
            "--jobs",
            "-j",
            min=1,
            help="Worker processes for sampling [default: all cores]. Same result for any "
            "value; samples below 1,000,000 per worker run in fewer processes.",
            show_default=False,
        ),
    ] = None,
    certify: Annotated[
        bool,
        typer.Option(
            "--certify",
            help="Decide every pair that sampling calls 'never' over its whole joint box: a "
            "proof, or a colliding witness configuration (then 'sometimes').",
        ),
    ] = False,
    certify_budget: Annotated[
        float,
        typer.Option(
            "--certify-budget", min=0.0, help="Seconds for --certify in all; then 'undecided'."
        ),
    ] = 60.0,
    mask_policy: Annotated[
        MaskPolicy,
        typer.Option(
            "--mask-policy",
            help="proven: ignore a never-colliding pair only when --certify proved it "
            "(implies --certify); sampled: also when sampling never saw it collide.",
        ),
    ] = MaskPolicy.sampled,
    moveit: Annotated[
        bool,
        typer.Option(
            "--moveit",
            help="Judge the default pose as MoveIt's Setup Assistant does (each joint at 0 when "
            "within its limits, else mid-range) instead of the XRDF's defaults, to compare with "
            "an SRDF's disable_collisions like with like.",
        ),
    ] = False,
    only: Annotated[
        ReportPart,
        typer.Option("--only", help="Text/Markdown/HTML: show only the pair table or findings."),
    ] = ReportPart.all,
    min_rate: Annotated[
        float,
        typer.Option(
            "--min-rate",
            min=0.0,
            max=1.0,
            help="Text/Markdown/HTML: list only pairs colliding in at least this fraction of "
            "configurations (e.g. 0.001); JSON keeps every pair.",
        ),
    ] = 0.0,
    strict: Annotated[bool, typer.Option("--strict", help="Warnings also exit 1.")] = False,
    xacro_arg: XacroArgOption = None,
    package_path: PackagePathOption = None,
) -> None:
    """Sample the c-space and report, per frame pair, how often it self-collides, how the
    ignore mask treats it and what to do about it."""
    from ..engine import default_jobs
    from ..report import CertifyOptions, recommended_xrdf, self_collision_report
    from ..report_render import (
        ReportView,
        render_html,
        render_json,
        render_markdown,
        render_text,
        write_heatmap,
    )
    from ..xrdf_io import dump_xrdf, load_xrdf
    from ..yaml_io import write_atomic

    inputs = [xrdf_file, urdf, configs]
    refuse_output_clash({"--output": output, "--plot": plot, "--write-mask": write_mask})
    for out_path in (output, plot, write_mask):
        if out_path is not None:
            refuse_input_overwrite(out_path, inputs)
    try:
        x = load_xrdf(xrdf_file)
        u = load_robot_option(urdf, xacro_arg, package_path)
        q_c = None
        if configs is not None:
            from ..configs import load_cspace_configurations
            from ..kinematics import build_kinematic_model

            kin, _ = build_kinematic_model(u, x, path=str(urdf))
            q_c = load_cspace_configurations(configs, kin, x)
        interactive = (
            output_format is not ReportFormat.json
            and sys.stderr.isatty()
            and (output is not None or sys.stdout.isatty())
        )
        progress = None
        bar = None
        if interactive:
            progress, bar = _progress_bar("sampling" if configs is None else "checking")
        try:
            report = self_collision_report(
                u,
                x,
                samples=samples,
                seed=seed,
                sampler=sampler.value,
                configs=q_c,
                progress=progress,
                urdf_path=str(urdf),
                coverage=coverage,
                clearance_margin=clearance_margin,
                jobs=default_jobs() if jobs is None else jobs,
                certify=(
                    CertifyOptions(certify_budget, mask_policy.value)
                    if certify or mask_policy is MaskPolicy.proven
                    else None
                ),
                moveit=moveit,
            )
        finally:
            if bar is not None:
                bar.stop()  # type: ignore[attr-defined]
        view = ReportView(only.value, min_rate)
        if output_format is ReportFormat.json:
            text = render_json(report)
        else:
            renderer = {
                ReportFormat.text: render_text,
                ReportFormat.markdown: render_markdown,
                ReportFormat.html: render_html,
            }[output_format]
            text = renderer(report, view)
        if write_mask is not None:
            new = recommended_xrdf(x, report)
            write_atomic(write_mask, dump_xrdf(new))
        if plot is not None:
            write_heatmap(report, plot)
    except XrdfToolsError as exc:
        fail(exc)
    except OSError as exc:
        fail(f"{exc.filename or ''}: {exc.strerror or exc}")
    if output is not None:
        try:
            write_atomic(output, text)
        except OSError as exc:
            fail(f"{output}: cannot write: {exc.strerror or exc}")
    else:
        typer.echo(text, nl=False)
    if output_format is not ReportFormat.json:
        notes = []
        if output is not None:
            notes.append(f"report written to {output}")
        if plot is not None:
            notes.append(f"heatmap written to {plot}")
        if write_mask is not None:
            ch = report.mask_change
            notes.append(
                f"XRDF with the recommended ignore list written to {write_mask} "
                f"({len(ch.added)} pair(s) added, {len(ch.removed)} removed, "
                f"{len(ch.dropped_unknown)} unknown frame(s) dropped)"
            )
        for n in notes:
            typer.echo(n, err=True)
    if has_failures(report.diagnostics, strict=strict):
        raise typer.Exit(EXIT_FINDINGS)
