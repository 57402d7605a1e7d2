"""Render a :class:`~xrdf_tools.report.Report` as text, JSON, Markdown, HTML or a PNG heatmap.

Every renderer returns a string (the PNG writer takes a path); nothing here prints. The JSON
document follows ``docs/report-schema.json`` (``schema_version`` below).
"""

from __future__ import annotations

import html
import io
import json
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from .. import __version__
from ..selfcollision.collision import Contact
from ..util.text import pair_text
from ..yaml.io import write_atomic
from . import PairStat, Report

__all__ = [
    "RENDERERS",
    "SCHEMA_VERSION",
    "ReportView",
    "render_html",
    "render_json",
    "render_markdown",
    "render_text",
    "report_to_dict",
    "write_heatmap",
]

SCHEMA_VERSION = 2
_TEXT_TRAJECTORY_LIMIT = 20
#: A full pair table longer than this (about a screen) ends the text report with how to see
#: only what matters: a TIAGo arm's report lists 1,830 frame pairs.
LONG_TABLE_PAIRS = 60


def _mm(x: float | None, bound: bool = False) -> str:
    if x is None or not math.isfinite(x):
        return "-"
    return f"{'≥' if bound else ''}{x * 1000:.1f}"


def _rate(p: PairStat) -> str:
    if p.rate is None:
        return "-"
    if p.hits == 0:
        return f"0 (<{p.rate_upper_95:.2g})"
    return f"{p.rate:.3%}"


def _contact_dict(c: Contact) -> dict[str, Any]:
    return {
        "frame_a": c.frame_a,
        "frame_b": c.frame_b,
        "clearance": c.clearance,
        "sphere_a": c.sphere_a,
        "sphere_b": c.sphere_b,
        "n_sphere_pairs": c.n_sphere_pairs,
    }


def report_to_dict(r: Report, *, timings: bool = False) -> dict[str, Any]:
    """The report as plain JSON data (see ``docs/report-schema.json``). The same inputs and
    options give the same data; ``timings`` adds the wall time (``elapsed_s``), which does not
    repeat."""
    counts: dict[str, int] = {}
    for p in r.pairs:
        counts[p.classification] = counts.get(p.classification, 0) + 1
    doc: dict[str, Any] = {
        "schema_version": SCHEMA_VERSION,
        "tool": f"xrdf-tools {__version__}",
        "xrdf": r.xrdf_path,
        "urdf": r.urdf_path,
        "source": r.source,
        "samples": r.samples,
        "sampler": r.sampler,
        "seed": r.seed,
        "cspace_joints": list(r.cspace_joints),
        "frames": list(r.frames),
        "sphere_counts": dict(r.sphere_counts),
        "placeholder_spheres": r.placeholders,
        "default_configuration": dict(r.default_configuration),
        "default_ok": r.default_ok,
        "default_contacts": [_contact_dict(c) for c in r.default_contacts],
        "classification_counts": counts,
        "pairs": [p.to_dict() for p in r.pairs],
        "trajectory": (
            None
            if r.trajectory is None
            else [
                {"index": h.index, "contacts": [_contact_dict(c) for c in h.contacts]}
                for h in r.trajectory
            ]
        ),
        "recommended_ignore": {a: list(bs) for a, bs in r.recommended_ignore.items()},
        "mask_change": {
            "added": [list(p) for p in r.mask_change.added],
            "removed": [list(p) for p in r.mask_change.removed],
            "dropped_unknown": list(r.mask_change.dropped_unknown),
        },
        "coverage": (
            None
            if r.coverage is None
            else {
                "per_frame": r.coverage.per_frame,
                "overall": r.coverage.overall_numbers,
                "note": r.coverage.note,
            }
        ),
        "diagnostics": [d.to_dict() for d in r.diagnostics],
    }
    if timings:
        doc["elapsed_s"] = round(r.elapsed_s, 3)
    return doc


def render_json(r: Report, *, timings: bool = False) -> str:
    return json.dumps(report_to_dict(r, timings=timings), indent=2) + "\n"


# ------------------------------------------------------------------------------------------
# Shared pieces
# ------------------------------------------------------------------------------------------
_HEADER = (
    "frame A",
    "frame B",
    "joints",
    "mask",
    "class",
    "hits",
    "rate (95% UB)",
    "min clr mm",
    "advice",
)


