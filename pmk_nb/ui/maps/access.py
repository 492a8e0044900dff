"""The Maps screen's accessibility panel: per converted storey, can a chair go where the plan says?

It shows what the converter's check wrote into each map's rooms file (so opening a map never
re-runs the check): the summary, the blocked doors by their rooms' names, unreachable rooms, leaks,
and the unit warning, with the storey's preview where the blocked openings are marked in red.
"""

from __future__ import annotations

import io
import json
from typing import TYPE_CHECKING, Any

import ipywidgets as w
import shapely

from pmk_nb.access import SKIP_OUTSIDE
from pmk_nb.openings import SKIP_WINDOW
from pmk_nb.ui.common.widgets import escape, picture, replace_children

if TYPE_CHECKING:
    from pmk_nb.library import GeneratedMap, MapEntry

RED = (220, 30, 30, 255)


def marked_preview(gm: GeneratedMap, doc: dict[str, Any]) -> bytes | None:
    """The storey's preview PNG with the openings the chair cannot pass drawn in red (None: no preview)."""
    from PIL import Image, ImageDraw

    from pmk_nb.rosmap import read_map_yaml

    if gm.preview is None or not gm.preview.is_file():
        return None
    try:
        meta = read_map_yaml(gm.yaml)
        img = Image.open(gm.preview).convert("RGBA")
    except Exception:
        return None
    ox, oy = float(meta.origin[0]), float(meta.origin[1])
    scale = img.width / max(gm.width * gm.resolution, 1e-9)  # preview pixels per metre
    blocked = {k["link"] for k in (doc.get("accessibility") or {}).get("links", []) if not k["chair"]}
    draw = ImageDraw.Draw(img)
    centre = {r["id"]: shapely.from_geojson(json.dumps(r["polygon"])).centroid for r in doc.get("rooms", [])}
    ends = {k["id"]: (k["a"], k["b"]) for k in doc.get("links", [])}
    for o in doc.get("openings", []):
        if o["link"] not in blocked:
            continue
        segments = list(o["segments"])
        if not segments and o["link"] in ends and all(c in centre for c in ends[o["link"]]):
            a, b = (centre[c] for c in ends[o["link"]])  # rooms that do not touch: join their middles
            segments = [{"coordinates": [(a.x, a.y), (b.x, b.y)]}]
        for seg in segments:
            pts = [((x - ox) * scale, img.height - (y - oy) * scale) for x, y, *_ in seg["coordinates"]]
            if len(pts) >= 2:
                draw.line(pts, fill=RED, width=max(3, int(0.3 * scale)))
            if pts:
                cx, cy = pts[len(pts) // 2]
                draw.ellipse((cx - 8, cy - 8, cx + 8, cy + 8), outline=RED, width=3)
    out = io.BytesIO()
    img.save(out, format="PNG")
    return out.getvalue()


def _storey_html(gm: GeneratedMap, doc: dict[str, Any] | None) -> str:
    label = escape(gm.storey or gm.yaml.stem)
    if doc is None:
        return f"<p><b>{label}</b>: no accessibility check for this map (convert it again to get one).</p>"
    report = doc.get("accessibility")
    if report and report.get("graph_lost"):
        return f"<p class='pmk-warn'><b>⚠ {label}</b>: nothing checked: {escape(report['graph_lost'])}</p>"
    if not report or not (report.get("graph") or report.get("not_checked")):
        return f"<p><b>{label}</b>: the plan has no navigation graph here, so there is nothing to check against.</p>"
    if not report.get("graph"):  # every transition of the storey leads to a window or a non-navigable cell
        listing = "".join(f"<li>{t}</li>" for t in _not_checked_items(report))
        return f"<p><b>{label}</b>: no passage between rooms to check</p><ul class='pmk-access-list'>{listing}</ul>"
    c = report["counts"]
    ok = report.get("ok", False)
    mark = "✓" if ok else "⚠"
    head = (
        f"<p class='{'pmk-ok' if ok else 'pmk-warn'}'><b>{mark} {label}</b>: {c['passable_chair']} of {c['links']} "
        f"passages fit a {report['chair_width']:.2f} m wheelchair</p>"
    )
    items = []
    for k in report["links"]:
        if k["chair"]:
            continue
        a, b = (escape(n) for n in k["names"])
        if k["rule"] == "apart":
            items.append(f"{a} – {b}: the rooms do not touch, so the map cannot join them")
        elif not k["point"]:
            items.append(f"{a} – {b}: no way through in the map")
        else:
            items.append(f"{a} – {b}: door narrower than the chair ({k['width']:.2f} m)")
    items += [f"{escape(n)}: cannot be reached from the rest of the floor" for n in report.get("unreachable", [])]
    items += [
        f"{escape(x['names'][0])} and {escape(x['names'][1])}: open to each other though the plan has no door"
        for x in report.get("leaks", [])
    ]
    items += _not_checked_items(report)
    listing = "".join(f"<li>{t}</li>" for t in items)
    return head + (f"<ul class='pmk-access-list'>{listing}</ul>" if listing else "")


NOT_PASSABLE = "cells marked not passable"
NOT_CHECKED_WHAT = {
    SKIP_WINDOW: "cells taken for windows or sills",
    SKIP_OUTSIDE: "doorways out of the map",
    "": NOT_PASSABLE,
}  # why a passage was not checked -> what it leads into
MAX_NOT_CHECKED = 10  # cells named; the rest are counted


def _layers_html(layers: list[dict[str, Any]]) -> str:
    """The plan's layers not drawn, and why (a thematic layer drawn would make walls across rooms)."""
    items = "".join(
        f"<li>{escape(str(n.get('id', '')))} ({n.get('cells', 0)} cells): {escape(str(n.get('reason', '')))}</li>"
        for n in layers
    )
    head = "<p><b>Layers not drawn</b> (tick one under <i>Layers to draw</i> and convert again to draw it):</p>"
    return f"{head}<ul class='pmk-access-list'>{items}</ul>"


def _not_checked_items(report: dict[str, Any]) -> list[str]:
    """The passages the check skipped (absent from reports written before it named them), one line per
    reason naming the cells they lead into. A cell judged a window from its height may be a door the
    rule misjudged: say so, since nothing else would show it."""
    skipped = report.get("not_checked") or []
    items = []
    groups: dict[str, list[dict[str, Any]]] = {what: [] for what in NOT_CHECKED_WHAT.values()}
    for x in skipped:
        groups[NOT_CHECKED_WHAT.get(x["reason"], NOT_PASSABLE)].append(x)
    for what, these in groups.items():
        windows = what == NOT_CHECKED_WHAT[SKIP_WINDOW]
        if not these:
            continue
        cells = list(dict.fromkeys(x["cell"] for x in these))
        names = ", ".join(escape(c) for c in cells[:MAX_NOT_CHECKED])
        more = f" and {len(cells) - MAX_NOT_CHECKED} more" if len(cells) > MAX_NOT_CHECKED else ""
        line = f"Not checked: {len(these)} passage{'s' if len(these) != 1 else ''} into {what} ({names}{more})."
        if windows:
            line += (
                " If one of these is really a door, the window rule misjudged it: tick it under "
                "<i>Not windows</i> and convert again to keep it navigable (command line: "
                "<code>pmk convert --not-window NAME</code>)."
            )
        items.append(line)
    return items


class AccessPanel:
    """Accessibility of the selected map's converted storeys; ``show(entry)`` refreshes it."""

    def __init__(self) -> None:
        self.text = w.HTML("")
        self.images = w.VBox([])
        self.widget = w.VBox([self.text, self.images], layout=w.Layout(width="100%"))
        self.widget.add_class("pmk-access")

    def show(self, entry: MapEntry | None, docs: list[dict[str, Any] | None]) -> None:
        """``docs``: the rooms file of each of ``entry``'s generated maps (read once by the screen)."""
        if entry is None or not entry.generated:
            self.text.value = ""
            replace_children(self.images, ())
            self.widget.layout.display = "none"
            return
        self.widget.layout.display = "flex"
        parts, images, conflict = [], [], ""
        layers: list[dict[str, Any]] = []
        suspect = next((s for doc in docs if isinstance(s := (doc or {}).get("unit_suspect"), dict)), None)
        if suspect is not None:  # before any door: a wrong unit makes every door look wrong
            parts.append(
                f"<p class='pmk-warn pmk-access-unit'><b>Suspect the unit first:</b> "
                f"{escape(str(suspect.get('message', '')))}</p>"
            )
        for gm, doc in zip(entry.generated, docs, strict=True):
            parts.append(_storey_html(gm, doc))
            conflict = conflict or (doc or {}).get("unit_conflict", "")
            layers = layers or [n for n in (doc or {}).get("skipped_layers") or [] if n.get("cells")]  # graphs only: no
            report = (doc or {}).get("accessibility") or {}
            if doc is not None and not report.get("ok", True) and report.get("checked", True):  # problems to mark
                png = marked_preview(gm, doc)
                if png is not None:
                    alt = f"The map {gm.yaml.stem} with its access problems marked"
                    images.append(picture(png, alt, "pmk-access-preview", on_img=True))
        if conflict:
            parts.append(f"<p class='pmk-warn'><b>Size warning:</b> {escape(conflict)}</p>")
        if layers:
            parts.append(_layers_html(layers))
        self.text.value = "<div class='pmk-heading-small'>Wheelchair access</div>" + "".join(parts)
        replace_children(self.images, images)
