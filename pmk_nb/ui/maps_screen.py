"""Maps screen: the maps folder (list, import, download), conversion to ROS maps, sending to the chair.

Mirrors the original's two tabs (thesis 5.2.3.3): the list of available IndoorGML maps with a
resolution and Convert ("parse") button, and once converted a preview and a Send button per storey;
and a Download tab (URL + name).  Sending a map makes it the Home screen's current map.  Slow work
runs in a thread with a progress bar; every failure becomes a message in the page.
"""

from __future__ import annotations

import math
import tempfile
import threading
from pathlib import Path
from typing import TYPE_CHECKING, Any

import ipywidgets as w

from pmk_nb.errors import GridTooLarge, LibraryError, PmkError
from pmk_nb.ui.maps_cards import generated_card, map_label
from pmk_nb.ui.maps_download import DownloadPanel
from pmk_nb.ui.maps_storeys import StoreysPanel
from pmk_nb.ui.widgets import (
    ConfirmBox,
    button,
    escape,
    field_error,
    guard,
    heading,
    progress_bar,
    progress_callback,
    run_in_thread,
    set_progress,
    show_failure,
    text,
)

if TYPE_CHECKING:
    from pmk_nb.library.folder import GeneratedMap, MapEntry
    from pmk_nb.ui.context import AppContext