@dataclass(frozen=True)
class ReportView:
    """What the text, Markdown and HTML renderings show (JSON always holds everything).

    ``only``: ``"all"``, ``"pairs"`` (the table) or ``"findings"``; ``min_rate``: table rows
    whose collision rate is at least this (pairs that were not sampled are left out when it is
    above 0), so that a PR2-size report shows the pairs that matter; ``timings``: also the wall
    time and rate (in every format, JSON included), which differ run to run while everything
    else is the same bytes for the same inputs and options.
    """

    only: str = "all"
    min_rate: float = 0.0
    timings: bool = False

    def rows(self, r: Report) -> list[PairStat]:
        if self.min_rate <= 0.0:
            return list(r.pairs)
        return [p for p in r.pairs if p.rate is not None and p.rate >= self.min_rate]


def _row(p: PairStat) -> tuple[str, ...]:
    return (
        p.frame_a,
        p.frame_b,
        str(p.joints_on_path),
        "ignored" if p.masked else "checked",
        p.classification,
        "-" if p.hits is None else str(p.hits),
        _rate(p),
        _mm(p.min_clearance, p.min_clearance_is_bound),
        p.note,
    )


def _timing(r: Report, view: ReportView) -> str:
    if not view.timings:
        return ""
    return f" in {r.elapsed_s:.2f} s ({r.configs_per_s:,.0f} configurations/s)"


def _summary_lines(r: Report, view: ReportView) -> list[str]:
    what = (
        f"{r.samples} {r.sampler} samples (seed {r.seed})"
        if r.source == "sampled"
        else f"{r.samples} given configurations"
    )
    n_sph = sum(r.sphere_counts.values())
    lines = [
        f"XRDF {r.xrdf_path or '<input>'} with URDF {r.urdf_path}",
        f"{what} over c-space [{', '.join(r.cspace_joints)}]" + _timing(r, view),
        f"{n_sph} spheres on {len(r.frames)} frames, {len(r.pairs)} frame pairs"
        + (f"; {r.placeholders} placeholder sphere(s) ignored" if r.placeholders else ""),
    ]
    if r.default_ok:
        lines.append("default configuration: free of self-collision (unmasked pairs)")
    else:
        lines.append(
            "default configuration: IN SELF-COLLISION: "
            + "; ".join(
                f"{pair_text(c.frame_a, c.frame_b)} {c.clearance * 1000:.1f} mm"
                for c in r.default_contacts
            )
        )
    return lines


def _mask_lines(r: Report) -> list[str]:
    ch = r.mask_change
    if ch.empty:
        return ["recommended ignore list: same as the current one"]
    out = ["recommended ignore list differs from the current one:"]
    out += [f"  + {a} / {b}" for a, b in ch.added]
    out += [f"  - {a} / {b}" for a, b in ch.removed]
    out += [f"  - unknown frame '{n}' dropped" for n in ch.dropped_unknown]
    return out


def _table(rows: Sequence[Sequence[str]]) -> list[str]:
    widths = [max(len(r[i]) for r in rows) for i in range(len(rows[0]) - 1)]
    return [
        "  ".join(c.ljust(w) for c, w in zip(r[:-1], widths, strict=True)) + "  " + r[-1]
        for r in rows
    ]


def _trajectory_lines(r: Report, limit: int | None) -> list[str]:
    if r.trajectory is None:
        return []
    if not r.trajectory:
        return [f"trajectory check: none of the {r.samples} configurations collides"]
    out = [f"trajectory check: {len(r.trajectory)} of {r.samples} configurations collide"]
    shown = r.trajectory if limit is None else r.trajectory[:limit]
    for h in shown:
        pairs = ", ".join(
            f"{pair_text(c.frame_a, c.frame_b)} {c.clearance * 1000:.1f} mm" for c in h.contacts
        )
        out.append(f"  #{h.index}: {pairs}")
    if limit is not None and len(r.trajectory) > limit:
        out.append(f"  ... and {len(r.trajectory) - limit} more (see --format json)")
    return out


def _coverage_lines(r: Report) -> list[str]:
    if r.coverage is None:
        return []
    out = ["sphere coverage:"]
    for f, m in r.coverage.per_frame.items():
        out.append(f"  {f}: " + ", ".join(f"{k} {v:.3g}" for k, v in m.items()))
    overall = r.coverage.overall_numbers
    if overall:
        out.append("  overall: " + ", ".join(f"{k} {v:.3g}" for k, v in overall.items()))
    if r.coverage.note:
        out.append(f"  ({r.coverage.note})")
    return out


