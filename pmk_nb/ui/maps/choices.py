"""The Maps screen's conversion choices: the plan's unit, the layers to draw, the cells that are not windows.

Both answer something the converter can only guess: a file in an editor's own unit, and a door the
window/sill rule took for a window (the accessibility panel names those cells). A kiosk user has no
command line, so the screen offers what ``pmk convert --unit`` and ``--not-window`` do. The last
conversion's choices come back from the map's rooms files (:mod:`pmk_nb.library.choices`), so
converting again keeps them.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any

import ipywidgets as w

from pmk_nb.errors import LibraryError
from pmk_nb.indoorgml import UNIT_CHOICES
from pmk_nb.library import ConvertChoices, last_choices, offered, window_cells
from pmk_nb.ui.common.style import TOUCH_PX
from pmk_nb.ui.common.widgets import checkbox, escape, field_error, guard, replace_children, tick_exactly

if TYPE_CHECKING:
    from pmk_nb.library import LayerOption, MapEntry
    from pmk_nb.ui.common.context import AppContext

UNIT_LABELS = {
    "auto": "auto (from sizes)",
    "m": "metres",
    "dm": "decimetres",
    "cm": "centimetres",
    "mm": "millimetres",
}
LAYERS_HELP = (
    "The navigation graph's layer is drawn; thematic layers (zones, sensors) are not, or their outlines "
    "would become walls across rooms. Tick the layers to draw instead, then Convert."
)
WINDOWS_HELP = (
    "These cells were taken for windows or sills from their height. Tick any that is really a door or "
    "floor, then Convert: it stays navigable and its passages are checked."
)


class ChoicesPanel:
    """Unit and not-window choices for the selected map; ``choices()`` is what Convert uses."""

    def __init__(self, ctx: AppContext, on_unit: Callable[[str], None] | None = None) -> None:
        self.ctx = ctx
        self.on_unit = on_unit  # told each valid unit chosen (the storeys table shows the sizes it gives)
        self.unit = w.Dropdown(
            options=[(UNIT_LABELS[u], u) for u in UNIT_CHOICES],
            value="auto",
            description="Plan's unit",
            style={"description_width": "180px"},
            layout=w.Layout(width="100%", max_width="420px", height=f"{TOUCH_PX - 8}px"),
        )
        self.unit.add_class("pmk-maps-unit")
        self.unit.observe(guard(ctx, "Choosing the unit")(self._on_unit), names="value")
        self.unit_error = field_error()
        self.windows_help = w.HTML(f"<div><b>Not windows</b><br>{escape(WINDOWS_HELP)}</div>")
        self.windows = w.VBox([])
        self.windows.add_class("pmk-maps-not-windows")
        self.windows_box = w.VBox([self.windows_help, self.windows], layout=w.Layout(display="none"))
        self.layers_help = w.HTML(f"<div><b>Layers to draw</b><br>{escape(LAYERS_HELP)}</div>")
        self.layers = w.VBox([])
        self.layers.add_class("pmk-maps-layers")
        self.layers_error = field_error()
        self.layers_box = w.VBox([self.layers_help, self.layers, self.layers_error], layout=w.Layout(display="none"))
        self.widget = w.VBox(
            [self.unit, self.unit_error, self.layers_box, self.windows_box], layout=w.Layout(width="100%")
        )
        self._shown: tuple[object, ...] | None = None  # (map name, its last choices, the cells offered)
        self._layers: tuple[str, ...] = ()  # the layers the last conversion drew (--layer), kept as they were
        self._auto: tuple[str, ...] = ()  # the layers the converter draws when none is asked for
        self._offered: tuple[LayerOption, ...] | None = None  # None: nothing offered yet for this map
        self._crs = "auto"  # the frame the last conversion read the coordinates in (--crs), kept as it was

    def show(self, entry: MapEntry | None, docs: list[dict[str, Any] | None]) -> None:
        """The choices of ``entry``'s last conversion, and the cells its reports took for windows (``docs``:
        the rooms files of its generated maps). Shown again for the same map and the same conversion (a
        refresh), what the user changed since stays."""
        last = last_choices(docs)
        offer = offered(last, window_cells(docs))
        shown = (entry.name if entry is not None else None, last, offer)
        if shown == self._shown:
            return
        self._shown = shown
        self._layers = last.layers  # chosen here or by `pmk maps convert --layer`: kept when converting again
        self._crs = last.crs  # given by `pmk maps convert --crs`: kept when converting again
        self._offered = None  # a new map or conversion: its layers are offered afresh
        self.set_layers(())
        self.unit.value = last.unit
        self.unit_error.value = ""
        action = "Choosing cells that are not windows"
        boxes = [checkbox(self.ctx, n, ticked, "pmk-maps-not-window", action, self._on_tick) for n, ticked in offer]
        replace_children(self.windows, boxes)
        self.windows_box.layout.display = "flex" if boxes else "none"

    def set_layers(self, options: Sequence[LayerOption]) -> None:
        """Offer the plan's layers with cells when it has more than one (``options``, from its storeys): ticked
        are those the last conversion drew (asked for), else those the converter draws by itself. The same
        options again (a refresh) keep what the user ticked since."""
        if tuple(options) == self._offered:
            return
        self._offered = tuple(options)
        self._auto = tuple(o.id for o in options if o.drawn)
        ticked = set(self._layers) or set(self._auto)
        action = "Choosing the layers to draw"
        boxes = (
            [checkbox(self.ctx, o.id, o.id in ticked, "pmk-maps-layer", action, self._on_layer) for o in options]
            if len(options) > 1
            else []
        )
        replace_children(self.layers, boxes)
        self.layers_error.value = ""
        self.layers_box.layout.display = "flex" if boxes else "none"

    def _ticked_layers(self) -> list[str]:
        return [str(b.description) for b in self.layers.children if isinstance(b, w.Checkbox) and b.value is True]

    def _on_layer(self, change: dict[str, Any]) -> None:
        if not isinstance(change.get("new"), bool):
            raise LibraryError("A layer box must be ticked or not.")
        self.layers_error.value = "" if self._ticked_layers() else "Tick at least one layer to draw."

    def tick_layers(self, ids: list[str]) -> None:
        """Tick exactly the layers ``ids`` (what clicking their boxes does)."""
        tick_exactly(self.layers.children, ids, "No layer {unknown} in this plan (layers: {known}).")

    def _chosen_layers(self) -> tuple[str, ...]:
        """The layers to ask for: none when the boxes say what the converter draws by itself."""
        if not self.layers.children:
            return self._layers
        ticked = self._ticked_layers()
        if not ticked:
            self.layers_error.value = "Tick at least one layer to draw."
            raise LibraryError("Tick at least one layer to draw.")
        return () if set(ticked) == set(self._auto) else tuple(ticked)

    def _valid_unit(self, unit: object) -> str:
        """``unit`` if it is one of the list, else the error said under the field and raised."""
        if unit not in UNIT_CHOICES:
            self.unit_error.value = "Choose a unit from the list."
            raise LibraryError(f"Unknown unit {unit!r}: choose one of {', '.join(UNIT_CHOICES)}.")
        self.unit_error.value = ""
        return str(unit)

    def _on_unit(self, change: dict[str, Any]) -> None:
        unit = self._valid_unit(change.get("new"))
        if self.on_unit is not None:
            self.on_unit(unit)

    def _on_tick(self, change: dict[str, Any]) -> None:
        if not isinstance(change.get("new"), bool):
            raise LibraryError("A not-a-window box must be ticked or not.")

    def tick(self, names: list[str]) -> None:
        """Tick exactly the cells ``names`` (what clicking their boxes does)."""
        tick_exactly(self.windows.children, names, "No cell {unknown} is offered as not a window (offered: {known}).")

    def choices(self) -> ConvertChoices:
        """What to convert with, checked again here: a page can set any synced value.

        Raises:
            LibraryError: a unit that is not one of the list; no layer ticked.
        """
        unit = self._valid_unit(self.unit.value)
        ticked = [str(b.description) for b in self.windows.children if isinstance(b, w.Checkbox) and b.value is True]
        return ConvertChoices(unit, tuple(ticked), self._chosen_layers(), self._crs)
