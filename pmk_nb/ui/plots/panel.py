"""Home's Plots panel (issue 29): speed and turn rate over the last minutes, any numeric field of any
topic (issue 40, :mod:`pmk_nb.ui.plots.field_plot`), the topic inspector and the TF tree
(:mod:`pmk_nb.ui.plots.tf_view`).

Details on demand: a "Plots" toggle beside Show sensors opens the panel under the map. The samples
come from Home's info timer (:meth:`PlotsPanel.tick`, a few per second, into the bounded
:class:`~pmk_nb.viewport.history.OdomHistory`, kept while the panel is closed so it opens with the
last minutes), and the chart is redrawn at most :data:`PLOT_HZ` times a second, only while open:
one small ipycanvas, one ``hold_canvas`` per redraw, no plotting library.
"""

from __future__ import annotations

import math
import time
from typing import TYPE_CHECKING, Any

import ipywidgets as w
import numpy as np
from ipycanvas import Canvas, hold_canvas

from pmk_nb.ui.common.widgets import TOUCH_PX
from pmk_nb.ui.home.info import whole_degrees
from pmk_nb.ui.plots.field_plot import FieldPlot
from pmk_nb.ui.plots.tf_view import TfTreeView
from pmk_nb.ui.plots.topic_inspector import TopicInspector
from pmk_nb.viewport import OdomHistory, plot_lines

if TYPE_CHECKING:
    from pmk_nb.chair.link import LinkCore

PLOT_HZ = 2.0  # chart redraws per second while the panel is open
SPAN_S = 300.0  # the chart shows the last five minutes
MIN_SPAN_S = 30.0  # ... or since the first sample, at least this long
CHART = (560, 180)  # canvas pixels
PAD = (46, 14)  # left margin for the axis labels, top/bottom margin
SPEED_RGB = "rgb(25, 90, 220)"
TURN_RGB = "rgb(230, 120, 0)"
GRID_RGB = "rgba(0, 0, 0, 0.15)"


