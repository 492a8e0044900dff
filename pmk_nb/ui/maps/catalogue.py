"""The Maps screen's Catalogue tab (issue 27): browse map catalogues and install a building with Get.

Catalogue URLs are added once and kept in the settings folder; Load reads one (through the guarded
downloader, every link kept inside the catalogue's folder), shows each building with its thumbnail,
storeys, size and date, and whether it is new, changed since it was installed here, or installed.
Search filters by name as you type. Get installs a building, every file's size and SHA-256 checked,
all files at once; a refusal leaves the maps folder as it was and says why.
"""

from __future__ import annotations

import hashlib
import io
import threading
from collections.abc import Callable
from typing import TYPE_CHECKING

import ipywidgets as w

from pmk_nb.catalogue import (
    CHANGED,
    INSTALLED,
    NEW,
    Building,
    Catalogue,
    CatalogueSources,
    InstallRecord,
    InstallResult,
    Reader,
    read_catalogue,
)
from pmk_nb.catalogue.install import install
from pmk_nb.errors import PmkError
from pmk_nb.ui.common.context import needs_pin
from pmk_nb.ui.common.widgets import (
    ConfirmBox,
    button,
    escape,
    field_error,
    guard,
    heading,
    picture,
    progress_bar,
    progress_callback,
    replace_children,
    run_in_thread,
    set_progress,
    show_failure,
    text,
)

if TYPE_CHECKING:
    from pmk_nb.ui.common.context import AppContext

MAX_THUMBNAIL_BYTES = 512 * 1024
MAX_SHOWN = 50  # cards drawn at once; the search narrows the rest
_BADGES = {
    NEW: ("New", "pmk-cat-new", "#1565c0"),
    CHANGED: ("Changed since installed", "pmk-cat-changed", "#b45309"),
    INSTALLED: ("Installed", "pmk-cat-installed", "#2e7d32"),
}


