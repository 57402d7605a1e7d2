"""The mask panel of the ``xrdf edit`` page: frame pairs with a toggle each, a report run from
the page and its recommended mask, buffer distances, witness poses.

The pair table lists the pairs of frames with spheres: those touching at the current pose
first, then by the last report's collision rate; a filter narrows it by frame name. The report
is :func:`xrdf_tools.report.self_collision_report` on the current document.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from ..report import Report, self_collision_report
from ..report.results import CertifyOptions, PairStat
from ..util.errors import XrdfToolsError
from ..util.numbers import REPORT_SAMPLES
from .edits import SetBuffer, SetIgnored, SetMask
from .markup import code, text
from .surface import PageSurface, from_browser
from .typed import TypedNumber

if TYPE_CHECKING:
    from ..xrdf.model import Xrdf

__all__ = ["MAX_ROWS", "MaskPanel", "pair_label"]

#: Pair toggles shown at once (the filter reaches the others).
MAX_ROWS = 24
#: Pairs of the report's table (highest collision rate first).
TABLE_ROWS = 12
#: The most samples the page's report takes (it runs while the page waits: about 5 s on a
#: TIAGo arm; ``xrdf report`` takes more, in worker processes).
MAX_PAGE_SAMPLES = 1_000_000
#: The longest certify budget the page's report takes, seconds.
MAX_CERTIFY_S = 120.0
#: The largest buffer distance the field takes, metres.
MAX_BUFFER = 0.5


def pair_label(a: str, b: str) -> str:
    """The label of a pair's toggle (also what the browser tests look for)."""
    return f"{a} ↔ {b}"


def _stat_text(p: PairStat) -> str:
    rate = "not sampled" if p.rate is None else f"rate {p.rate:.2%}"
    proof = f", {p.certificate}" if p.certificate else ""
    return f"{rate}, {p.classification}{proof} → {p.recommendation}"


