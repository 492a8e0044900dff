"""Pieces of the Maps screen's list tab: a map's line in the list and the card of one generated map."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

import ipywidgets as w

from pmk_nb.ui.common.widgets import button, escape, guard, picture

if TYPE_CHECKING:
    from pmk_nb.library import GeneratedMap, MapEntry, StoreyInfo
    from pmk_nb.ui.common.context import AppContext

THUMB_PX = 220


def map_label(entry: MapEntry, storeys: list[StoreyInfo] | None = None) -> str:
    """One line of the maps list: name, storey count (when known) and what has been generated."""
    n = len(entry.generated)
    status = getattr(entry, "status", "converted" if n else "not converted")
    parts = []
    if storeys is not None:
        parts.append(f"{len(storeys)} storey{'' if len(storeys) == 1 else 's'}")
    elif n > 1:
        parts.append(f"{n} storeys")
    if n:  # short: a <select> row cannot wrap, and a phone is 360 px wide
        resolutions = sorted({g.resolution for g in entry.generated if g.resolution})
        parts.append(f"{resolutions[0]:g} m" if len(resolutions) == 1 else "converted")
    if status != "converted":
        parts.append(status)
    return f"{entry.name} ({', '.join(parts)})"


def generated_card(
    ctx: AppContext, gm: GeneratedMap, several: bool, on_send: Callable[[GeneratedMap], Any]
) -> w.Widget:
    """Preview, size and a Send button for one generated map (``several``: label it by storey)."""
    label = f"Storey {gm.storey}" if several and gm.storey else "Map"
    thumb: w.Widget
    if gm.preview is not None and Path(gm.preview).is_file():
        thumb = picture(
            Path(gm.preview).read_bytes(),
            f"Preview of the map {Path(gm.yaml).stem}",
            "pmk-maps-preview",
            style=f"max-width: {THUMB_PX}px; max-height: {THUMB_PX}px; object-fit: contain; display: block",
        )
    else:
        thumb = w.HTML("<i>no preview image</i>")
    send = button(
        f"Send {gm.storey}" if several and gm.storey else "Send",
        "pmk-maps-send",
        icon="paper-plane",
        style="success",
    )
    send.on_click(guard(ctx, "Sending")(lambda _b, g=gm: on_send(g)))
    lines = [
        f"<b>{escape(label)}</b>",
        f"{gm.width} × {gm.height} cells at {gm.resolution:g} m",
        escape(Path(gm.yaml).name),
    ]
    if getattr(gm, "broken", ""):
        lines.append(f"<span class='pmk-field-error'>Unreadable: {escape(gm.broken)}. Convert again.</span>")
        send.disabled = True
    elif getattr(gm, "stale", False):
        lines.append("<span class='pmk-field-error'>The IndoorGML file changed since: convert again.</span>")
    info = w.HTML("<br>".join(lines))
    card = w.HBox(
        [thumb, w.VBox([info, send], layout=w.Layout(padding="0 0 0 12px"))],
        layout=w.Layout(margin="8px 0", align_items="center"),
    )
    card.add_class("pmk-maps-card")
    return card
