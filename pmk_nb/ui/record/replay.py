"""A recording's replay: the chair's pose, its laser and its planned path following a time slider, and
a plot of any numeric field of the recording with a cursor at the slider's time.

What is shown at each time comes from :class:`pmk_nb.recordings.timeline.Timeline` (pure); this module
only draws it: a matplotlib figure (Agg, no pyplot state) as a PNG in an ``<img alt>`` whose text says
what the picture shows, for a reader who cannot see it. The view is framed on the whole drive (its
poses, 2 m round them), so it does not jump while the slider moves; the recorded map, if any, is the
background. The plot is drawn once per chosen field; the slider moves only its cursor (a line laid over
the picture where its axes are), so scrubbing costs one picture, not two.
"""

from __future__ import annotations

import io
import math
from dataclasses import dataclass
from pathlib import Path

import ipywidgets as w
import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from pmk_nb.recordings import ReplayFrame, Tables, Timeline, read_recording
from pmk_nb.ui.common.widgets import escape, html_slot, picture_html

MARGIN_M = 2.0
STEP_S = 0.1  # the slider's step
SIZE_IN = (6.0, 4.5)
PLOT_SIZE_IN = (6.0, 2.2)


def frame_text(timeline: Timeline, frame: ReplayFrame) -> str:
    """The caption and the picture's text alternative."""
    parts = [f"{frame.t:.1f} s of {timeline.duration:.1f} s"]
    if frame.pose is None:
        parts.append("no pose yet")
    else:
        x, y, yaw = frame.pose
        parts.append(f"chair at x {x:.2f} m, y {y:.2f} m, heading {math.degrees(yaw):.0f}°")
    if frame.laser is not None:
        parts.append(f"{len(frame.laser)} laser hits")
    if frame.path is not None:
        parts.append(f"planned path of {len(frame.path)} points")
    return " · ".join(parts)


def _bounds(timeline: Timeline) -> tuple[float, float, float, float] | None:
    poses = timeline.poses()
    if poses.size == 0:
        return None
    (x0, y0), (x1, y1) = poses.min(axis=0), poses.max(axis=0)
    return x0 - MARGIN_M, x1 + MARGIN_M, y0 - MARGIN_M, y1 + MARGIN_M


def draw(timeline: Timeline, frame: ReplayFrame) -> bytes:
    """The frame as a PNG: map, the drive so far, the planned path, the laser hits, the chair."""
    fig = Figure(figsize=SIZE_IN, dpi=80)
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    grid = timeline.grid
    if grid is not None:
        shown = np.select([grid.cells < 0, grid.cells >= 50], [0.75, 0.0], 1.0)
        ax.imshow(shown, cmap="gray", vmin=0, vmax=1, origin="lower", extent=grid.extent, interpolation="nearest")
    poses = timeline.poses(until=frame.t)
    if len(poses):
        ax.plot(poses[:, 0], poses[:, 1], "-", color="tab:blue", lw=1.5, alpha=0.6, label="driven")
    if frame.path is not None and len(frame.path):
        ax.plot(frame.path[:, 0], frame.path[:, 1], "--", color="tab:green", lw=2, label="planned path")
    if frame.laser is not None and len(frame.laser):
        ax.scatter(frame.laser[:, 0], frame.laser[:, 1], s=3, color="tab:red", label="laser")
    if frame.pose is not None:
        x, y, yaw = frame.pose
        ax.plot(x, y, "o", color="black", ms=8)
        ax.arrow(x, y, 0.6 * math.cos(yaw), 0.6 * math.sin(yaw), width=0.06, color="black")
    bounds = _bounds(timeline)
    if bounds is not None:
        ax.set_xlim(bounds[0], bounds[1])
        ax.set_ylim(bounds[2], bounds[3])
    ax.set_aspect("equal", adjustable="box")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    if ax.get_legend_handles_labels()[0]:
        ax.legend(loc="upper right", fontsize="small")
    fig.tight_layout()
    out = io.BytesIO()
    fig.savefig(out, format="png")
    return out.getvalue()


@dataclass(frozen=True)
class SeriesPicture:
    """A field's plot as a PNG, with where its axes sit (fractions of the picture, from its top left)
    and the time span they show: enough to lay the cursor over it in the page."""

    png: bytes
    left: float
    right: float
    top: float
    bottom: float
    t_max: float

    def cursor_left(self, t: float) -> float:
        """The cursor's left edge at ``t`` seconds, in percent of the picture's width."""
        share = min(max(t / self.t_max, 0.0), 1.0) if self.t_max > 0 else 0.0
        return 100.0 * (self.left + share * (self.right - self.left))


