"""Plot anything (issue 40): any numeric field of any topic, several series on one chart, a time window
and Pause, in Home's Plots panel (JupyterLab and the kiosk alike: plain ipywidgets and one ipycanvas).

The topics come from the topic inspector's listing; a picked topic's numeric fields from the bridge's
type definitions (rosapi ``message_details``, on a worker thread: :mod:`pmk_nb.chair.link.streams.fields`); a
path may also be typed (a bridge without definitions). Each topic plotted has one throttled
subscription (:class:`~pmk_nb.chair.link.streams.series.TopicSeries`) shared by its series, ended when its
last series is removed, the panel closes or the preview stops. Pause freezes the chart (the samples
keep coming); the chart is redrawn from Home's info timer at most :data:`PLOT_HZ` times a second.
"""

from __future__ import annotations

import logging
import re
import threading
import time
from typing import Any

import ipywidgets as w
import numpy as np
from ipycanvas import Canvas, hold_canvas

from pmk_nb.chair.link import LinkCore, TopicSeries, numeric_fields
from pmk_nb.errors import PmkError
from pmk_nb.ui.common.widgets import TOUCH_PX, button, escape
from pmk_nb.viewport import series_lines

log = logging.getLogger(__name__)

PLOT_HZ = 2.0
CHART = (560, 200)
PAD = (58, 12)
WINDOWS = (("30 s", 30.0), ("1 min", 60.0), ("5 min", 300.0), ("15 min", 900.0))
COLOURS = ("rgb(25, 90, 220)", "rgb(230, 120, 0)", "rgb(20, 150, 60)", "rgb(200, 30, 60)", "rgb(130, 60, 200)")
MAX_SERIES = len(COLOURS)
PATH = re.compile(r"^[A-Za-z_]\w*(\[\d+\])?(\.[A-Za-z_]\w*(\[\d+\])?)*$")
NONE = ""


