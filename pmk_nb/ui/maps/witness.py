"""The Maps screen's witness panel: does each converted storey's written map agree with its plan?

It shows the verdict the converter's witness stored in the rooms file (``pmk_nb.witness.stored`` puts
it in words), each finding on its own line and the map with the findings ringed and numbered (drawn
in a thread: reading a large map must not hold the page). "Check against the plan" runs the witness
on the files as they are now: for a map converted before the witness, or edited since.
"""

from __future__ import annotations

import threading
from typing import TYPE_CHECKING, Any

import ipywidgets as w

from pmk_nb.access import profile_chair_width
from pmk_nb.ui.common.widgets import button, error_text, escape, guard, picture, replace_children, run_in_thread
from pmk_nb.witness import Verdict, VerdictState, stored_verdict, verdict_of

if TYPE_CHECKING:
    from pmk_nb.library import GeneratedMap, MapEntry
    from pmk_nb.ui.common.context import AppContext

OK_STATES = (VerdictState.AGREES,)


def _label(gm: GeneratedMap, several: bool) -> str:
    """Which storey, when the map has several ('' for one: the headline says "The map ...")."""
    return f"Storey {gm.storey}" if several and gm.storey else ""


def verdict_html(label: str, verdict: Verdict) -> str:
    """One storey's verdict: the headline, then the findings numbered as on the picture."""
    ok = verdict.state in OK_STATES
    cls = "pmk-ok" if ok else "pmk-warn"
    mark = "✓" if ok else "⚠"
    who = f"{escape(label)}: " if label else ""
    head = f"<p class='{cls} pmk-witness-verdict'><b>{mark} {who}</b>{escape(verdict.headline)}</p>"
    items = "".join(f"<li>{escape(line)}</li>" for line in verdict.lines)
    listing = f"<ol class='pmk-witness-list'>{items}</ol>" if items else ""
    more = f"<p>and {verdict.more} more (<code>pmk check MAP.yaml</code> lists them all)</p>" if verdict.more else ""
    return head + listing + more


def _draw(gm: GeneratedMap, verdict: Verdict) -> bytes:
    """The map with the verdict's findings ringed (reads the map: run it off the kernel's thread)."""
    from pmk_nb.rosmap import read_map
    from pmk_nb.witness import findings_png

    return findings_png(read_map(gm.yaml), verdict.report.findings if verdict.report is not None else [])


class WitnessPanel:
    """The witness's verdict on the selected map's storeys; ``show(entry, docs)`` refreshes it."""

    def __init__(self, ctx: AppContext) -> None:
        self.ctx = ctx
        self.entry: MapEntry | None = None
        self.verdicts: list[Verdict] = []
        self._generation = 0
        self._lock = threading.Lock()  # one check at a time
        self.text = w.HTML("")
        self.text.add_class("pmk-witness-text")
        self.images = w.VBox([])
        self.images.add_class("pmk-witness-images")
        self.check_button = button("Check against the plan", "pmk-witness-check", icon="search")
        self.check_button.on_click(guard(ctx, "Checking the map")(lambda _b: self.check()))
        self.status = w.HTML("")
        self.status.add_class("pmk-witness-status")
        self.widget = w.VBox(
            [self.text, self.images, self.check_button, self.status],
            layout=w.Layout(width="100%", align_items="flex-start", display="none"),
        )
        self.widget.add_class("pmk-witness")

    def show(self, entry: MapEntry | None, docs: list[dict[str, Any] | None]) -> threading.Thread | None:
        """``docs``: the rooms file of each of ``entry``'s generated maps. Returns the picture thread, if any."""
        self._generation += 1  # only the kernel's thread selects: a stale thread's result is dropped
        generation = self._generation
        self.entry = entry
        self.status.value = ""
        if entry is None or not entry.generated:
            self.verdicts = []
            self.text.value = ""
            replace_children(self.images, ())
            self.widget.layout.display = "none"
            return None
        self.widget.layout.display = "flex"
        return self._present(entry, [stored_verdict(doc) for doc in docs], generation)

    def _present(
        self, entry: MapEntry, verdicts: list[Verdict], generation: int, pngs: list[bytes | None] | None = None
    ) -> threading.Thread | None:
        """Say the verdicts at once; show the pictures ``pngs`` (one per map, None: none) or, when not
        given, draw those of the verdicts with findings in a thread."""
        self.verdicts = verdicts
        several = len(entry.generated) > 1
        parts = [verdict_html(_label(gm, several), v) for gm, v in zip(entry.generated, verdicts, strict=True)]
        self.text.value = "<div class='pmk-heading-small'>Map against the plan</div>" + "".join(parts)
        if pngs is not None:
            self._pictures(entry, verdicts, pngs)
            return None
        replace_children(self.images, ())
        pairs = list(zip(entry.generated, verdicts, strict=True))
        if not any(v.lines and not gm.broken for gm, v in pairs):
            return None

        def work() -> list[bytes | None]:
            return [_draw(gm, v) if v.lines and not gm.broken else None for gm, v in pairs]

        def done(drawings: list[bytes | None]) -> None:
            if generation == self._generation:
                self._pictures(entry, verdicts, drawings)

        def failed(err: BaseException) -> None:
            if generation == self._generation:
                self.status.value = f"<span class='pmk-msg-error'>No picture: {escape(error_text(err))}</span>"

        return run_in_thread(self.ctx, "Drawing the witness's findings", work, on_done=done, on_error=failed)

    def _pictures(self, entry: MapEntry, verdicts: list[Verdict], pngs: list[bytes | None]) -> None:
        replace_children(
            self.images,
            [
                _picture(gm, v, png)
                for gm, v, png in zip(entry.generated, verdicts, pngs, strict=True)
                if png is not None
            ],
        )

    def check(self) -> threading.Thread | None:
        """Judge the selected map's files, as they are now, against the plan (in a thread)."""
        entry = self.entry
        if entry is None or not entry.generated:
            return None
        generation = self._generation
        width = profile_chair_width(None, self.ctx.profile())
        self.status.value = "Checking the map against the plan…"

        def work() -> tuple[list[Verdict], list[bytes | None]]:
            from pmk_nb.witness import findings_png, witness_map

            verdicts: list[Verdict] = []
            pngs: list[bytes | None] = []
            for gm in entry.generated:
                if gm.broken:  # its card says why; nothing to judge
                    verdicts.append(stored_verdict(None))
                    pngs.append(None)
                    continue
                report, grid = witness_map(gm.yaml, chair_width=width)
                verdicts.append(verdict_of(report))
                pngs.append(findings_png(grid, report.findings) if report.findings else None)
                del grid  # one storey's grid in memory at a time
            return verdicts, pngs

        def done(result: tuple[list[Verdict], list[bytes | None]]) -> None:
            if generation != self._generation:
                return  # another map was selected meanwhile
            verdicts, pngs = result
            self._present(entry, verdicts, generation, pngs)
            self.status.value = "Checked the map's files as they are now against the plan."

        def failed(err: BaseException) -> None:
            if generation == self._generation:
                self.status.value = f"<span class='pmk-msg-error'>{escape(error_text(err))}</span>"

        return run_in_thread(
            self.ctx,
            "Checking the map",
            work,
            on_done=done,
            on_error=failed,
            busy=[self.check_button],
            exclusive=self._lock,
        )


def _picture(gm: GeneratedMap, verdict: Verdict, png: bytes) -> w.Widget:
    n = len(verdict.report.findings) if verdict.report is not None else 0
    alt = f"The map {gm.yaml.stem} with the witness's {n} finding(s) ringed and numbered"
    return picture(png, alt, "pmk-witness-picture", on_img=True)
