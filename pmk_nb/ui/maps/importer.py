"""Importing an IndoorGML file chosen on this device into the maps folder (the Maps screen's Import).

The browser sends the file's bytes; they go through a temporary file into
:meth:`MapsFolder.import_file`.  The outcome is said under the Import button, in the page's words:
the file is named as the user knows it (never by the temporary path), and a file that is not XML
gets no advice about URLs (nothing was downloaded).
"""

from __future__ import annotations

import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

import ipywidgets as w

from pmk_nb.errors import AlreadyExists, LibraryError
from pmk_nb.ui.common.context import needs_pin
from pmk_nb.ui.common.upload import uploaded_file
from pmk_nb.ui.common.widgets import TOUCH_PX, ConfirmBox, escape, guard

if TYPE_CHECKING:
    from pmk_nb.library import MapEntry
    from pmk_nb.ui.common.context import AppContext

UPLOAD_MAX_BYTES = 200 * 1024 * 1024


def import_failure_text(filename: str, temp_path: str, err: LibraryError) -> str:
    """Why ``filename`` was not imported, naming it by its own name.

    A file that is not well-formed XML is worded from the parser's error (the library's sentence
    suggests checking a URL, which is advice for downloads); other reasons keep the library's
    words with the temporary path replaced by the file's name.
    """
    cause = err.__cause__
    if isinstance(cause, SyntaxError):  # the XML parser's error: lxml's XMLSyntaxError is one
        where = f" at line {cause.lineno}" if cause.lineno else ""
        return (
            f"{filename} is not an IndoorGML map: it is not well-formed XML{where} ({cause.msg}). "
            "Choose the building's .gml or .xml file."
        )
    said = err.message.replace(temp_path, filename).rstrip(". ")
    hint = f" {err.hint}" if err.hint else ""
    return f"{filename} was not imported: {said}.{hint}"


class ImportPanel:
    """The Import button, its confirmation and its status line.

    Args:
        ctx: the session (maps folder, notifications).
        on_imported: told the new map's entry (the screen lists and selects it).
    """

    def __init__(self, ctx: AppContext, on_imported: Callable[[MapEntry], None]) -> None:
        self.ctx = ctx
        self._on_imported = on_imported
        self.upload = w.FileUpload(
            accept=".gml,.xml", multiple=False, description="Import IndoorGML", tooltip="Import an IndoorGML file"
        )
        self.upload.layout = w.Layout(height=f"{TOUCH_PX}px", width="auto")
        self.upload.add_class("pmk-maps-import")
        self.upload.observe(guard(ctx, "Importing a map")(self._on_upload), names="value")
        self.confirm = ConfirmBox(ctx, "pmk-maps-import-confirm")
        self.status = w.HTML("")
        self.status.add_class("pmk-maps-import-status")

    def _say(self, message: str, level: str = "info") -> None:
        self.status.value = f"<div class='pmk-msg-{level}'>{escape(message)}</div>" if message else ""
        if message:
            self.ctx.notify(message, level, inline=True)  # type: ignore[arg-type]

    def _on_upload(self, change: dict[str, Any]) -> None:
        got = uploaded_file(change)
        if got is None:
            return
        filename, data = Path(got[0]).name or "upload.gml", got[1]
        self.upload.value = ()  # so the same file can be chosen again
        if len(data) > UPLOAD_MAX_BYTES:
            self._say(
                f"{filename} is larger than {UPLOAD_MAX_BYTES // 2**20} MiB: copy it into the maps folder instead.",
                "error",
            )
            return
        self.import_bytes(filename, data)

    @needs_pin("Importing a map")
    def import_bytes(self, filename: str, data: bytes, *, overwrite: bool = False) -> MapEntry | None:
        """Store an uploaded file in the maps folder (asks before replacing a map of the same name)."""
        name = Path(filename).stem
        self._say("")
        if not overwrite and self.ctx.maps.exists(name):
            self.confirm.ask(
                f"A map named '{name}' exists. Replace it with {filename}?",
                lambda: self.import_bytes(filename, data, overwrite=True),
            )
            return None
        with tempfile.TemporaryDirectory(prefix="pmk-upload-") as tmp:
            path = Path(tmp) / Path(filename).name
            path.write_bytes(data)
            try:
                entry = self.ctx.maps.import_file(path, name=name, overwrite=overwrite, label=Path(filename).name)
            except AlreadyExists:
                raise
            except LibraryError as err:
                self._say(import_failure_text(filename, str(path), err), "error")
                return None
        self._say(f"Imported {filename} as {entry.name}.")
        self._on_imported(entry)
        return entry