DEFAULT_RESOLUTION = 0.05
MAX_RESOLUTION = 1.0
CONNECT_TIMEOUT = 10.0
UPLOAD_MAX_BYTES = 200 * 1024 * 1024


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
        # -- list tab --
        self.map_list = w.Select(options=[], rows=10, layout=w.Layout(width="97%", height="420px"))
        self.map_list.add_class("pmk-maps-list")
        self.map_list.observe(guard(ctx, "Selecting a map")(self._on_select), names="value")
        self.refresh_button = button("Refresh", "pmk-maps-refresh", icon="refresh")
        self.refresh_button.on_click(guard(ctx, "Refreshing the maps list")(lambda _b: self.refresh()))
        self.upload = w.FileUpload(accept=".gml,.xml", multiple=False, description="Import IndoorGML")
        self.upload.layout = w.Layout(height="56px", width="auto")
        self.upload.add_class("pmk-maps-import")
        self.upload.observe(guard(ctx, "Importing a map")(self._on_upload), names="value")
        self.import_confirm = ConfirmBox(ctx, "pmk-maps-import-confirm")
        left = w.VBox(
            [self.map_list, w.HBox([self.refresh_button, self.upload]), self.import_confirm.widget],
            layout=w.Layout(width="40%", min_width="300px"),
        )
        self.title = heading("Select a map")
        self.details = w.HTML("")
        self.details.add_class("pmk-maps-details")
        self.resolution = text(f"{DEFAULT_RESOLUTION}", "Resolution (m/cell)", "pmk-maps-resolution")
        self.resolution.layout.width = "360px"
        self.resolution.style.description_width = "180px"
        self.resolution_error = field_error()
        self.convert_button = button("Convert", "pmk-maps-convert", icon="cogs", style="primary")
        self.convert_button.on_click(guard(ctx, "Converting")(lambda _b: self.convert()))
        self.convert_progress = progress_bar("pmk-maps-convert-progress")
        self.generated_box = w.VBox([])
        self.generated_box.add_class("pmk-maps-generated")
        self.send_progress = progress_bar("pmk-maps-send-progress")
        self.password = text("", "SSH password", "pmk-maps-password", password=True)
        self.password_ok = button("Send", "pmk-maps-password-ok", icon="paper-plane", style="primary")
        self.password_box = w.VBox(
            [w.HTML("The chair asks for an SSH password:"), self.password, self.password_ok],
            layout=w.Layout(display="none"),
        )
        self.password_box.add_class("pmk-confirm")
        self.password_ok.on_click(guard(ctx, "Sending")(lambda _b: self._password_entered()))
        self._pending_send: GeneratedMap | None = None
        self.status = w.HTML("")
        self.status.add_class("pmk-maps-status")
        self.storeys_panel = StoreysPanel(ctx, on_loaded=lambda _name: self._relabel())
        self.convert_row = w.VBox(
            [
                self.storeys_panel.widget,
                self.resolution,
                self.resolution_error,
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
                self.password_box,
                self.send_progress,
                self.status,
            ],
            layout=w.Layout(width="60%", padding="0 0 0 16px"),
        )
        self.convert_row.layout.display = "none"
        list_tab = w.HBox([left, right], layout=w.Layout(width="100%"))
        self.downloader = DownloadPanel(ctx, on_downloaded=lambda _entry: self.refresh())
        self.tabs = w.Tab(children=[list_tab, self.downloader.widget], titles=("Maps", "Download"))
        self.tabs.add_class("pmk-maps-tabs")
        self.widget = w.VBox([self.tabs], layout=w.Layout(width="100%"))
        self.widget.add_class("pmk-maps")
        self.refresh()

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
            self.generated_box.children = ()
            self.storeys_panel.show(None)
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
        self.generated_box.children = tuple(self._generated_card(g, several) for g in entry.generated)

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
    def convert(self) -> Any:
        """Convert the selected map at the typed resolution (in a thread); returns the thread."""
        entry = self._selected()
        storeys = self.storeys_panel.selected() if self.storeys_panel.name == entry.name else None
        try:
            resolution = parse_resolution(self.resolution.value)
        except ValueError as err:
            self.resolution_error.value = escape(err)
            self.ctx.notify(str(err), "warning")
            return None
        self.resolution_error.value = ""
        set_progress(self.convert_progress, 0.0)
        which = f" (storeys {', '.join(storeys)})" if storeys else ""
        self.status.value = f"Converting {escape(entry.name)}{escape(which)} at {resolution:g} m…"

        def work() -> list[GeneratedMap]:
            return self.ctx.maps.convert(
                entry.name, resolution, storeys=storeys, progress=progress_callback(self.convert_progress, self.status)
            )

        def done(generated: list[GeneratedMap]) -> None:
            self.refresh()
            set_progress(self.convert_progress, 1.0, style="success")
            what = f"{len(generated)} storeys" if len(generated) > 1 else "ready to send"
            self.status.value = f"Converted {escape(entry.name)} at {resolution:g} m: {what}."
            self.ctx.notify(f"Converted {entry.name} at {resolution:g} m.")

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
        """Red bar and message; a grid too large for the resolution gets the way out under the field."""
        show_failure(self.convert_progress, self.status)(err)
        cause = err if isinstance(err, GridTooLarge) else err.__cause__
        if isinstance(cause, GridTooLarge):
            self.resolution_error.value = escape(
                f"Too fine for this building: use {cause.suggested_resolution:g} m per cell or coarser."
            )

    # -- send --------------------------------------------------------------------------------------
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
        set_progress(self.send_progress, 0.0)
        name = Path(gm.yaml).stem
        self.status.value = f"Sending {escape(name)} to {escape(profile.name)}…"

        def work() -> Any:
            from pmk_nb.chair.deploy import deploy
            from pmk_nb.rosmap.files import MapFiles

            files = MapFiles(yaml=Path(gm.yaml), image=Path(gm.image), preview=gm.preview)
            link = self.ctx.link()
            if not link.is_connected:
                link.connect(timeout=CONNECT_TIMEOUT)
            return deploy(
                files,
                profile,
                password=password,
                link=link,
                progress=progress_callback(self.send_progress, self.status),
            )

        def done(_report: Any) -> None:
            set_progress(self.send_progress, 1.0, style="success")
            # the message first: whoever sees the new current map also sees the final status
            self.status.value = f"Sent {escape(name)}: the chair now uses it; it is the current map on Home."
            self.ctx.set_current_map(name, gm.yaml, gm.preview)
            self.ctx.notify(f"Sent {name} to {profile.name}.")
            self._update_info()

        return run_in_thread(
            self.ctx,
            "Sending",
            work,
            on_done=done,
            on_error=show_failure(self.send_progress, self.status),
            busy=[*self._send_buttons(), self.convert_button],
            exclusive=self._files_lock,
        )

    def _send_buttons(self) -> list[w.Button]:
        return _buttons_in(self.generated_box)

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
    def _on_upload(self, change: dict[str, Any]) -> None:
        files = change.get("new") or ()
        if not files:
            return
        item = files[0]
        filename = Path(str(item.get("name", "upload.gml"))).name
        content = item.get("content", b"")
        data = content.tobytes() if isinstance(content, memoryview) else bytes(content)
        if len(data) > UPLOAD_MAX_BYTES:
            raise LibraryError(
                f"{filename} is larger than {UPLOAD_MAX_BYTES // 2**20} MiB; copy it into the maps folder instead."
            )
        self.upload.value = ()  # so the same file can be chosen again
        self.import_bytes(filename, data)

    def import_bytes(self, filename: str, data: bytes, *, overwrite: bool = False) -> MapEntry | None:
        """Store an uploaded file in the maps folder (asks before replacing a map of the same name)."""
        name = Path(filename).stem
        if not overwrite and self.ctx.maps.exists(name):
            self.import_confirm.ask(
                f"A map named '{name}' exists. Replace it with {filename}?",
                lambda: self.import_bytes(filename, data, overwrite=True),
            )
            return None
        with tempfile.TemporaryDirectory(prefix="pmk-upload-") as tmp:
            path = Path(tmp) / Path(filename).name
            path.write_bytes(data)
            entry = self.ctx.maps.import_file(path, name=name, overwrite=overwrite)
        self.ctx.notify(f"Imported {entry.name}.")
        self.refresh()
        self.map_list.value = entry.name
        return entry

    def close(self) -> None:
        self.widget.close()


def _buttons_in(widget: w.Widget) -> list[w.Button]:
    if isinstance(widget, w.Button):
        return [widget]
    return [b for child in getattr(widget, "children", ()) for b in _buttons_in(child)]
