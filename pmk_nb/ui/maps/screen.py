"""Maps screen: the maps folder (list, import, download), conversion to ROS maps, sending to the chair.

Mirrors the original's two tabs (thesis 5.2.3.3): the IndoorGML maps with a resolution and Convert
("parse"), once converted a preview and a Send button per storey; and a Download tab (URL + name);
the Catalogue tab (``catalogue``) installs buildings from STAC map catalogues.
Sending a map makes it Home's current map. Slow work runs in a thread; every failure becomes a message.
"""

from __future__ import annotations

import math
import threading
from pathlib import Path
from typing import TYPE_CHECKING, Any

import ipywidgets as w

from pmk_nb.access import profile_chair_width, sidecar_doc
from pmk_nb.defaults import DEFAULT_RESOLUTION
from pmk_nb.errors import GridTooLarge, LibraryError, PmkError
from pmk_nb.library import ConvertOptions
from pmk_nb.ui.common.context import needs_pin
from pmk_nb.ui.common.widgets import (
    button,
    buttons_in,
    escape,
    field_error,
    guard,
    heading,
    progress_bar,
    progress_callback,
    replace_children,
    run_in_thread,
    set_progress,
    show_failure,
    text,
    too_fine_text,
)
from pmk_nb.ui.maps.access import AccessPanel
from pmk_nb.ui.maps.cards import generated_card, map_label
from pmk_nb.ui.maps.catalogue import CataloguePanel
from pmk_nb.ui.maps.choices import ChoicesPanel
from pmk_nb.ui.maps.download import DownloadPanel
from pmk_nb.ui.maps.importer import ImportPanel
from pmk_nb.ui.maps.storeys import StoreysPanel
from pmk_nb.ui.maps.witness import WitnessPanel
from pmk_nb.ui.settings.host_key_prompt import HostKeyPrompt, strict

if TYPE_CHECKING:
    from pmk_nb.library import GeneratedMap, MapEntry
    from pmk_nb.ui.common.context import AppContext

MAX_RESOLUTION = 1.0
CONNECT_TIMEOUT = 10.0


def parse_resolution(raw: object) -> float:
    """Metres per cell from user input; raises ValueError with a message fit for the page."""
    try:
        value = float(str(raw).strip().replace(",", "."))
    except ValueError:
        raise ValueError(f"Resolution {raw!r} is not a number: type metres per cell, e.g. 0.05.") from None
    if not math.isfinite(value) or value <= 0:
        raise ValueError(f"Resolution must be a positive number of metres per cell (got {raw!r}).")
    if value > MAX_RESOLUTION:
        raise ValueError(f"Resolution {value:g} m is too coarse for navigation: use at most {MAX_RESOLUTION:g} m.")
    return value