# ------------------------------------------------------------------------------------------
# Text / Markdown / HTML
# ------------------------------------------------------------------------------------------
def render_text(r: Report, view: ReportView = ReportView()) -> str:
    lines = _summary_lines(r, view)
    lines.append("")
    if view.only != "findings":
        lines += _pair_table_lines(r, view)
    if view.only == "pairs":
        return "\n".join(lines) + "\n"
    lines += _trajectory_lines(r, _TEXT_TRAJECTORY_LIMIT)
    lines += _mask_lines(r)
    lines += _coverage_lines(r)
    lines.append("")
    if r.diagnostics:
        lines.append("findings:")
        lines += [
            f"  {d.location()}: {d.severity.value} {d.rule} {d.message}" for d in r.diagnostics
        ]
    else:
        lines.append("findings: none")
    lines += _long_table_hint(r, view)
    return "\n".join(lines) + "\n"


def _long_table_hint(r: Report, view: ReportView) -> list[str]:
    """Where the whole pair table scrolled past: the options that show what matters."""
    if view.only != "all" or len(view.rows(r)) <= LONG_TABLE_PAIRS:
        return []
    fewer = (
        f"a --min-rate above {view.min_rate:g} fewer pairs"
        if view.min_rate > 0.0
        else "--min-rate 0.001 the pairs that collide in 0.1 % of the samples or more"
    )
    return [
        "",
        f"({len(view.rows(r))} frame pairs in the table above: --only findings shows the "
        f"findings alone, {fewer}; --format json holds every pair)",
    ]


def _pair_table_lines(r: Report, view: ReportView) -> list[str]:
    lines = ["spheres per frame: " + ", ".join(f"{f} {n}" for f, n in r.sphere_counts.items())]
    lines.append("")
    rows = view.rows(r)
    if rows:
        lines += _table([_HEADER, *(_row(p) for p in rows)])
        lines.append("")
    if len(rows) < len(r.pairs):
        lines += [f"({len(r.pairs) - len(rows)} pair(s) below --min-rate not shown)", ""]
    return lines


def _md_cell(s: str) -> str:
    """Text as Markdown shows it, in a table cell or a list item: a name from the robot
    files may hold ``|`` (a new cell), a line break (a new row) or HTML (``<img ...>``)."""
    text = html.escape(" ".join(s.splitlines()), quote=False)
    return text.replace("|", "\\|")


def render_markdown(r: Report, view: ReportView = ReportView()) -> str:
    out = ["# Self-collision report", ""]
    out += [f"- {_md_cell(s)}" for s in _summary_lines(r, view)]
    out += ["", "## Spheres per frame", "", "| frame | spheres |", "|---|---:|"]
    out += [f"| {_md_cell(f)} | {n} |" for f, n in r.sphere_counts.items()]
    out += ["", "## Frame pairs", ""]
    out.append("| " + " | ".join(_HEADER) + " |")
    out.append("|" + "---|" * len(_HEADER))
    out += ["| " + " | ".join(_md_cell(c) for c in _row(p)) + " |" for p in view.rows(r)]
    traj = _trajectory_lines(r, None)
    if traj:
        out += ["", "## Trajectory check", "", *(f"    {t}" for t in traj)]
    out += ["", "## Mask", "", *(f"    {t}" for t in _mask_lines(r))]
    cov = _coverage_lines(r)
    if cov:
        out += ["", "## Coverage", "", *(f"    {t}" for t in cov)]
    out += ["", "## Findings", ""]
    if r.diagnostics:
        out += [
            f"- **{d.severity.value}** `{d.rule}` {_md_cell(d.location())}: {_md_cell(d.message)}"
            for d in r.diagnostics
        ]
    else:
        out.append("None.")
    return "\n".join(out) + "\n"


_CLASS_COLOUR = {
    "adjacent": "#dddddd",
    "default": "#f4b183",
    "always": "#f8cbad",
    "never": "#e2f0d9",
    "sometimes": "#fff2cc",
}


