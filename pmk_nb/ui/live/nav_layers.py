"""The navigation stack's layers on the live map (issue 40): a toggle each for the global and local
costmaps, the footprint, the local plan and markers.

The link side (:class:`~pmk_nb.chair.link.streams.navlayers.NavLayerWatch`) finds each layer's topic by type and
follows only the layers switched on; the geometry is :mod:`pmk_nb.viewport.costmap` and
:mod:`pmk_nb.viewport.markers`. A costmap is a map overlay: its RGBA image is put on a hidden canvas of
its own only when the costmap changes, and drawn scaled onto the map layer when the map is repainted
(a few bytes), never sent again per frame. The footprint, the local plan and the markers are vector
overlays of the chair layer. Home's info timer calls :meth:`NavLayers.tick`; ``state`` reports what is
drawn (the page and the browser tests read it).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import ipywidgets as w
import numpy as np
from ipycanvas import Canvas

from pmk_nb.chair.link import LAYERS, LayerLink, NavLayerWatch
from pmk_nb.ui.common.widgets import TOUCH_PX, escape
from pmk_nb.viewport import Transform2D, costmap_placement, costmap_rgba, framed_pixels, marker_draws, pooled_costs

if TYPE_CHECKING:
    from pmk_nb.chair.link import Costmap, Footprint, PlannedPath
    from pmk_nb.ui.live.view import LiveView
    from pmk_nb.viewport import PlanarMarker, Viewport

GLOBAL, LOCAL, FOOTPRINT, LOCAL_PLAN, MARKERS = LAYERS  # the link's layer names, in its order
LABELS = {
    GLOBAL: "Global costmap",
    LOCAL: "Local costmap",
    FOOTPRINT: "Footprint",
    LOCAL_PLAN: "Local plan",
    MARKERS: "Markers",
}
FOOTPRINT_RGB = "rgb(0, 190, 0)"  # RViz's footprint green
LOCAL_PLAN_RGB = "rgba(0, 120, 255, 0.9)"
MAP_FRAME = "map"
#: a frame's place on the map that moved less than this (m, rad) does not redraw a costmap
MOVED = 0.01


def _moved(a: Transform2D | None, b: Transform2D | None) -> bool:
    if a is None or b is None:
        return a is not b
    return max(abs(a.x - b.x), abs(a.y - b.y), abs(math.remainder(a.theta - b.theta, math.tau))) > MOVED


class CostmapOverlay:
    """One costmap on the map layer (a map overlay: ``version`` changes when it must be drawn again)."""

    def __init__(self) -> None:
        self.version = 0
        self.costmap: Costmap | None = None
        self.map_from_frame: Transform2D | None = None
        self.image: Canvas | None = None
        self._put: tuple[int, str] | None = None  # (costmap version, topic) on the hidden canvas
        self._pooled: tuple[tuple[int, str], np.ndarray, int] | None = None
        self.puts = 0  # images sent: once per costmap change

    def set(self, costmap: Costmap | None, map_from_frame: Transform2D | None) -> None:
        """Show ``costmap`` with its frame at ``map_from_frame`` in the map (None: not known yet, hidden)."""
        old = self.costmap
        same = (old is None and costmap is None) or (
            old is not None and costmap is not None and (old.version, old.topic) == (costmap.version, costmap.topic)
        )
        if same and not _moved(self.map_from_frame, map_from_frame):
            return
        self.costmap, self.map_from_frame = costmap, map_from_frame
        self.version += 1

    def invalidate(self) -> None:
        """A new page: its hidden canvas is empty, put the image again."""
        self._put = None
        self.version += 1

    def draw(self, layer: Canvas, view: Viewport) -> None:
        costmap, tf = self.costmap, self.map_from_frame
        if costmap is None or tf is None or costmap.data.size == 0:
            return
        key = (costmap.version, costmap.topic)
        if self._pooled is None or self._pooled[0] != key:  # once per costmap, not per repaint
            self._pooled = (key, *pooled_costs(costmap.data))  # a building-sized one is pooled, never sent whole
        _key, cells, factor = self._pooled
        height, width = cells.shape
        if self.image is None or (self.image.width, self.image.height) != (width, height):
            if self.image is not None:
                self.image.close()
            self.image = Canvas(width=width, height=height)  # a new size is a new canvas: never resized
            self._put = None
        if self._put != key:
            self.image.clear()
            self.image.put_image_data(costmap_rgba(cells), 0, 0)  # RGBA, never RGB
            self._put = key
            self.puts += 1
        place = costmap_placement(view, costmap.origin, costmap.resolution * factor, (width, height), tf)
        layer.save()
        layer.translate(place.x, place.y)
        if place.angle:
            layer.rotate(place.angle)
        layer.image_smoothing_enabled = False  # one cell, one crisp square
        layer.draw_image(self.image, 0, -place.height, place.width, place.height)
        layer.restore()

    def close(self) -> None:
        if self.image is not None:
            self.image.close()
            self.image = None


class VectorOverlay:
    """The footprint, the local plan and the markers on the chair layer (a frame overlay)."""

    def __init__(self) -> None:
        self.version = 0
        self.footprint: tuple[Footprint, Transform2D] | None = None
        self.plan: tuple[PlannedPath, Transform2D] | None = None
        self.markers: list[tuple[PlanarMarker, Transform2D]] = []
        self._key: tuple[object, ...] | None = None

    def set(self, key: tuple[object, ...], **parts: Any) -> None:
        """New parts when ``key`` (what they were made from) changed."""
        if key == self._key:
            return
        self._key = key
        self.footprint, self.plan, self.markers = parts["footprint"], parts["plan"], parts["markers"]
        self.version += 1

    def draw(self, layer: Canvas, view: Viewport) -> None:
        if self.plan is not None and self.plan[0].points.shape[0] >= 2:
            layer.line_width = 3
            layer.stroke_style = LOCAL_PLAN_RGB
            layer.stroke_lines(framed_pixels(view, self.plan[1], self.plan[0].points))
        if self.footprint is not None and self.footprint[0].points.shape[0] >= 3:
            layer.line_width = 2
            layer.stroke_style = FOOTPRINT_RGB
            layer.stroke_polygon(framed_pixels(view, self.footprint[1], self.footprint[0].points))
        for marker, tf in self.markers:
            for step in marker_draws(marker, view, tf):
                _draw_step(layer, step.op, step.xy, step.style, step.size, step.text)
        layer.line_width = 1


def _draw_step(layer: Canvas, op: str, xy: np.ndarray, style: str, size: float, text: str) -> None:
    """One :class:`~pmk_nb.viewport.markers.MarkerDraw` as canvas calls."""
    if op == "lines":
        layer.line_width, layer.stroke_style = size, style
        layer.stroke_lines(xy)
    elif op == "segments":
        layer.line_width, layer.stroke_style = size, style
        layer.stroke_line_segments(xy)
    elif op == "squares":
        layer.fill_style = style
        layer.fill_rects(xy[:, 0] - size / 2, xy[:, 1] - size / 2, size)
    elif op == "polygon":
        layer.fill_style = style
        layer.fill_polygon(xy)
    elif op == "text":
        layer.fill_style, layer.font, layer.text_align = style, f"{size:.0f}px sans-serif", "center"
        layer.fill_text(text, float(xy[0, 0]), float(xy[0, 1]))
        layer.text_align = "start"


class NavLayers:
    """The toggles (``widget``), the overlays on ``live`` and the link's watch."""

    def __init__(self, live: LiveView) -> None:
        self.live = live
        self.link: LayerLink | None = None
        self.watch: NavLayerWatch | None = None
        self.costmaps = {GLOBAL: CostmapOverlay(), LOCAL: CostmapOverlay()}
        self.vectors = VectorOverlay()
        live.map_overlays.extend([self.costmaps[GLOBAL], self.costmaps[LOCAL]])  # global under local
        live.overlays.append(self.vectors)
        self.toggles: dict[str, w.ToggleButton] = {}
        for layer in LAYERS:
            toggle = w.ToggleButton(value=False, description=LABELS[layer], tooltip=f"Show the {LABELS[layer].lower()}")
            toggle.layout = w.Layout(height=f"{TOUCH_PX}px", width="auto")
            toggle.add_class(f"pmk-layer-{layer.replace('_', '-')}")
            toggle.observe(lambda change, name=layer: self._on_toggle(name, change), names="value")
            self.toggles[layer] = toggle
        self.state = w.HTML("")
        self.state.add_class("pmk-live-layers-state")
        self.widget = w.VBox([w.HBox(list(self.toggles.values()), layout=w.Layout(flex_flow="row wrap")), self.state])
        self.widget.add_class("pmk-live-layers")

    def _on_toggle(self, layer: str, change: dict[str, Any]) -> None:
        on = change.get("new") is True  # anything but a real True from the page is off
        if self.watch is not None:
            self.watch.want(layer, on)
        self.tick()

    def attach(self, link: LayerLink | None) -> None:
        """Follow ``link``'s layers (None: the preview stopped; every subscription ends)."""
        if self.watch is not None:
            self.watch.stop()
        self.link = link
        self.watch = NavLayerWatch(link.topics_of_type) if link is not None else None
        if self.watch is not None:
            for layer, toggle in self.toggles.items():
                self.watch.want(layer, toggle.value is True)
        self.tick()

    def _frame(self, frame: str) -> Transform2D | None:
        """map <- ``frame`` from the link's tf tree; identity for the map itself, and for the frame the
        live view draws the chair in when it knows no map pose (odometry as the pose: the view shows
        ``odom`` as the map); None while unknown (the layer waits)."""
        if frame in ("", MAP_FRAME) or self.link is None:
            return Transform2D()
        found = self.link.frame_transform(MAP_FRAME, frame)
        if found is not None:
            return found
        pose = self.link.latest_pose()
        return Transform2D() if pose is not None and getattr(pose, "frame", None) == frame else None

    def tick(self) -> None:
        """From Home's info timer: (re)subscribe on the link's current socket, take the latest layers."""
        watch, link = self.watch, self.link
        if watch is None or link is None:
            for overlay in self.costmaps.values():
                overlay.set(None, None)
            self.vectors.set((), footprint=None, plan=None, markers=[])
            self.state.value = ""
            return
        watch.follow(link.ros if link.is_connected else None)
        on = {layer for layer, toggle in self.toggles.items() if toggle.value is True}
        for layer, overlay in self.costmaps.items():
            costmap = watch.costmap(layer) if layer in on else None
            overlay.set(costmap, self._frame(costmap.frame) if costmap is not None else None)
        footprint = watch.footprint() if FOOTPRINT in on else None
        plan = watch.local_plan() if LOCAL_PLAN in on else None
        version, shown = watch.markers() if MARKERS in on else (0, [])
        fp = (footprint, self._frame(footprint.frame)) if footprint is not None else None
        lp = (plan, self._frame(plan.frame)) if plan is not None else None
        marks = [(m, tf) for frame, m in shown if (tf := self._frame(frame)) is not None]
        counts = watch.counts
        key = (
            counts[FOOTPRINT] if fp is not None else None,
            fp and fp[1],
            counts[LOCAL_PLAN] if lp is not None else None,
            lp and lp[1],
            version if MARKERS in on else None,
            tuple(tf for _m, tf in marks),
        )
        self.vectors.set(
            key,
            footprint=fp if fp is not None and fp[1] is not None else None,
            plan=lp if lp is not None and lp[1] is not None else None,
            markers=marks,
        )
        self.state.value = self._state_html(watch, on)

    def _state_html(self, watch: NavLayerWatch, on: set[str]) -> str:
        """What is drawn, in words and as data attributes (the page's tests read them)."""
        found = watch.topics()
        parts, data = [], []
        for layer in LAYERS:
            if layer not in on:
                continue
            topics = found.get(layer, ())
            what = self._what(watch, layer)
            parts.append(
                f"{LABELS[layer]}: {escape(what or ('waiting for ' + topics[0] if topics else 'no topic yet'))}"
            )
            data.append(f'data-{layer.replace("_", "-")}="{escape(what)}"')
        return f"<small {' '.join(data)}>{' · '.join(parts)}</small>" if parts else ""

    def _what(self, watch: NavLayerWatch, layer: str) -> str:
        if layer in (GLOBAL, LOCAL):
            overlay = self.costmaps[layer]
            c = overlay.costmap
            return "" if c is None else f"{c.data.shape[1]}x{c.data.shape[0]} cells, {c.topic}"
        if layer == FOOTPRINT:
            fp = self.vectors.footprint
            return "" if fp is None else f"{fp[0].points.shape[0]} points, {fp[0].topic}"
        if layer == LOCAL_PLAN:
            lp = self.vectors.plan
            return "" if lp is None else f"{lp[0].points.shape[0]} poses, {lp[0].topic}"
        n = len(self.vectors.markers)
        return f"{n} markers" if n else ""

    def close(self) -> None:
        self.attach(None)
        for overlay in self.costmaps.values():
            overlay.close()