class MapsScreen:
    """The Maps screen; ``widget`` is its content, ``info_widget`` its part of the info panel."""

    def __init__(self, ctx: AppContext) -> None:
        self.ctx = ctx
        self.entries: dict[str, MapEntry] = {}
        self._quiet = False
        # convert and send touch the same files: one at a time; downloads have their own lock
        self._files_lock = threading.Lock()
        self.info_widget = w.HTML("")
        self.info_widget.add_class("pmk-maps-info")
        left = self._list_column()
        self.title = heading("Select a map")
        self.details = w.HTML("")
        self.details.add_class("pmk-maps-details")
        self.resolution = text(f"{DEFAULT_RESOLUTION}", "Resolution (m/cell)", "pmk-maps-resolution")
        self.resolution.layout.max_width = "420px"
        self.resolution.style.description_width = "180px"
        self.resolution_error = field_error()
        self.convert_button = button("Convert", "pmk-maps-convert", icon="cogs", style="primary")
        self.convert_button.on_click(guard(ctx, "Converting")(lambda _b: self.convert()))
        self.convert_progress = progress_bar("pmk-maps-convert-progress")
        self.generated_box = w.VBox([])
        self.generated_box.add_class("pmk-maps-generated")
        self.send_progress = progress_bar("pmk-maps-send-progress")
        self.password_box = self._password_box()
        self._pending_send: GeneratedMap | None = None
        self.status = w.HTML("")
        self.status.add_class("pmk-maps-status")
        self.host_key = HostKeyPrompt(ctx, self.send_progress, self.status)  # first SSH host key (issue 30)
        self.storeys_panel = StoreysPanel(ctx, on_loaded=self._storeys_loaded)
        self.access_panel = AccessPanel()  # wheelchair access of the converted storeys
        self.witness_panel = WitnessPanel(ctx)  # the written map judged against the plan (issue 37)
        self.choices = ChoicesPanel(ctx, on_unit=self.storeys_panel.set_unit)  # the plan's unit, not-windows
        self.convert_row = w.VBox(
            [
                self.storeys_panel.widget,
                self.resolution,
                self.resolution_error,
                self.choices.widget,
                self.convert_button,
                self.convert_progress,
            ],
            layout=w.Layout(align_items="flex-start", width="100%"),
        )
        right = w.VBox(
            [
                self.title,
                self.details,
                self.convert_row,
                self.generated_box,
                self.access_panel.widget,
                self.witness_panel.widget,
                self.password_box,
                self.host_key.widget,
                self.send_progress,
                self.status,
            ],
        )
        right.add_class("pmk-maps-right")
        self.convert_row.layout.display = "none"
        # two columns side by side when they fit, else the details below the list (pmk-maps-listtab)
        list_tab = w.Box([left, right])
        list_tab.add_class("pmk-maps-listtab")
        self.downloader = DownloadPanel(ctx, on_downloaded=lambda _entry: self.refresh())
        self.catalogue = CataloguePanel(ctx, on_installed=lambda _result: self.refresh())  # issue 27
        tabs = [list_tab, self.downloader.widget, self.catalogue.widget]
        self.tabs = w.Tab(children=tabs, titles=("Maps", "Download", "Catalogue"))
        self.tabs.add_class("pmk-maps-tabs")
        self.widget = w.VBox([self.tabs], layout=w.Layout(width="100%"))
        self.widget.add_class("pmk-maps")
        self.refresh()

    def _list_column(self) -> w.VBox:
        """The maps list, Refresh and Import (sizes in the style sheet: a shorter list on a phone)."""
        ctx = self.ctx
        self.map_list = w.Select(options=[], rows=10, layout=w.Layout(width="100%"), tooltip="Maps in the folder")
        self.map_list.add_class("pmk-maps-list")
        self.map_list.observe(guard(ctx, "Selecting a map")(self._on_select), names="value")
        self.refresh_button = button("Refresh", "pmk-maps-refresh", icon="refresh")
        self.refresh_button.on_click(guard(ctx, "Refreshing the maps list")(lambda _b: self.refresh()))
        self.importer = ImportPanel(ctx, on_imported=self._imported)
        self.upload = self.importer.upload
        self.import_confirm = self.importer.confirm
        buttons = w.HBox([self.refresh_button, self.upload])
        buttons.add_class("pmk-row")
        left = w.VBox([self.map_list, buttons, self.import_confirm.widget, self.importer.status])
        left.add_class("pmk-maps-left")
        return left

    def _password_box(self) -> w.VBox:
        """Asks for the SSH password when Send needs one (the status line says why, not this box)."""
        self.password = text("", "SSH password", "pmk-maps-password", password=True)
        self.password_ok = button("Send", "pmk-maps-password-ok", icon="paper-plane", style="primary")
        self.password_ok.on_click(guard(self.ctx, "Sending")(lambda _b: self._password_entered()))
        box = w.VBox(
            [w.HTML("The chair asks for an SSH password:"), self.password, self.password_ok],
            layout=w.Layout(display="none"),
        )
        box.add_class("pmk-confirm")
        return box

    # -- list --------------------------------------------------------------------------------------
    def on_show(self) -> None:
        self.refresh()

    def refresh(self) -> None:
        """Re-read the maps folder, keeping the selection when the map still exists."""
        selected = self.map_list.value
        try:
            entries = self.ctx.maps.list()
        except PmkError as err:
            self.ctx.notify(f"Cannot list the maps folder: {err}", "error")
            entries = []
        self.entries = {e.name: e for e in entries}
        self._relabel(select=selected if selected in self.entries else None)
        if selected in self.entries:
            self._show_entry(self.entries[selected])
        else:
            self.map_list.value = None
            self._show_entry(None)
        self._update_info()

    def _relabel(self, select: str | None = None) -> None:
        """Rebuild the list's labels (storey counts arrive later than the list) keeping the selection."""
        keep = self.map_list.value if select is None else select
        self._quiet = True  # setting options fires value changes that are not the user's
        try:
            self.map_list.options = [
                (map_label(e, self.ctx.maps.cached_storeys(e)), e.name) for e in self.entries.values()
            ]
            self.map_list.value = keep if keep in self.entries else None
        finally:
            self._quiet = False

    def select(self, name: str) -> None:
        """Select a map by name (what tapping the list does)."""
        if name not in self.entries:
            raise LibraryError(f"No map named {name!r} in {self.ctx.maps.root}.")
        self.map_list.value = name

    def _on_select(self, change: dict[str, Any]) -> None:
        name = change.get("new")
        if self._quiet:
            return
        if name is not None and not isinstance(name, str):
            raise LibraryError("Unknown map selected.")
        self._show_entry(self.entries.get(name) if name else None)

    def _show_entry(self, entry: MapEntry | None) -> None:
        self.status.value = ""
        self.password_box.layout.display = "none"
        if entry is None:
            self.title.value = "<div class='pmk-heading'>Select a map</div>"
            self.details.value = "<p>Tap a map in the list, or import / download one.</p>"
            self.convert_row.layout.display = "none"
            replace_children(self.generated_box, ())
            self.storeys_panel.show(None)
            self.access_panel.show(None, [])
            self.witness_panel.show(None, [])
            self.choices.show(None, [])
            return
        self.title.value = f"<div class='pmk-heading'>{escape(entry.name)}</div>"
        size_kb = entry.size / 1024
        lines = [f"IndoorGML file: {escape(Path(entry.source).name)} ({size_kb:,.0f} KiB)"]
        if entry.generated:
            lines.append(f"Generated maps: {len(entry.generated)}")
        else:
            lines.append("Not converted yet: choose a resolution and press Convert.")
        self.details.value = "<br>".join(lines)
        self.convert_row.layout.display = "flex"
        self.storeys_panel.show(entry)
        known = self.ctx.maps.cached_storeys(entry)  # one storey of several converted: still say which
        several = len(entry.generated) > 1 or (known is not None and len(known) > 1)
        replace_children(self.generated_box, [self._generated_card(g, several) for g in entry.generated])
        docs = [sidecar_doc(g.yaml) for g in entry.generated]  # the rooms files, read once for the panels
        self.access_panel.show(entry, docs)
        self.witness_panel.show(entry, docs)
        self.choices.show(entry, docs)
        self.choices.set_layers(self.storeys_panel.layers())  # when the storeys are known at once

    def _storeys_loaded(self, _name: str) -> None:
        """Storeys read in the background arrived for the map shown: relabel the list, offer its layers."""
        self._relabel()
        self.choices.set_layers(self.storeys_panel.layers())

    def _generated_card(self, gm: GeneratedMap, several: bool) -> w.Widget:
        return generated_card(self.ctx, gm, several, self.send)

    def _selected(self) -> MapEntry:
        name = self.map_list.value
        if not isinstance(name, str) or name not in self.entries:
            raise LibraryError("Select a map in the list first.")
        return self.entries[name]

    def _update_info(self) -> None:
        current = self.ctx.current_map
        cur = escape(current.name) if current else "none yet"
        self.info_widget.value = f"<div>Maps: {len(self.entries)}</div><div>Current map: <b>{cur}</b></div>"

    # -- convert -----------------------------------------------------------------------------------
    @needs_pin("Converting")
    def convert(self) -> Any:
        """Convert the selected map at the typed resolution (in a thread); returns the thread."""
        entry = self._selected()
        storeys = self.storeys_panel.selected() if self.storeys_panel.name == entry.name else None
        # a new attempt: the previous attempt's messages go, whatever this one says
        self.status.value = ""
        set_progress(self.convert_progress, None)
        try:
            resolution = parse_resolution(self.resolution.value)
        except ValueError as err:
            self.resolution_error.value = escape(err)  # one place: under the field
            self.ctx.notify(str(err), "warning", inline=True)
            return None
        self.resolution_error.value = ""
        choices = self.choices.choices()
        set_progress(self.convert_progress, 0.0)
        which = f" (storeys {', '.join(storeys)})" if storeys else ""
        self.status.value = f"Converting {escape(entry.name)}{escape(which)} at {resolution:g} m…"

        options = ConvertOptions(  # passed whole; every other setting is pmk_nb.defaults'
            resolution=resolution,
            storeys=storeys,
            chair_width=profile_chair_width(None, self.ctx.profile()),  # Settings: the chair's width
            unit=choices.unit,
            not_windows=tuple(choices.not_windows),
            layers=tuple(choices.layers),
            crs=choices.crs,
        )

        def work() -> list[GeneratedMap]:
            progress = progress_callback(self.convert_progress, self.status)
            return self.ctx.maps.convert_with(entry.name, options, progress=progress)

        def done(generated: list[GeneratedMap]) -> None:
            self.refresh()
            set_progress(self.convert_progress, None)
            what = f"{len(generated)} storeys" if len(generated) > 1 else "ready to send"
            self.status.value = f"Converted {escape(entry.name)} at {resolution:g} m: {what}."
            self.ctx.notify(f"Converted {entry.name} at {resolution:g} m.", inline=True)

        return run_in_thread(
            self.ctx,
            "Converting",
            work,
            on_done=done,
            on_error=self._convert_failed,
            busy=[self.convert_button],
            exclusive=self._files_lock,
        )

    def _convert_failed(self, err: BaseException) -> None:
        """The message in one place: a grid too large for the resolution under the field, else the status."""
        cause = err if isinstance(err, GridTooLarge) else err.__cause__
        if isinstance(cause, GridTooLarge):
            set_progress(self.convert_progress, None)
            self.status.value = ""
            self.resolution_error.value = escape(too_fine_text(cause))
            return
        show_failure(self.convert_progress, self.status)(err)

    # -- send --------------------------------------------------------------------------------------
    @needs_pin("Sending")
    def send(self, gm: GeneratedMap, password: str | None = None) -> Any:
        """Upload a generated map to the chair, reload it there and make it the current map."""
        profile = self.ctx.profile()
        if profile is None:
            raise PmkError("No wheelchair configured: fill in and save the Settings screen first.")
        if profile.auth == "password":
            password = password or self.ctx.ssh_password(profile)
            if not password:
                self._pending_send = gm
                self.password.value = ""
                self.password_box.layout.display = "flex"
                self.status.value = "Enter the chair's SSH password to send."
                return None
        self.password_box.layout.display = "none"
        self.resolution_error.value = ""  # the convert attempt's advice is over
        set_progress(self.send_progress, 0.0)
        name = Path(gm.yaml).stem
        self.status.value = f"Sending {escape(name)} to {escape(profile.name)}…"
        failed = show_failure(self.send_progress, self.status)

        def work() -> Any:
            from pmk_nb.chair.deploy import deploy
            from pmk_nb.rosmap import MapFiles

            files = MapFiles(yaml=Path(gm.yaml), image=Path(gm.image), preview=gm.preview)
            link = self.ctx.link()
            if not link.is_connected:
                link.connect(timeout=CONNECT_TIMEOUT)
            progress = progress_callback(self.send_progress, self.status)
            # strict: an unknown host key stops before the upload, for self.host_key to ask
            return deploy(files, strict(profile), password=password, link=link, progress=progress)

        def done(_report: Any) -> None:
            set_progress(self.send_progress, None)
            # the message first: whoever sees the new current map also sees the final status
            self.status.value = f"Sent {escape(name)}: the chair now uses it; it is the current map on Home."
            self.ctx.set_current_map(name, gm.yaml, gm.preview)
            self.ctx.notify(f"Sent {name} to {profile.name}.", inline=True)
            self._update_info()

        return run_in_thread(
            self.ctx,
            "Sending",
            work,
            on_done=done,
            on_error=lambda err: self.host_key.ask(err, lambda: self.send(gm, password)) or failed(err),
            busy=[*self._send_buttons(), self.convert_button],
            exclusive=self._files_lock,
        )

    def _send_buttons(self) -> list[w.Button]:
        return buttons_in(self.generated_box)

    @needs_pin("Sending")  # it also stores the password
    def _password_entered(self) -> Any:
        gm = self._pending_send
        password = self.password.value
        if gm is None:
            raise PmkError("Nothing to send: press Send next to a map.")
        if not isinstance(password, str) or not password:
            raise PmkError("Type the SSH password first.")
        profile = self.ctx.profile()
        if profile is not None:
            self.ctx.profiles.set_password(profile, password)
        self._pending_send = None
        self.password.value = ""
        return self.send(gm, password=password)

    # -- import ------------------------------------------------------------------------------------
    def import_bytes(self, filename: str, data: bytes, *, overwrite: bool = False) -> MapEntry | None:
        """Store an uploaded file in the maps folder (asks before replacing a map of the same name)."""
        return self.importer.import_bytes(filename, data, overwrite=overwrite)

    def _imported(self, entry: MapEntry) -> None:
        self.refresh()
        self.map_list.value = entry.name

    def close(self) -> None:
        self.widget.close()