class CataloguePanel:
    """Catalogue URLs (settings), the buildings of the chosen one, Get; ``on_installed(result)`` after a Get."""

    def __init__(self, ctx: AppContext, on_installed: Callable[[InstallResult], None]) -> None:
        self.ctx = ctx
        self._on_installed = on_installed
        self._lock = threading.Lock()
        self.sources = CatalogueSources(ctx.config_dir)
        self.catalogue: Catalogue | None = None
        self.thumbnails: dict[str, bytes] = {}
        self.source = w.Dropdown(
            options=self.sources.urls(),
            description="Catalogue",
            style={"description_width": "200px"},
            layout=w.Layout(width="100%", max_width="720px"),
        )
        self.source.add_class("pmk-cat-source")
        self.url = text("", "Add a catalogue", "pmk-cat-url", placeholder="https://server/maps/catalog.json")
        self.add_button = button("Add", "pmk-cat-add", icon="plus", style="primary")
        self.add_button.on_click(guard(ctx, "Adding a catalogue")(lambda _b: self.add()))
        self.load_button = button("Load", "pmk-cat-load", icon="refresh")
        self.load_button.on_click(guard(ctx, "Loading the catalogue")(lambda _b: self.load()))
        self.remove_button = button("Remove", "pmk-cat-remove", icon="trash")
        self.remove_button.on_click(guard(ctx, "Removing a catalogue")(lambda _b: self.remove()))
        self.search = text("", "Search", "pmk-cat-search", placeholder="building name")
        self.search.continuous_update = True
        self.search.observe(guard(ctx, "Searching")(lambda _c: self.render()), names="value")
        self.error = field_error()
        self.confirm = ConfirmBox(ctx, "pmk-cat-confirm", yes="Replace")
        self.progress = progress_bar("pmk-cat-progress")
        self.status = w.HTML("")
        self.status.add_class("pmk-cat-status")
        self.results = w.VBox([], layout=w.Layout(width="100%"))
        self.results.add_class("pmk-cat-results")
        row = w.HBox([self.load_button, self.remove_button])
        row.add_class("pmk-row")
        self.widget = w.VBox(
            [
                heading("Map catalogues"),
                self.url,
                self.add_button,
                self.error,
                self.source,
                row,
                self.search,
                self.confirm.widget,
                self.progress,
                self.status,
                self.results,
            ],
            layout=w.Layout(align_items="flex-start", width="100%"),
        )
        self.widget.add_class("pmk-cat")

    # -- catalogue URLs (settings) -----------------------------------------------------------------
    @needs_pin("Adding a catalogue")
    def add(self) -> threading.Thread | None:
        """Keep the typed URL in the settings, select it and load it."""
        url = self.url.value
        if not isinstance(url, str) or not url.strip().lower().startswith(("http://", "https://")):
            self.error.value = "Give the http:// or https:// address of a catalog.json (or of its folder)."
            return None
        try:
            urls = self.sources.add(url.strip())
        except PmkError as err:
            self.error.value = escape(str(err))
            return None
        self.error.value = ""
        self.url.value = ""
        self.source.options = urls
        self.source.value = url.strip()
        return self.load()

    @needs_pin("Removing a catalogue")
    def remove(self) -> None:
        url = self.source.value
        if url in self.sources.urls():
            self.source.options = self.sources.remove(url)
            self.catalogue = None
            self.render()

    # -- browse ------------------------------------------------------------------------------------
    def load(self) -> threading.Thread | None:
        """Read the selected catalogue and its thumbnails (in a thread)."""
        url = self.source.value
        if not isinstance(url, str) or url not in self.sources.urls():  # a page can send any value
            self.error.value = "Add a catalogue first, then choose it."
            return None
        self.error.value = ""
        set_progress(self.progress, None)
        self.status.value = f"Reading {escape(url)}…"
        allow_local = self.ctx.maps.allow_local

        def work() -> tuple[Catalogue, dict[str, bytes]]:
            catalogue = read_catalogue(url, allow_local=allow_local)
            return catalogue, _thumbnails(catalogue, allow_local)

        def done(result: tuple[Catalogue, dict[str, bytes]]) -> None:
            self.catalogue, self.thumbnails = result
            n = len(self.catalogue.buildings)
            said = f"{escape(self.catalogue.title)}: {n} building{'s' if n != 1 else ''}."
            refused = self.catalogue.refused
            if refused:  # the clean ones are listed; the bad ones named, each with why
                said += " Left out, they fail the checks: " + "; ".join(
                    f"{escape(r.id)} ({escape(str(r.error))})" for r in refused
                )
            self.status.value = said
            self.render()

        return run_in_thread(
            self.ctx,
            "Loading the catalogue",
            work,
            on_done=done,
            on_error=show_failure(self.progress, self.status),
            busy=[self.load_button, self.add_button],
            exclusive=self._lock,
        )

    def statuses(self) -> dict[str, str]:
        """new / changed / installed per building of the loaded catalogue."""
        if self.catalogue is None:
            return {}
        record = InstallRecord(self.ctx.maps.root)
        url = self.catalogue.url
        return {b.id: record.status(b, url, present=self.ctx.maps.exists(b.id)) for b in self.catalogue.buildings}

    def render(self) -> None:
        """Draw the buildings whose name matches the search."""
        if self.catalogue is None:
            replace_children(self.results, [])
            return
        query = self.search.value.strip().casefold() if isinstance(self.search.value, str) else ""
        shown = [b for b in self.catalogue.buildings if query in b.id.casefold() or query in b.title.casefold()]
        statuses = self.statuses()
        cards = [self._card(b, statuses.get(b.id, NEW)) for b in shown[:MAX_SHOWN]]
        if not shown:
            cards = [w.HTML(f"No building matches {escape(self.search.value)!s}.")]
        replace_children(self.results, cards)

    def _card(self, b: Building, status: str) -> w.Widget:
        label, css, colour = _BADGES[status]
        storeys = ", ".join(
            f"{escape(s.storey or s.id)} ({s.width}×{s.height} at {s.resolution:g} m)" for s in b.storeys
        )
        info = w.HTML(
            f"<b>{escape(b.title)}</b> <span class='pmk-cat-badge {css}' style='color:#fff;background:{colour};"
            f"border-radius:4px;padding:0 6px'>{label}</span><br>"
            f"{len(b.storeys)} storey{'s' if len(b.storeys) != 1 else ''}: {storeys}<br>"
            f"{b.size / 1024:.0f} KiB · updated {escape(b.updated)}"
        )
        get = button("Get" if status != INSTALLED else "Get again", "pmk-cat-get", icon="download", style="primary")
        get.on_click(guard(self.ctx, "Installing")(lambda _b, bid=b.id: self.get(bid)))
        thumb = self.thumbnails.get(b.id)
        box = w.Layout(width="128px", height="auto", margin="0 12px 0 0")
        if thumb:
            shown = picture(
                thumb, f"Plan of {b.title}", "pmk-cat-thumb", style="width: 128px; height: auto", on_img=True
            )
            shown.layout = box
        else:
            shown = w.HTML("(no thumbnail)", layout=box)
            shown.add_class("pmk-cat-thumb")
        card = w.HBox([shown, w.VBox([info, get])], layout=w.Layout(align_items="center"))
        card.add_class("pmk-cat-card")
        return card

    # -- install -----------------------------------------------------------------------------------
    @needs_pin("Installing")
    def get(self, building_id: str, *, overwrite: bool = False) -> threading.Thread | None:
        """Install a building of the loaded catalogue (asks before replacing a map made elsewhere)."""
        catalogue = self.catalogue
        if catalogue is None or not isinstance(building_id, str) or building_id not in self.statuses():
            self.status.value = "Load a catalogue and press Get beside one of its buildings."
            return None
        if not overwrite and self.statuses()[building_id] == NEW and self.ctx.maps.exists(building_id):
            self.confirm.ask(
                f"A map named '{building_id}' exists and did not come from this catalogue. Replace it?",
                lambda: self.get(building_id, overwrite=True),
            )
            return None
        set_progress(self.progress, 0.0)
        self.status.value = f"Installing {escape(building_id)}…"

        def work() -> InstallResult:
            return install(
                catalogue, building_id, self.ctx.maps, overwrite=overwrite, progress=progress_callback(self.progress)
            )

        def done(result: InstallResult) -> None:
            set_progress(self.progress, None)
            self.status.value = (
                f"Installed {escape(result.name)}: {len(result.files)} files, every size and "
                "SHA-256 checked. It is on the Maps tab."
            )
            self.render()
            self._on_installed(result)
            self.ctx.notify(f"Installed {result.name} from the catalogue.", inline=True)

        return run_in_thread(
            self.ctx,
            "Installing",
            work,
            on_done=done,
            on_error=show_failure(self.progress, self.status),
            busy=[self.load_button],
            exclusive=self._lock,
        )

    def close(self) -> None:
        self.widget.close()


def _thumbnails(catalogue: Catalogue, allow_local: bool) -> dict[str, bytes]:
    """The first storey's thumbnail of each building shown, checked like any file (skipped when not)."""
    reader = Reader(catalogue.url, allow_local=allow_local)
    out: dict[str, bytes] = {}
    for b in catalogue.buildings[:MAX_SHOWN]:
        asset = next((s.assets["thumbnail"] for s in b.storeys if "thumbnail" in s.assets), None)
        if asset is None or asset.size > MAX_THUMBNAIL_BYTES:
            continue
        buf = io.BytesIO()
        try:
            reader.fetch_to(asset.url, buf, max_bytes=asset.size)
        except PmkError:
            continue  # a missing picture is no reason to hide the building
        data = buf.getvalue()
        if hashlib.sha256(data).hexdigest() == asset.sha256:
            out[b.id] = data
    return out
