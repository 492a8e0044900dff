"""The storeys of the selected map on the Maps screen, and the choice of which ones to convert.

Storeys are shown before conversion (issue 4): at once when the maps folder already knows them,
otherwise read in a background thread behind a "reading storeys..." hint, so a large building never
blocks the page. For a building with several storeys a checkbox per storey picks what Convert
writes (default all).
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import ipywidgets as w

from pmk_nb.errors import LibraryError
from pmk_nb.ui.common.widgets import checkbox, escape, field_error, replace_children, run_in_thread, tick_exactly

if TYPE_CHECKING:
    from pmk_nb.library import LayerOption, MapEntry, StoreyInfo
    from pmk_nb.ui.common.context import AppContext


def storeys_table(storeys: list[StoreyInfo], unit: str = "auto") -> str:
    """HTML table: storey, cells, doors, size in metres (were the plan read in ``unit``, when one is chosen)."""
    rows = []
    for s in storeys:
        size = s.size_as(unit)
        dims = f"{_metres(size[0])} × {_metres(size[1])} m" if size else "–"
        rows.append(f"<tr><td>{escape(s.name)}</td><td>{s.cells}</td><td>{s.doors}</td><td>{dims}</td></tr>")
    label = "Size" if unit == "auto" else f"Size (plan in {escape(unit)})"
    head = f"<tr><th>Storey</th><th>Cells</th><th>Doors</th><th>{label}</th></tr>"
    style = "border-collapse:separate;border-spacing:16px 2px;margin-left:-16px;text-align:left"  # columns apart
    return f"<table class='pmk-maps-storeys-table' style='{style}'>{head}{''.join(rows)}</table>"


def _metres(v: float) -> str:
    """One decimal, as the storeys are rooms and floors; a plan read in too small a unit still shows
    its size (two digits), not 0.0."""
    return f"{v:.1f}" if v >= 1 or v == 0 else f"{v:.2g}"


def unit_warning(storeys: list[StoreyInfo]) -> str:
    """The plan's doubts (unit suspected, graph lost, layers not drawn) and its unit conflict, said before
    converting, with what to do about each, or ""."""
    notes = storeys[0].notes if storeys else ()
    parts = []
    if notes:
        items = "".join(f"<li>{escape(n)}</li>" for n in notes)
        offer = any(not o.drawn for o in storeys[0].layers)
        hint = "A layer not drawn can be drawn instead: tick it under <i>Layers to draw</i>." if offer else ""
        parts.append(f"<div class='pmk-maps-plan-notes pmk-warn'><b>Before you convert</b><ul>{items}</ul>{hint}</div>")
    conflict = next((s.unit_conflict for s in storeys if s.unit_conflict), "")
    if conflict:
        parts.append(
            f"<div class='pmk-maps-unit-warning pmk-field-error'>Units: {escape(conflict)}. If the map comes out "
            "the wrong size, choose the unit the file uses under <i>Plan's unit</i> and convert again (command "
            "line: <code>pmk convert --unit m|dm|cm|mm</code>).</div>"
        )
    return "".join(parts)


class StoreysPanel:
    """Storeys of one map; ``selected()`` is what to pass to ``MapsFolder.convert(storeys=...)``."""

    def __init__(self, ctx: AppContext, on_loaded: Callable[[str], None] | None = None) -> None:
        self.ctx = ctx
        self.on_loaded = on_loaded  # told the map name when storeys read in the background arrive
        self.name: str | None = None
        self.storeys: list[StoreyInfo] | None = None
        self.unit = "auto"  # the plan's unit chosen for Convert: the sizes shown are those it gives
        self._generation = 0
        self._lock = threading.Lock()
        self.table = w.HTML("")
        self.table.add_class("pmk-maps-storeys")
        self.choice_label = w.HTML("Storeys to convert:")
        self.choices = w.HBox([])
        self.choices.add_class("pmk-maps-storey-choice")
        self.choice_error = field_error()
        self.choice_box = w.VBox([self.choice_label, self.choices, self.choice_error], layout=w.Layout(display="none"))
        self.widget = w.VBox([self.table, self.choice_box])

    def show(self, entry: MapEntry | None) -> threading.Thread | None:
        """Show the storeys of ``entry``: at once if known, else read in a thread (returned)."""
        with self._lock:
            self._generation += 1
            generation = self._generation
        self.name = entry.name if entry is not None else None
        self.storeys = None
        self.choice_error.value = ""
        self._set_choices([])
        if entry is None:
            self.table.value = ""
            return None
        known = self.ctx.maps.cached_storeys(entry.name)
        if known is not None:
            self._fill(known)
            return None
        self.table.value = "<i>reading storeys...</i>"

        def done(storeys: list[StoreyInfo]) -> None:
            if generation != self._generation:
                return  # another map was selected meanwhile
            self._fill(storeys)
            if self.on_loaded is not None:
                self.on_loaded(entry.name)

        def failed(err: BaseException) -> None:
            if generation == self._generation:
                self.table.value = f"<span class='pmk-field-error'>Cannot read the storeys: {escape(err)}</span>"

        return run_in_thread(
            self.ctx, "Reading storeys", lambda: self.ctx.maps.storeys(entry.name), on_done=done, on_error=failed
        )

    def _fill(self, storeys: list[StoreyInfo]) -> None:
        """The storeys' checkboxes, then their table: once the table shows them (from the reading
        thread), the checkboxes to choose among them are there too."""
        self.storeys = list(storeys)
        self._set_choices(storeys if len(storeys) > 1 else [])
        if not storeys:
            self.table.value = "<i>No storeys with cells in this file.</i>"
        else:
            self.table.value = storeys_table(storeys, self.unit) + unit_warning(storeys)

    def layers(self) -> tuple[LayerOption, ...]:
        """The plan's layers with cells (the same for every storey), () while its storeys are unknown."""
        return self.storeys[0].layers if self.storeys else ()

    def set_unit(self, unit: str) -> None:
        """Show the sizes the plan has when read in ``unit`` (the Maps screen's unit choice)."""
        self.unit = unit
        if self.storeys:
            self.table.value = storeys_table(self.storeys, unit) + unit_warning(self.storeys)

    def _set_choices(self, storeys: list[StoreyInfo]) -> None:
        boxes = [
            checkbox(self.ctx, s.name, True, "pmk-maps-storey-check", "Choosing storeys", self._on_check)
            for s in storeys
        ]
        replace_children(self.choices, boxes)
        self.choice_box.layout.display = "flex" if boxes else "none"

    def _on_check(self, change: dict[str, Any]) -> None:
        if not isinstance(change.get("new"), bool):
            raise LibraryError("A storey checkbox must be on or off.")
        self.choice_error.value = "" if self._checked() else "Tick at least one storey to convert."

    def _checked(self) -> list[str]:
        return [str(b.description) for b in self.choices.children if isinstance(b, w.Checkbox) and b.value is True]

    def check(self, names: list[str]) -> None:
        """Tick exactly the storeys ``names`` (what clicking the checkboxes does)."""
        tick_exactly(self.choices.children, names, "No storey {unknown} in this map (storeys: {known}).")

    def selected(self) -> list[str] | None:
        """Storey names to convert, None for all (also while storeys are unknown).

        Raises:
            LibraryError: none ticked, or a ticked name that is not a storey of the shown map.
        """
        if self.storeys is None or len(self.storeys) < 2:
            return None
        checked = self._checked()
        if not checked:
            self.choice_error.value = "Tick at least one storey to convert."
            raise LibraryError("Tick at least one storey to convert.")
        names = {s.name for s in self.storeys}
        if any(c not in names for c in checked):
            raise LibraryError("The storey list changed: select the map again.")
        self.choice_error.value = ""
        return None if len(checked) == len(names) else checked
