"""The Maps screen's Download tab: fetch an IndoorGML file by URL into the maps folder.

As in the original (thesis 5.2.3.3): a URL and a name, then Download.  Replacing a map of the same
name needs an explicit confirmation in the page; an unreachable URL or a file that is not
IndoorGML is explained (the library's message), never a traceback.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import TYPE_CHECKING

import ipywidgets as w

from pmk_nb.errors import AlreadyExists
from pmk_nb.ui.common.context import needs_pin
from pmk_nb.ui.common.widgets import (
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
    from pmk_nb.library import MapEntry
    from pmk_nb.ui.common.context import AppContext


class DownloadPanel:
    """URL + name form with progress; ``on_downloaded(entry)`` runs after a successful download."""

    def __init__(self, ctx: AppContext, on_downloaded: Callable[[MapEntry], None]) -> None:
        self.ctx = ctx
        self._on_downloaded = on_downloaded
        self._lock = threading.Lock()
        self.url = text("", "URL", "pmk-maps-url", placeholder="https://server/maps/building.gml")
        self.name = text("", "Name", "pmk-maps-name", placeholder="e.g. clinic")
        self.error = field_error()
        self.button = button("Download", "pmk-maps-download", icon="download", style="primary")
        self.button.on_click(guard(ctx, "Downloading")(lambda _b: self.download()))
        self.confirm = ConfirmBox(ctx, "pmk-maps-download-confirm")
        self.progress = progress_bar("pmk-maps-download-progress")
        self.status = w.HTML("")
        self.status.add_class("pmk-maps-download-status")
        self.widget = w.VBox(
            [
                heading("Download an IndoorGML map"),
                self.url,
                self.name,
                self.error,
                self.button,
                self.confirm.widget,
                self.progress,
                self.status,
            ],
            layout=w.Layout(align_items="flex-start", width="100%"),
        )

    @needs_pin("Downloading")
    def download(self, *, overwrite: bool = False) -> threading.Thread | None:
        """Download the URL into the maps folder (in a thread); asks before replacing a map."""
        url, name = self.url.value, self.name.value
        self.status.value = ""  # a new attempt: the previous one's outcome goes
        set_progress(self.progress, None)
        if not isinstance(url, str) or not url.strip().lower().startswith(("http://", "https://")):
            self.error.value = "Give an http:// or https:// address of an IndoorGML file."
            return None
        if not isinstance(name, str) or not name.strip():
            self.error.value = "Give the map a name."
            return None
        url, name = url.strip(), name.strip()
        self.error.value = ""
        if not overwrite and self.ctx.maps.exists(name):
            self.confirm.ask(f"A map named '{name}' exists. Replace it?", lambda: self.download(overwrite=True))
            return None
        set_progress(self.progress, 0.0)
        self.status.value = f"Downloading {escape(url)}…"

        def work() -> MapEntry:
            return self.ctx.maps.download(url, name, overwrite=overwrite, progress=progress_callback(self.progress))

        def done(entry: MapEntry) -> None:
            self._on_downloaded(entry)
            set_progress(self.progress, None)
            self.status.value = f"Downloaded {escape(entry.name)}. Convert it on the Maps tab."
            self.ctx.notify(f"Downloaded {entry.name}.", inline=True)

        return run_in_thread(
            self.ctx,
            "Downloading",
            work,
            on_done=done,
            on_error=self._failed,
            busy=[self.button],
            exclusive=self._lock,
        )

    def _failed(self, err: BaseException) -> None:
        show_failure(self.progress, self.status)(err)
        if isinstance(err, AlreadyExists):  # taken meanwhile (another tab, a drop-in file): offer to replace
            name = err.name or self.name.value
            self.confirm.ask(f"A map named '{name}' exists. Replace it?", lambda: self.download(overwrite=True))

    def close(self) -> None:
        self.widget.close()
