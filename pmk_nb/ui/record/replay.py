"""A recording's replay: the chair's pose, its laser and its planned path following a time slider.

What is shown at each time comes from :class:`pmk_nb.recordings.timeline.Timeline` (pure); this module
only draws it: a matplotlib figure (Agg, no pyplot state) as a PNG in an ``<img alt>`` whose text says
what the picture shows, for a reader who cannot see it. The view is framed on the whole drive (its
poses, 2 m round them), so it does not jump while the slider moves; the recorded map, if any, is the
background.
"""

from __future__ import annotations

import io
import math
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
        self.slider.observe(lambda change: self.show(float(change["new"])), names="value")
        self.widget = w.VBox([self.picture, self.slider, self.caption])
        self.widget.add_class("pmk-replay")
        self.show(start)  # the first pose: before it the replay has no chair to show

    def show(self, t: float) -> ReplayFrame:
        """Draw the recording at ``t`` seconds since it began."""
        self.frame = self.timeline.at(t)
        said = frame_text(self.timeline, self.frame)
        self.picture.value = picture_html(draw(self.timeline, self.frame), f"Replay of {self.path.name}: {said}")
        self.caption.value = escape(said)
        return self.frame