class PlotsPanel:
    """``toggle`` goes in Home's controls, ``widget`` under the map (hidden until toggled)."""

    def __init__(self, span_s: float = SPAN_S) -> None:
        self.span_s = float(span_s)
        self.history = OdomHistory(capacity=int(span_s * 4) + 8)  # Home's info timer runs at 4 Hz
        self._drawn_at = -math.inf
        self._last_odom: Any = None
        self._link: LinkCore | None = None
        self.draws = 0
        self.toggle = w.ToggleButton(value=False, description="Plots", icon="line-chart")
        self.toggle.tooltip = "Speed and turn rate over time; the chair's topics"
        self.toggle.layout = w.Layout(height=f"{TOUCH_PX}px", width="auto", min_width="120px")
        self.toggle.add_class("pmk-plots-toggle")
        self.canvas = Canvas(width=CHART[0], height=CHART[1])
        self.canvas.layout = w.Layout(width=f"{CHART[0]}px", max_width="100%", height="auto")
        self.canvas.add_class("pmk-plots-chart")
        self.legend = w.HTML(_legend(None, None, span_s))
        self.legend.add_class("pmk-plots-legend")
        self.topics = TopicInspector()
        self.fields = FieldPlot()  # any numeric field of any topic (issue 40)
        self.tf = TfTreeView()  # frames, parents, rates and ages (issue 40)
        self.widget = w.VBox(
            [
                w.HTML("<b>Speed and turn rate</b>"),
                self.canvas,
                self.legend,
                w.HTML("<b>Plot any field</b>"),
                self.fields.widget,
                w.HTML("<b>Topics</b>"),
                self.topics.widget,
                w.HTML("<b>TF tree</b>"),
                self.tf.widget,
            ]
        )
        self.widget.add_class("pmk-plots-panel")
        self.widget.layout.display = "none"
        self.toggle.observe(self._on_toggle, names="value")

    @property
    def open(self) -> bool:
        return self.toggle.value is True

    def attach(self, link: LinkCore | None) -> None:
        """The preview's link (None: stopped). The history is kept across previews of the same page."""
        self.topics.attach(link if self.open else None)
        self.fields.attach(link if self.open else None)
        self.tf.attach(link if self.open else None)
        self._link = link

    def _on_toggle(self, change: dict[str, Any]) -> None:
        on = change.get("new") is True  # anything but a real True from the page is off
        self.widget.layout.display = "" if on else "none"
        self.toggle.icon = "check" if on else "line-chart"
        self.topics.attach(self._link if on else None)  # closing ends the inspected topic's subscription
        self.fields.attach(self._link if on else None)  # ... and the plotted topics'
        self.tf.attach(self._link if on else None)  # ... and the TF tree's /tf, /tf_static
        if on:
            self._drawn_at = -math.inf
            self.redraw()

    def tick(self, odom: Any, now: float | None = None) -> None:
        """From Home's info timer: keep the newest odometry sample; redraw at PLOT_HZ while open."""
        now = time.monotonic() if now is None else now
        if odom is not None and odom is not self._last_odom:
            self._last_odom = odom
            self.history.add(float(odom.received), float(odom.v), float(odom.w))
        if not self.open:
            return
        self.topics.tick()
        self.fields.set_topics(self.topics.types)
        self.fields.tick(now)
        self.tf.tick()
        if now - self._drawn_at >= 1.0 / PLOT_HZ:
            self._drawn_at = now
            self.redraw(now)

    def redraw(self, now: float | None = None) -> None:
        """Draw the chart from the history (one ``hold_canvas``)."""
        now = time.monotonic() if now is None else now
        width, height = CHART[0] - PAD[0], CHART[1] - 2 * PAD[1]
        samples = self.history.window(now - self.span_s)
        # the time axis grows with the history, from MIN_SPAN_S to span_s: a fresh preview's first
        # seconds fill the chart instead of a sliver at its right edge
        age = now - float(samples[0, 0]) if samples.shape[0] else 0.0
        span = min(self.span_s, max(MIN_SPAN_S, age))
        lines = plot_lines(samples, now, span, width, height)
        c = self.canvas
        with hold_canvas():
            c.clear()
            c.fill_style = "white"
            c.fill_rect(0, 0, CHART[0], CHART[1])
            c.stroke_style = GRID_RGB
            c.line_width = 1
            for frac in (0.0, 0.25, 0.5, 0.75, 1.0):
                y = PAD[1] + frac * (height - 1)
                c.stroke_line(PAD[0], y, CHART[0], y)
            c.font = "11px sans-serif"
            c.fill_style = SPEED_RGB
            c.fill_text(f"{lines.speed_max:g} m/s", 2, PAD[1] + 4)
            c.fill_style = TURN_RGB
            c.fill_text(f"{lines.turn_max:g} °/s", 2, PAD[1] + 18)
            c.fill_style = "rgb(90, 90, 90)"
            c.fill_text("0", 2, PAD[1] + height / 2 + 4)
            for pts, rgb in ((lines.speed, SPEED_RGB), (lines.turn, TURN_RGB)):
                if pts.shape[0] >= 2:
                    pts = pts + np.array(PAD, dtype=float)
                    c.stroke_style = rgb
                    c.line_width = 2
                    c.stroke_lines(pts)
        last = samples[-1] if samples.shape[0] else None
        self.legend.value = _legend(
            None if last is None else float(last[1]), None if last is None else float(last[2]), span
        )
        self.draws += 1

    def close(self) -> None:
        self.topics.attach(None)
        self.fields.close()
        self.tf.close()
        self.canvas.close()


def _legend(v: float | None, w_rad: float | None, span_s: float) -> str:
    now = "" if v is None or w_rad is None else f" · now {v:.2f} m/s, {whole_degrees(w_rad)}°/s"
    return (
        f"<small><span style='color:{SPEED_RGB}'>━ speed (m/s)</span> &nbsp; "
        f"<span style='color:{TURN_RGB}'>━ turn rate (°/s)</span> · last {_span_words(span_s)}{now}</small>"
    )


def _span_words(span_s: float) -> str:
    return f"{span_s:.0f} s" if span_s < 120 else f"{span_s / 60:.0f} min"
