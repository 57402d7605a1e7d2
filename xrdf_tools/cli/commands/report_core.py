"""The body of ``xrdf report``, without typer, its options and its fast start-up path.

:func:`run` is what ``xrdf report`` does once its arguments are read; the Typer command
(:mod:`xrdf_tools.cli.commands.report`) and :func:`fast_main` both call it, reading their
options from the one table :data:`REPORT_OPTIONS`. A short report (a CI check of a robot's
mask) must not pay typer's start-up; command lines the fast path does not read exactly as typer
would, ``-v``, and any run that draws a progress bar (a terminal) are left to typer.
"""

from __future__ import annotations

import sys
from collections.abc import Callable, Sequence
from contextlib import AbstractContextManager, nullcontext
from dataclasses import dataclass
from enum import Enum
from pathlib import Path
from typing import TYPE_CHECKING

from ...util.errors import XrdfToolsError, one_line
from ...util.numbers import CERTIFY_BOXES, MAX_SAMPLES, REPORT_SAMPLES
from .options import (
    PACKAGE_PATH,
    QUIET,
    ROBOT_URDF,
    VERBOSE,
    XACRO_ARG,
    Option,
    OptionTable,
    choice,
    configs,
    integer,
    number,
    output,
    parse_command_line,
    path,
    seed,
)
from .plain import (
    EXIT_FINDINGS,
    EXIT_OK,
    EXIT_USAGE,
    OutputFormat,
    ProgressUpdate,
    check_input_overwrite,
    check_output_clash,
    detail,
    echo,
    has_failures,
    is_stdio,
    is_terminal,
    load_robot_option,
    load_xrdf_input,
    note,
    one_bar,
    progress_lines,
    render_diagnostics,
    run_verbosity,
    timed,
    write_result,
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


REPORT_OPTIONS = OptionTable(
    (
        ROBOT_URDF,
        Option(
            "samples",
            ("--samples", "-n"),
            "Configurations to sample (at most 10,000,000,000).",
            integer,
            bounds=(1, MAX_SAMPLES),
        ),
        seed("the sampler"),
        Option(
            "sampler",
            ("--sampler",),
            "uniform: independent samples (the 'never' confidence holds); halton: "
            "scrambled low-discrepancy points (better coverage, bound indicative).",
            choice(SamplerChoice),
        ),
        configs(
            "Check these configurations instead of sampling (exactly, also outside the joint "
            "limits)."
        ),
        Option(
            "output_format",
            ("--format", "-f"),
            "Output format: the full report (text, json, markdown, html) or only its "
            "findings as GitHub annotations or a SARIF 2.1.0 log (code scanning).",
            choice(ReportFormat),
        ),
        output("the report"),
        Option("plot", ("--plot",), "Write a collision-matrix heatmap PNG.", path),
        Option(
            "write_mask",
            ("--write-mask",),
            "Write the XRDF with the recommended ignore list ('-': stdout, with -o FILE).",
            path,
        ),
        Option(
            "clearance_margin",
            ("--clearance-margin",),
            "Minimum clearances below this (metres) are exact; a pair that never comes "
            "closer shows \u2265 it.",
            number,
            bounds=(0.0, None),
        ),
        Option("coverage", ("--coverage",), "Add sphere coverage metrics (reads meshes)."),
        Option(
            "jobs",
            ("--jobs", "-j"),
            "Worker processes for sampling [default: all cores; more than the cores are "
            "not started]. Same result for any value; samples below 1,000,000 per worker run "
            "in fewer processes.",
            integer,
            bounds=(1, None),
            typer_extra={"show_default": False},
        ),
        Option(
            "certify",
            ("--certify",),
            "Decide every pair that sampling calls 'never' over its whole joint box: a "
            "proof, or a colliding witness configuration (then 'sometimes').",
        ),
        Option(
            "certify_boxes",
            ("--certify-boxes",),
            "Work for --certify in all, in joint boxes, shared evenly among the pairs still to "
            "decide; a pair that needs more is 'undecided'. The same verdicts on every machine "
            "(4,000,000: about a minute on one core for Panda-size links).",
            integer,
            bounds=(0, None),
        ),
        Option(
            "certify_budget",
            ("--certify-budget",),
            "Also stop --certify after this many seconds in all (default: no time limit). "
            "With a time limit, which pairs are decided can depend on the machine's speed.",
            number,
            bounds=(0.0, None),
            typer_extra={"show_default": False},
        ),
        Option(
            "mask_policy",
            ("--mask-policy",),
            "proven: ignore a never-colliding pair only when --certify proved it "
            "(implies --certify); sampled: also when sampling never saw it collide.",
            choice(MaskPolicy),
        ),
        Option(
            "moveit",
            ("--moveit",),
            "Judge the default pose as MoveIt's Setup Assistant does (each joint at 0 when "
            "within its limits, else mid-range) instead of the XRDF's defaults, to compare with "
            "an SRDF's disable_collisions like with like.",
        ),
        Option(
            "only",
            ("--only",),
            "Text/Markdown/HTML: show only the pair table or findings.",
            choice(ReportPart),
        ),
        Option(
            "min_rate",
            ("--min-rate",),
            "Text/Markdown/HTML: list only pairs colliding in at least this fraction of "
            "configurations (e.g. 0.001); JSON keeps every pair.",
            number,
            bounds=(0.0, 1.0),
        ),
        Option("strict", ("--strict",), "Warnings also exit 1."),
        Option(
            "timings",
            ("--timings",),
            "Also write the wall time and configurations/s into the report (every format). "
            "Without it the report is the same bytes for the same inputs and options; with "
            "-v the time goes to stderr either way.",
        ),
        XACRO_ARG,
        PACKAGE_PATH,
        QUIET,
        VERBOSE,
    )
)


@dataclass(frozen=True)
class ReportArgs:
    """The arguments of ``xrdf report`` (as the Typer command receives them)."""

    xrdf_file: Path
    urdf: Path
    samples: int = REPORT_SAMPLES
    seed: int = 0
    sampler: SamplerChoice = SamplerChoice.uniform
    configs: Path | None = None
    output_format: ReportFormat = ReportFormat.text
    output: Path | None = None
    plot: Path | None = None
    write_mask: Path | None = None
    clearance_margin: float = 0.01
    coverage: bool = False
    jobs: int | None = None
    certify: bool = False
    certify_boxes: int = CERTIFY_BOXES
    certify_budget: float | None = None
    mask_policy: MaskPolicy = MaskPolicy.sampled
    moveit: bool = False
    only: ReportPart = ReportPart.all
    min_rate: float = 0.0
    strict: bool = False
    timings: bool = False
    xacro_arg: list[str] | None = None
    package_path: list[str] | None = None


#: ``progress_bar()``: a context yielding the bar's ``update`` (None: no bar drawn).
ProgressBar = Callable[[], AbstractContextManager[ProgressUpdate | None]]


def _no_bar() -> AbstractContextManager[ProgressUpdate | None]:
    return nullcontext(None)


def run(args: ReportArgs, progress_bar: ProgressBar = _no_bar) -> int:
    """Report as ``xrdf report`` does: the report on stdout (or ``-o``), the heatmap and the
    XRDF with the recommended mask where asked, notes on stderr; returns the exit code (0, or
    1 for findings). Raises :class:`XrdfToolsError` for a usage or input error (exit 2)."""
    output = _check_outputs(args)
    report, text = _report(args, progress_bar)
    write_result(text, output)
    if args.output_format not in _MACHINE_FORMATS:
        for n in _written_notes(report, output, args.plot, args.write_mask):
            note(n)
    return EXIT_FINDINGS if has_failures(report.diagnostics, strict=args.strict) else EXIT_OK


def _check_outputs(args: ReportArgs) -> Path | None:
    """The report's ``-o`` (None: stdout), once no output would replace an input or another."""
    if is_stdio(args.plot):
        raise XrdfToolsError("--plot needs a file name (a PNG is not written to stdout)")
    outputs = {"--output": args.output or Path("-"), "--plot": args.plot}
    check_output_clash({**outputs, "--write-mask": args.write_mask})
    output = None if is_stdio(args.output) else args.output  # '-o -': stdout, as without -o
    for out_path in (output, args.plot, args.write_mask):
        if out_path is not None:
            check_input_overwrite(out_path, [args.xrdf_file, args.urdf, args.configs])
    return output


def _report(args: ReportArgs, progress_bar: ProgressBar) -> tuple[Report, str]:
    """The report and its text; the mask and the heatmap written where asked."""
    from ...report import (
        CertifyOptions,
        ReportRequest,
        given_configurations,
        recommended_mask_yaml,
        run_report,
    )
    from ...report.render import ReportView, write_heatmap

    try:
        x = load_xrdf_input(args.xrdf_file)
        u = load_robot_option(args.urdf, args.xacro_arg, args.package_path)
        q_c = None
        if args.configs is not None:
            q_c = given_configurations(u, x, args.configs, urdf_path=str(args.urdf))
        proven = args.mask_policy is MaskPolicy.proven
        request = ReportRequest(
            samples=args.samples,
            seed=args.seed,
            sampler=args.sampler.value,
            coverage=args.coverage,
            clearance_margin=args.clearance_margin,
            jobs=_clamped_jobs(args.jobs),
            certify=(
                CertifyOptions(args.certify_boxes, args.mask_policy.value, args.certify_budget)
                if args.certify or proven
                else None
            ),
            moveit=args.moveit,
        )
        label = "sampling" if q_c is None else "checking"
        detail(
            f"{label} {args.samples if q_c is None else len(q_c):,} configuration(s) "
            f"({args.sampler.value} sampler, seed {args.seed}, {request.jobs} job(s))"
        )
        with progress_bar() as bar, timed(label):
            report = run_report(
                u,
                x,
                request,
                urdf_path=str(args.urdf),
                configs=q_c,
                progress=one_bar(bar, label) or progress_lines(label),
                certify_progress=one_bar(bar, "certifying pairs") or progress_lines("certify"),
            )
        view = ReportView(args.only.value, args.min_rate, args.timings)
        text = _render(report, args.output_format, view)
        if args.write_mask is not None:
            write_result(recommended_mask_yaml(x, report), args.write_mask)
        if args.plot is not None:
            write_heatmap(report, args.plot)
    except XrdfToolsError:
        raise
    except OSError as exc:
        raise XrdfToolsError(f"{exc.filename or ''}: {exc.strerror or exc}") from None
    return report, text


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


# --------------------------------------------------------------------------------------------
# The fast path: `xrdf report ...` without typer
# --------------------------------------------------------------------------------------------
def parse_fast(argv: Sequence[str]) -> tuple[ReportArgs, bool] | None:
    """The :class:`ReportArgs` of ``argv`` (the words after ``xrdf``) and whether ``-q`` was
    given, when it is a ``report`` command line read here exactly as typer would read it,
    else None (typer runs it)."""
    line = parse_command_line(REPORT_OPTIONS, argv, "report")
    if line is None or len(line.arguments) != 1 or "urdf" not in line.values:
        return None  # no XRDF, two, or no --urdf: typer's usage error
    quiet = bool(line.values.pop("quiet", False))
    return ReportArgs(Path(line.arguments[0]), **line.values), quiet


def fast_main(argv: Sequence[str]) -> int | None:
    """Run ``xrdf report`` without typer when :func:`parse_fast` reads ``argv`` and no
    progress bar is drawn (``-q``, or stderr is no terminal): the exit code (an error on
    stderr as ``error: ...``, like the Typer command), or None when typer must run it."""
    parsed = parse_fast(argv)
    if parsed is None or (is_terminal(sys.stderr) and not parsed[1]):
        return None
    args, quiet = parsed
    try:
        with run_verbosity(quiet):
            return run(args)
    except XrdfToolsError as exc:
        echo(f"error: {one_line(str(exc))}", err=True)
        return EXIT_USAGE