class FieldPlot:
    """``widget``: topic, field, Add; the series with Remove; window and Pause; the chart and its legend."""

    def __init__(self) -> None:
        self.link: LinkCore | None = None
        self.types: dict[str, str] = {}
        self.series: list[tuple[str, str]] = []  # (topic, field) in the order added
        self.subs: dict[str, TopicSeries] = {}
        self.paused_at: float | None = None
        self._drawn_at = -float("inf")
        self._lock = threading.Lock()
        self._fields_for: str | None = None
        self._pending_fields: tuple[str, list[str], str] | None = None
        self.draws = 0
        self.topic = w.Dropdown(options=[("— topic —", NONE)], value=NONE, description="Topic")
        self.topic.add_class("pmk-fieldplot-topic")
        self.field = w.Combobox(
            placeholder="field, e.g. twist.twist.linear.x", description="Field", ensure_option=False
        )
        self.field.add_class("pmk-fieldplot-field")
        self.add_button = button("Add", "pmk-fieldplot-add", icon="plus", width="auto")
        self.list = w.Select(options=[], rows=3)
        self.list.add_class("pmk-fieldplot-series")
        self.remove_button = button("Remove", "pmk-fieldplot-remove", icon="minus", width="auto")
        self.window = w.Dropdown(options=WINDOWS, value=60.0, description="Window")
        self.window.add_class("pmk-fieldplot-window")
        self.pause = w.ToggleButton(value=False, description="Pause", icon="pause")
        self.pause.layout = w.Layout(height=f"{TOUCH_PX}px", width="auto")
        self.pause.add_class("pmk-fieldplot-pause")
        self.status = w.HTML("")
        self.status.add_class("pmk-fieldplot-status")
        self.canvas = Canvas(width=CHART[0], height=CHART[1])
        self.canvas.layout = w.Layout(width=f"{CHART[0]}px", max_width="100%", height="auto")
        self.canvas.add_class("pmk-fieldplot-chart")
        self.legend = w.HTML("")
        self.legend.add_class("pmk-fieldplot-legend")
        self.widget = w.VBox(
            [
                w.HBox([self.topic, self.field, self.add_button], layout=w.Layout(flex_flow="row wrap")),
                w.HBox([self.list, self.remove_button, self.window, self.pause], layout=w.Layout(flex_flow="row wrap")),
                self.status,
                self.canvas,
                self.legend,
            ]
        )
        self.widget.add_class("pmk-fieldplot")
        self.topic.observe(self._on_topic, names="value")
        self.add_button.on_click(lambda _b: self.add(self.topic.value, self.field.value))
        self.remove_button.on_click(lambda _b: self.remove(self.list.value))
        self.pause.observe(self._on_pause, names="value")

    # -- link and topics ---------------------------------------------------------------------------------
    def attach(self, link: LinkCore | None) -> None:
        """Plot from ``link`` (None: every subscription ends; the series' samples are dropped)."""
        for sub in self.subs.values():
            sub.stop()
        self.subs = {}
        self.series = []
        self.link = link
        self._show_series()

    def set_topics(self, types: dict[str, str]) -> None:
        """The chair's topics with their types (the inspector's listing)."""
        if types == self.types:
            return
        self.types = dict(types)
        current = self.topic.value if self.topic.value in self.types else NONE
        self.topic.options = [("— topic —", NONE), *[(name, name) for name in sorted(self.types)]]
        self.topic.value = current

    def _on_topic(self, change: dict[str, Any]) -> None:
        topic = change.get("new")
        self.field.options = ()
        if not isinstance(topic, str) or topic not in self.types or self.link is None:
            return
        self._fields_for = topic
        self.status.value = "<small>Reading the topic's type definition…</small>"
        args = (self.link, topic, self.types[topic])
        threading.Thread(target=self._list_fields, args=args, daemon=True, name="pmk-fieldplot-fields").start()

    def _list_fields(self, link: LinkCore, topic: str, type_name: str) -> None:
        try:
            fields = numeric_fields(link.discovery.message_details(type_name, timeout=5.0), type_name)
            note = f"{len(fields)} numeric fields of {type_name}" if fields else "no type definition: type a field"
        except (PmkError, OSError) as err:  # no rosapi, a busy bridge: a field can still be typed
            log.info("reading the type definition of %s failed: %s", type_name, err)
            fields, note = [], "the bridge gave no type definition: type a field's path"
        with self._lock:
            self._pending_fields = (topic, fields, note)

    # -- series ---------------------------------------------------------------------------------------------
    def add(self, topic: object, path: object) -> bool:
        """Plot ``path`` of ``topic``; refused in words (status) when either is unknown or malformed."""
        if not isinstance(topic, str) or topic not in self.types:
            self.status.value = "<span class='pmk-msg-warning'>Pick a topic first.</span>"
            return False
        path = path.strip() if isinstance(path, str) else ""
        if not PATH.match(path):
            self.status.value = "<span class='pmk-msg-warning'>Pick or type a field, e.g. twist.twist.linear.x.</span>"
            return False
        if (topic, path) in self.series:
            return True
        if len(self.series) >= MAX_SERIES:
            self.status.value = f"<span class='pmk-msg-warning'>At most {MAX_SERIES} series: remove one first.</span>"
            return False
        if self.link is None or not self.link.is_connected:
            self.status.value = "<span class='pmk-msg-warning'>Not connected to the chair.</span>"
            return False
        sub = self.subs.get(topic)
        if sub is None:
            sub = self.subs[topic] = TopicSeries(self.link.ros, topic, self.types[topic])
        sub.add_field(path)
        self.series.append((topic, path))
        self.status.value = ""
        self._show_series()
        self.redraw()
        return True

    def remove(self, key: object) -> None:
        """Stop plotting the series named ``key`` ("topic field"); its topic's subscription ends with its last."""
        found = [s for s in self.series if f"{s[0]} {s[1]}" == key]
        for topic, path in found:
            self.series.remove((topic, path))
            sub = self.subs.get(topic)
            if sub is not None:
                sub.remove_field(path)
                if not sub.fields:
                    sub.stop()
                    del self.subs[topic]
        self._show_series()
        self.redraw()

    def _show_series(self) -> None:
        self.list.options = [f"{t} {f}" for t, f in self.series]

    def _on_pause(self, change: dict[str, Any]) -> None:
        on = change.get("new") is True
        self.paused_at = time.monotonic() if on else None
        self.pause.icon = "play" if on else "pause"
        self.pause.description = "Resume" if on else "Pause"
        self.redraw()

    # -- timer and drawing -----------------------------------------------------------------------------------
    def tick(self, now: float | None = None) -> None:
        """From Home's info timer (while the panel is open): field lists in, the chart at PLOT_HZ."""
        now = time.monotonic() if now is None else now
        with self._lock:
            pending, self._pending_fields = self._pending_fields, None
        if pending is not None and pending[0] == self._fields_for == self.topic.value:
            self.field.options = tuple(pending[1])
            self.status.value = f"<small>{escape(pending[2])}</small>"
        if self.paused_at is None and now - self._drawn_at >= 1.0 / PLOT_HZ:
            self.redraw(now)

    def redraw(self, now: float | None = None) -> None:
        """Draw the chart (one ``hold_canvas``); paused, at the moment Pause was pressed."""
        now = self.paused_at if self.paused_at is not None else (time.monotonic() if now is None else now)
        self._drawn_at = now
        span = float(self.window.value)
        width, height = CHART[0] - PAD[0], CHART[1] - 2 * PAD[1]
        windows = [self._samples(topic, path, now - span, now) for topic, path in self.series]
        plot = series_lines(windows, now, span, width, height)
        c = self.canvas
        with hold_canvas():
            c.clear()
            c.fill_style = "white"
            c.fill_rect(0, 0, CHART[0], CHART[1])
            c.stroke_style, c.line_width = "rgba(0, 0, 0, 0.15)", 1
            for frac in (0.0, 0.5, 1.0):
                c.stroke_line(PAD[0], PAD[1] + frac * (height - 1), CHART[0], PAD[1] + frac * (height - 1))
            c.font, c.fill_style = "11px sans-serif", "rgb(60, 60, 60)"
            c.fill_text(f"{plot.y_max:g}", 2, PAD[1] + 4)
            c.fill_text(f"{plot.y_min:g}", 2, PAD[1] + height - 1)
            for i, pts in enumerate(plot.lines):
                if pts.shape[0] >= 2:
                    c.stroke_style, c.line_width = COLOURS[i % len(COLOURS)], 2
                    c.stroke_lines(pts + np.array(PAD, dtype=float))
        self.legend.value = self._legend(windows, span)
        self.draws += 1

    def _samples(self, topic: str, path: str, since: float, until: float) -> np.ndarray:
        sub = self.subs.get(topic)
        ring = sub.rings.get(path) if sub is not None else None
        rows = ring.window(since) if ring is not None else np.empty((0, 2))
        return rows[rows[:, 0] <= until]

    def _legend(self, windows: list[np.ndarray], span: float) -> str:
        items = []
        for i, ((topic, path), rows) in enumerate(zip(self.series, windows, strict=True)):
            last = f" = {rows[-1, 1]:.4g}" if rows.shape[0] else " (no samples yet)"
            items.append(
                f"<span style='color:{COLOURS[i % len(COLOURS)]}'>━ {escape(topic)} {escape(path)}{last}</span>"
            )
        words = "paused" if self.paused_at is not None else "live"
        label = next((name for name, secs in WINDOWS if secs == span), f"{span:g} s")
        return (
            f"<small>{' &nbsp; '.join(items) or 'No series yet: pick a topic and a field, then Add.'}"
            + f" · last {label}, {words}</small>"
        )

    def close(self) -> None:
        self.attach(None)
        self.canvas.close()
