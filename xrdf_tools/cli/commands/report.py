"""``xrdf report``: self-collision report over sampled (or given) configurations.

Exit codes: 0 no finding; 1 a finding of severity error (an unmasked pair always colliding or
colliding at the default pose, a given configuration in collision) or, with ``--strict``, a
warning (mask hides collisions, unknown mask frame); 2 usage or input error.
"""

from __future__ import annotations

from collections.abc import Callable
from enum import Enum
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from ...util.errors import XrdfToolsError
from ...util.numbers import MAX_SAMPLES
from .common import (
    PackagePathOption,
    QuietOption,
    VerboseOption,
    XacroArgOption,
    fail,
    load_xrdf_input,
    note,
    one_bar,
    progress_bar,
    progress_wanted,
    refuse_input_overwrite,
    refuse_output_clash,
    write_output,
)
from .core import (
    EXIT_FINDINGS,
    OutputFormat,
    Verbosity,
    detail,
    has_failures,
    is_stdio,
    load_robot_option,
    render_diagnostics,
    timed,
    verbosity,
)

if TYPE_CHECKING:
    from ...report import Report
    from ...report.render import ReportView


class ReportFormat(str, Enum):
    text = "text"
    json = "json"
    markdown = "markdown"
    html = "html"
    github = "github"
    sarif = "sarif"


#: Formats read by programs: no notes on stderr about what was written.
_MACHINE_FORMATS = (ReportFormat.json, ReportFormat.github, ReportFormat.sarif)


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