class MaskPanel:
    """Pair toggles, buffer distance, report run and witness poses."""

    def __init__(self, page: PageSurface, gui: Any) -> None:
        from ..selfcollision.collision import SphereSet

        self.page = page
        self.gui = gui
        self.report: Report | None = None
        self.report_for: Xrdf | None = None
        self.rows: dict[tuple[str, str], Any] = {}
        self._spheres: SphereSet | None = None
        with gui.add_folder("Mask"):
            self.buffer = TypedNumber(
                gui, "Buffer (m)", 0.0, lo=0.0, hi=MAX_BUFFER, unit=" m", hint="1e-3 is 1 mm"
            )
            self.filter = gui.add_text("Filter pairs", "")
            self.summary = gui.add_markdown("")
            self.pairs = gui.add_folder("Pairs (ignored when ticked)")
            self.samples = TypedNumber(
                gui,
                "Report samples",
                min(page.report_samples, MAX_PAGE_SAMPLES),
                lo=1,
                hi=MAX_PAGE_SAMPLES,
                integer=True,
                hint="1e5 is 100,000",
            )
            self.budget = TypedNumber(
                gui, "Certify budget (s)", 0.0, lo=0.0, hi=MAX_CERTIFY_S, unit=" s"
            )
            run = gui.add_button("Run report")
            self.apply_mask = gui.add_button("Apply recommended mask", visible=False)
            self.witness = gui.add_dropdown("Witness", ("none",), visible=False)
            self.pose_witness = gui.add_button("Pose witness", visible=False)

        self.buffer.on_number(page.say, self._set_buffer)
        for field in (self.samples, self.budget):
            field.watch(page.say)
        self.filter.on_update(lambda e: self.update(document=True) if from_browser(e) else None)
        run.on_click(lambda e: self.run_report() if from_browser(e) else None)
        self.apply_mask.on_click(lambda e: self._apply_mask() if from_browser(e) else None)
        self.pose_witness.on_click(lambda e: self._pose_witness() if from_browser(e) else None)

    # --- buffers ---------------------------------------------------------------------------
    def sync_selection(self, frame: str) -> None:
        sc = self.page.state.xrdf.self_collision
        self.buffer.show(float(sc.buffer_distance.get(frame, 0.0)) if sc else 0.0)

    def _set_buffer(self, distance: float) -> None:
        sel = self.page.selected
        if sel is None:
            self.page.say("select a link first")
            return
        self.page.apply(SetBuffer(sel[0], distance), merge_key=("buffer", sel[0]))

    # --- report ----------------------------------------------------------------------------
    def run_report(self) -> None:
        """Run a report on the current document (in the GUI callback's thread)."""
        page = self.page
        xrdf = page.state.xrdf
        budget = self.budget.take(page.say)
        samples = self.samples.take(page.say) if budget is not None else None
        if budget is None or samples is None:
            return
        n = int(samples)
        self.summary.content = f"_sampling {n} configurations…_"
        try:
            report = self_collision_report(
                page.robot.robot,
                xrdf,
                samples=n,
                seed=0,
                certify=CertifyOptions(budget_s=budget) if budget > 0 else None,
            )
        except XrdfToolsError as e:
            self.summary.content = f"_report failed: {text(e)}_"
            return
        with page.lock:
            self.report, self.report_for = report, xrdf
            witnesses = [
                pair_label(p.frame_a, p.frame_b) for p in report.pairs if p.witness is not None
            ]
            self.witness.options = tuple(witnesses) or ("none",)
            self.witness.visible = self.pose_witness.visible = bool(witnesses)
            self.apply_mask.visible = True
            self.update(document=True)

    def _apply_mask(self) -> None:
        r = self.report
        if r is None:
            return
        label = "apply the report's recommended mask"
        if self.report_for is not self.page.state.xrdf:  # said in the message that follows
            label += " (the report is of an earlier version: run it again to check)"
        unproven = [p for p in r.pairs if p.classification == "never" and not _proven(p)]
        if unproven and r.samples < REPORT_SAMPLES:
            label += (
                f" (from {r.samples:,} samples: {len(unproven)} pair(s) never seen colliding may "
                f"collide rarely; xrdf report samples {REPORT_SAMPLES:,})"
            )
        self.page.apply(SetMask(r.recommended_ignore, label))

    def _pose_witness(self) -> None:
        r = self.report
        if r is None:
            return
        for p in r.pairs:
            if p.witness is not None and pair_label(p.frame_a, p.frame_b) == self.witness.value:
                page = self.page
                page.set_pose(page.robot.pose_from(page.q, p.witness))
                return

    def _summary(self) -> str:
        r = self.report
        if r is None:
            return "Run a report to see collision rates and the recommended mask."
        ch = r.mask_change
        stale = "" if self.report_for is self.page.state.xrdf else " (for an earlier version)"
        head = (
            f"Report{stale}: {r.samples} samples, {len(r.pairs)} pairs; recommended mask adds "
            f"{len(ch.added)} and removes {len(ch.removed)} pair(s)."
        )
        ranked = sorted(r.pairs, key=lambda p: (-(p.rate or 0.0), p.frame_a, p.frame_b))
        rows = [
            f"| {code(p.frame_a)} ↔ {code(p.frame_b)} | "
            + ("–" if p.rate is None else f"{p.rate:.2%}")
            + f" | {text(p.classification)} | {text(p.certificate or '')} | "
            + f"{text(p.recommendation)} |"
            for p in ranked[:TABLE_ROWS]
        ]
        table = "| pair | rate | verdict | proof | mask |\n|---|---:|---|---|---|\n"
        return head + "\n\n" + table + "\n".join(rows)

    # --- the pair table --------------------------------------------------------------------
    def _all_pairs(self) -> list[tuple[str, str]]:
        spheres = self.page.robot.sphere_set(self.page.state.xrdf)
        names = spheres.frame_names
        return [
            (names[int(a)], names[int(b)])
            for a, b in zip(
                spheres.frame_pair_a.tolist(), spheres.frame_pair_b.tolist(), strict=True
            )
        ]

    def listed(self) -> list[tuple[str, str]]:
        """The pairs the table shows, in order (see the module docstring)."""
        words = self.filter.value.strip().lower().split()
        touching = {
            frozenset((c.frame_a, c.frame_b)): k
            for k, c in enumerate(self.page.collisions.contacts)
        }
        rates: dict[frozenset[str], float] = {}
        if self.report is not None:
            rates = {frozenset((p.frame_a, p.frame_b)): p.rate or 0.0 for p in self.report.pairs}

        def key(ab: tuple[str, str]) -> tuple[int, float, str, str]:
            pair = frozenset(ab)
            return (touching.get(pair, len(touching)), -rates.get(pair, 0.0), *ab)

        pairs = [
            ab for ab in self._all_pairs() if all(any(w in f.lower() for f in ab) for w in words)
        ]
        return sorted(pairs, key=key)[:MAX_ROWS]

    def update(self, *, document: bool) -> None:
        page = self.page
        if document:
            self.summary.content = self._summary()
        want = self.listed()
        sc = page.state.xrdf.self_collision
        if set(self.rows) != set(want):  # rebuilt only when other pairs are listed
            for h in self.rows.values():
                h.remove()
            self.rows = {}
            with self.pairs:
                for a, b in want:
                    self.rows[(a, b)] = self._row(a, b)
        for (a, b), h in self.rows.items():
            h.value = bool(sc is not None and sc.is_ignored(a, b))

    def _row(self, a: str, b: str) -> Any:

        hint = None
        if self.report is not None:
            try:
                hint = _stat_text(self.report.pair(a, b))
            except KeyError:
                hint = None
        sc = self.page.state.xrdf.self_collision
        box = self.gui.add_checkbox(
            pair_label(a, b), bool(sc is not None and sc.is_ignored(a, b)), hint=hint
        )

        def toggled(e: Any) -> None:
            if from_browser(e):
                self.page.apply(SetIgnored(a, b, bool(box.value)))

        box.on_update(toggled)
        return box


def _proven(pair: PairStat) -> bool:
    """The pair's "never" is proven over its whole joint box (``--certify``), not only sampled."""
    return pair.certificate == "proven"