def draw_series(times: np.ndarray, values: np.ndarray, label: str, duration: float) -> SeriesPicture:
    """One field over the whole recording (steps: each value holds until the next message)."""
    fig = Figure(figsize=PLOT_SIZE_IN, dpi=80)
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    if len(times):
        ax.step(times, values, where="post", color="tab:blue", lw=1.3)
    t_max = max(duration, STEP_S)
    ax.set_xlim(0.0, t_max)
    ax.set_xlabel("time [s]")
    ax.set_title(label, fontsize="small")
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    out = io.BytesIO()
    fig.savefig(out, format="png")
    box = ax.get_position()
    return SeriesPicture(out.getvalue(), box.x0, box.x1, 1.0 - box.y1, 1.0 - box.y0, t_max)


def series_html(picture: SeriesPicture, t: float, alt: str) -> str:
    """The plot with its cursor at ``t``: an ``<img alt>`` and a line laid over its axes."""
    img = picture_html(picture.png, alt, style="max-width: 100%; height: auto; display: block")
    cursor = (
        f'<div class="pmk-replay-cursor" aria-hidden="true" style="position: absolute; '
        f"left: {picture.cursor_left(t):.2f}%; top: {100 * picture.top:.2f}%; "
        f'height: {100 * (picture.bottom - picture.top):.2f}%; width: 2px; background: #c62828"></div>'
    )
    return f'<div class="pmk-replay-plot-box" style="position: relative; display: inline-block">{img}{cursor}</div>'


def field_label(topic: str, field: str) -> str:
    return f"{topic} · {field}"


class ReplayView:
    """A recording's replay: a picture and a time slider under it; ``widget`` goes on the page."""

    def __init__(self, path: str | Path, tables: Tables | None = None) -> None:
        self.path = Path(path)
        self.timeline = Timeline.from_tables(tables if tables is not None else read_recording(self.path))
        # the first pose, on the slider's steps (the page snaps a value to them: down would be before it)
        start = min(math.ceil(self.timeline.first_pose / STEP_S) * STEP_S, self.timeline.duration)
        self.slider = w.FloatSlider(
            value=start,
            min=0.0,
            max=max(self.timeline.duration, STEP_S),
            step=STEP_S,
            description="Time [s]",
            readout_format=".1f",
            continuous_update=True,
            layout=w.Layout(width="100%", max_width="40em"),
        )
        self.slider.add_class("pmk-replay-slider")
        self.picture = html_slot("pmk-replay-picture")
        self.caption = html_slot("pmk-replay-caption")
        self.frame: ReplayFrame = self.timeline.at(start)
        fields = self.timeline.numeric_fields()
        self.field = w.Dropdown(
            options=[(field_label(*f), f) for f in fields],
            value=self.timeline.default_field(),
            description="Plot",
            layout=w.Layout(width="100%", max_width="40em"),
        )
        self.field.add_class("pmk-replay-field")
        self.plot = html_slot("pmk-replay-plot")
        self.value = html_slot("pmk-replay-value")
        #: the plotted field and its picture (None: nothing plotted)
        self._series: tuple[tuple[str, str], SeriesPicture] | None = None
        self.slider.observe(lambda change: self.show(float(change["new"])), names="value")
        self.field.observe(lambda _change: self.plot_field(), names="value")
        plot_part = [self.field, self.plot, self.value] if fields else []
        self.widget = w.VBox([self.picture, self.slider, self.caption, *plot_part])
        self.widget.add_class("pmk-replay")
        self.plot_field(draw_cursor=False)
        self.show(start)  # the first pose: before it the replay has no chair to show

    def plot_field(self, *, draw_cursor: bool = True) -> None:
        """Draw the chosen field over the whole recording (the cursor then follows the slider)."""
        chosen = self.field.value
        if not isinstance(chosen, tuple) or len(chosen) != 2:
            self._series = None
            self.plot.value = self.value.value = ""
            return
        topic, name = chosen
        times, values = self.timeline.series(topic, name)
        self._series = (topic, name), draw_series(times, values, field_label(topic, name), self.timeline.duration)
        if draw_cursor:
            self._show_cursor(self.frame.t)

    def _show_cursor(self, t: float) -> None:
        if self._series is None:
            return
        (topic, name), series = self._series
        value = self.timeline.value_at(topic, name, t)
        label = field_label(topic, name)
        said = f"{label} = " + ("no message yet" if value is None else f"{value:.4g}") + f" at {t:.1f} s"
        self.plot.value = series_html(series, t, f"Plot of {label} over the recording; {said}")
        self.value.value = escape(said)

    def show(self, t: float) -> ReplayFrame:
        """Draw the recording at ``t`` seconds since it began."""
        self.frame = self.timeline.at(t)
        said = frame_text(self.timeline, self.frame)
        self.picture.value = picture_html(draw(self.timeline, self.frame), f"Replay of {self.path.name}: {said}")
        self.caption.value = escape(said)
        self._show_cursor(self.frame.t)
        return self.frame