def command(
    xrdf_file: Annotated[
        Path, typer.Argument(help="The XRDF to check ('-': stdin).", show_default=False)
    ],
    urdf: Annotated[
        Path, typer.Option("--urdf", help="The robot's URDF (or xacro).", show_default=False)
    ],
    samples: Annotated[
        int,
        typer.Option(
            "--samples",
            "-n",
            min=1,
            max=MAX_SAMPLES,
            help="Configurations to sample (at most 10,000,000,000).",
        ),
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
        ReportFormat,
        typer.Option(
            "--format",
            "-f",
            help="Output format: the full report (text, json, markdown, html) or only its "
            "findings as GitHub annotations or a SARIF 2.1.0 log (code scanning).",
        ),
    ] = ReportFormat.text,
    output: Annotated[
        Path | None,
        typer.Option(
            "--output", "-o", help="Write the report here (atomically; '-': stdout, the default)."
        ),
    ] = None,
    plot: Annotated[
        Path | None, typer.Option("--plot", help="Write a collision-matrix heatmap PNG.")
    ] = None,
    write_mask: Annotated[
        Path | None,
        typer.Option(
            "--write-mask",
            help="Write the XRDF with the recommended ignore list ('-': stdout, with -o FILE).",
        ),
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
            help="Worker processes for sampling [default: all cores; more than the cores are "
            "not started]. Same result for any value; samples below 1,000,000 per worker run "
            "in fewer processes.",
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
    quiet: QuietOption = False,
    verbose: VerboseOption = False,
) -> None:
    """Sample the c-space and report, per frame pair, how often it self-collides, how the
    ignore mask treats it and what to do about it."""
    from ...report import CertifyOptions, recommended_xrdf, self_collision_report
    from ...report.render import ReportView, write_heatmap
    from ...xrdf.io import dump_xrdf

    inputs = [xrdf_file, urdf, configs]
    if is_stdio(plot):
        fail("--plot needs a file name (a PNG is not written to stdout)")
    stdout = Path("-")
    refuse_output_clash({"--output": output or stdout, "--plot": plot, "--write-mask": write_mask})
    if is_stdio(output):
        output = None  # '-o -': standard output, as without -o
    for out_path in (output, plot, write_mask):
        if out_path is not None:
            refuse_input_overwrite(out_path, inputs)
    try:
        x = load_xrdf_input(xrdf_file)
        u = load_robot_option(urdf, xacro_arg, package_path)
        q_c = None
        if configs is not None:
            from ...robot.kinematics import build_kinematic_model
            from ...selfcollision.configurations import load_cspace_configurations

            kin, _ = build_kinematic_model(u, x, path=str(urdf))
            q_c = load_cspace_configurations(configs, kin, x)
        n_jobs = _clamped_jobs(jobs)
        label = "sampling" if configs is None else "checking"
        detail(
            f"{label} {samples if q_c is None else len(q_c):,} configuration(s) "
            f"({sampler.value} sampler, seed {seed}, {n_jobs} job(s))"
        )
        with progress_bar() as bar, timed(label):
            report = self_collision_report(
                u,
                x,
                samples=samples,
                seed=seed,
                sampler=sampler.value,
                configs=q_c,
                progress=one_bar(bar, label) or _progress_lines(label),
                urdf_path=str(urdf),
                coverage=coverage,
                clearance_margin=clearance_margin,
                jobs=n_jobs,
                certify=(
                    CertifyOptions(certify_budget, mask_policy.value)
                    if certify or mask_policy is MaskPolicy.proven
                    else None
                ),
                moveit=moveit,
            )
        text = _render(report, output_format, ReportView(only.value, min_rate))
        if write_mask is not None:
            new = recommended_xrdf(x, report)
            write_output(dump_xrdf(new), write_mask)
        if plot is not None:
            write_heatmap(report, plot)
    except XrdfToolsError as exc:
        fail(exc)
    except OSError as exc:
        fail(f"{exc.filename or ''}: {exc.strerror or exc}")
    write_output(text, output)
    if output_format not in _MACHINE_FORMATS:
        for n in _written_notes(report, output, plot, write_mask):
            note(n)
    if has_failures(report.diagnostics, strict=strict):
        raise typer.Exit(EXIT_FINDINGS)


def _clamped_jobs(jobs: int | None) -> int:
    """``--jobs``, or the cores this process may use; more than that is clamped with a note."""
    from ...selfcollision.engine import default_jobs

    cores = default_jobs()
    n_jobs = cores if jobs is None else jobs
    if n_jobs > cores:
        note(f"--jobs {n_jobs}: this process may use {cores} core(s); using that many")
    return min(n_jobs, cores)


def _written_notes(
    report: Report, output: Path | None, plot: Path | None, write_mask: Path | None
) -> list[str]:
    """What was written where (notes on stderr after a human-readable report)."""
    notes = []
    if output is not None:
        notes.append(f"report written to {output}")
    if plot is not None:
        notes.append(f"heatmap written to {plot}")
    if write_mask is not None:
        ch = report.mask_change
        notes.append(
            "XRDF with the recommended ignore list written to "
            f"{'stdout' if is_stdio(write_mask) else write_mask} "
            f"({len(ch.added)} pair(s) added, {len(ch.removed)} removed, "
            f"{len(ch.dropped_unknown)} unknown frame(s) dropped)"
        )
    return notes


def _render(report: Report, fmt: ReportFormat, view: ReportView) -> str:
    """The report in ``fmt``: whole (text, JSON, Markdown, HTML) or its findings through the
    one diagnostics renderer (GitHub annotations, SARIF listing every report rule)."""
    from ...report import RULES
    from ...report.render import RENDERERS

    if fmt in (ReportFormat.github, ReportFormat.sarif):
        return render_diagnostics(
            report.diagnostics, OutputFormat(fmt.value), files=None, rules=RULES
        )
    return RENDERERS[fmt.value](report, view)


def _progress_lines(label: str) -> Callable[[int, int], None] | None:
    """With ``-v`` and no progress bar (stderr not a terminal, e.g. CI): one line per tenth of
    the configurations on stderr (``sampling: 30 % (30,000/100,000), 4.2 s``)."""
    if progress_wanted() or verbosity() < Verbosity.VERBOSE:
        return None
    import time

    start = time.perf_counter()
    printed = [0]

    def line(done: int, total: int) -> None:
        tenth = 10 * done // max(total, 1)
        if tenth > printed[0]:
            printed[0] = tenth
            pct = 100 * done // max(total, 1)
            detail(f"{label}: {pct} % ({done:,}/{total:,}), {time.perf_counter() - start:.1f} s")

    return line