def render_html(r: Report, view: ReportView = ReportView()) -> str:
    e = html.escape
    out = [
        "<!DOCTYPE html>",
        '<html lang="en"><head><meta charset="utf-8"><title>Self-collision report</title>',
        "<style>body{font-family:sans-serif;margin:2em}table{border-collapse:collapse}"
        "td,th{border:1px solid #bbb;padding:2px 6px;font-size:90%}th{background:#eee}"
        ".num{text-align:right}</style></head><body>",
        "<h1>Self-collision report</h1><ul>",
        *(f"<li>{e(s)}</li>" for s in _summary_lines(r, view)),
        "</ul><h2>Spheres per frame</h2><table><tr><th>frame</th><th>spheres</th></tr>",
        *(f'<tr><td>{e(f)}</td><td class="num">{n}</td></tr>' for f, n in r.sphere_counts.items()),
        "</table><h2>Frame pairs</h2><table><tr>",
        *(f"<th>{e(h)}</th>" for h in _HEADER),
        "</tr>",
    ]
    for p in view.rows(r):
        colour = _CLASS_COLOUR.get(p.classification, "#ffffff")
        out.append(
            f'<tr style="background:{colour}">' + "".join(f"<td>{e(c)}</td>" for c in _row(p))
        )
        out.append("</tr>")
    out.append("</table>")
    for title, lines in (
        ("Trajectory check", _trajectory_lines(r, None)),
        ("Mask", _mask_lines(r)),
        ("Coverage", _coverage_lines(r)),
    ):
        if lines:
            out.append(f"<h2>{title}</h2><pre>{e(chr(10).join(lines))}</pre>")
    out.append("<h2>Findings</h2>")
    if r.diagnostics:
        out.append("<ul>")
        out += [
            f"<li><b>{e(d.severity.value)}</b> <code>{e(d.rule)}</code> {e(d.location())}: "
            f"{e(d.message)}</li>"
            for d in r.diagnostics
        ]
        out.append("</ul>")
    else:
        out.append("<p>None.</p>")
    out.append("</body></html>")
    return "\n".join(out) + "\n"


def _render_json_view(r: Report, view: ReportView = ReportView()) -> str:
    return render_json(r, timings=view.timings)  # every pair and row: only timings apply


#: The one table of the report's renderers: format name → ``(report, view) → text``. The
#: ``github`` and ``sarif`` formats show only the findings (:attr:`Report.diagnostics`), with the
#: diagnostics' renderers; the heatmap is an extra file (:func:`write_heatmap`).
RENDERERS: dict[str, Callable[[Report, ReportView], str]] = {
    "text": render_text,
    "json": _render_json_view,
    "markdown": render_markdown,
    "html": render_html,
}


# ------------------------------------------------------------------------------------------
# PNG heatmap
# ------------------------------------------------------------------------------------------
def write_heatmap(r: Report, path: str | Path) -> None:
    """Collision-rate matrix of the frame pairs as a PNG (matplotlib, Agg, imported lazily).

    Cell colour: collision rate (log scale); adjacent pairs are grey, masked pairs are hatched
    with an ``x``; the number in a cell is the rate in percent.
    """
    from ..util.extras import VIZ, require

    require(VIZ, "viz", "--plot")
    import numpy as np
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.colors import LogNorm
    from matplotlib.figure import Figure
    from matplotlib.patches import Rectangle

    frames = list(r.frames)
    n = len(frames)
    pos = {f: i for i, f in enumerate(frames)}
    rate = np.full((n, n), np.nan)
    for p in r.pairs:
        if p.rate is not None:
            i, j = pos[p.frame_a], pos[p.frame_b]
            rate[i, j] = rate[j, i] = p.rate
    size = max(4.0, 0.45 * n + 2.5)
    # a figure of its own (no pyplot): the caller's backend and figures are left alone, and
    # names are drawn as written (a '$' in a frame name starts no math text)
    fig = Figure(figsize=(size + 1.5, size), dpi=110)
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    floor = 0.5 / max(r.samples, 1)
    shown = np.where(np.isnan(rate), np.nan, np.maximum(rate, floor))
    im = ax.imshow(shown, cmap="magma_r", norm=LogNorm(vmin=floor, vmax=1.0))
    for p in r.pairs:
        i, j = pos[p.frame_a], pos[p.frame_b]
        for a, b in ((i, j), (j, i)):
            if p.adjacent and p.rate is None:
                ax.add_patch(Rectangle((b - 0.5, a - 0.5), 1, 1, color="#bbbbbb"))
            if p.masked:
                ax.text(b, a, "x", ha="center", va="center", color="#1f77b4", fontsize=12)
            elif p.rate:
                ax.text(
                    b,
                    a,
                    f"{p.rate * 100:.2g}",
                    ha="center",
                    va="center",
                    fontsize=6,
                    color="white" if p.rate > 0.05 else "black",
                )
    ax.set_xticks(range(n), frames, rotation=90, fontsize=7, parse_math=False)
    ax.set_yticks(range(n), frames, fontsize=7, parse_math=False)
    ax.set_title(f"self-collision rate over {r.samples} configurations (x = ignored)", fontsize=9)
    fig.colorbar(im, ax=ax, label="collision rate")
    fig.tight_layout()
    buf = io.BytesIO()
    fig.savefig(buf, format="png")
    write_atomic(path, buf.getvalue())
