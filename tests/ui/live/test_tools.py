"""The map tools on the live view, kernel side: taps through the canvas's own event handlers give the
distance and the initial pose; the pointer's map coordinates; the scale bar and grid drawn (issue 29)."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

from pmk_nb.grid import OccupancyGrid
from pmk_nb.ui.live.tools import MapTools
from pmk_nb.ui.live.view import LiveView


class FakeLink:
    """Records initial poses; stands for a connected ChairLink."""

    def __init__(self, connected: bool = True) -> None:
        self.connected = connected
        self.poses: list[tuple[float, float, float]] = []

    def set_initial_pose(self, x: float, y: float, yaw: float) -> bool:
        if self.connected:
            self.poses.append((x, y, yaw))
        return self.connected


def tools_on_map() -> tuple[LiveView, MapTools]:
    live = LiveView(400, 200)
    live.set_map(OccupancyGrid(np.zeros((100, 200), np.int8), 0.05, (0.0, 0.0, 0.0)))  # 10 x 5 m, 40 px/m
    return live, MapTools(live)


def tap(live: LiveView, x: float, y: float) -> None:
    live.gestures.on_mouse_down(x, y)
    live.gestures.on_mouse_up(x, y)


def test_measure_two_taps_gives_the_distance_and_a_third_starts_again() -> None:
    live, tools = tools_on_map()
    tools.mode.value = "measure"
    assert live.gestures.picker is tools.picker
    tap(live, 40.0, 160.0)  # map (1, 1)
    assert "second point" in tools.readout.value
    tap(live, 160.0, 0.0)  # map (4, 5)
    assert "5.00 m" in tools.readout.value and "pmk-tools-distance" in tools.readout.value
    assert tools.overlay.points == [pytest.approx((1.0, 1.0)), pytest.approx((4.0, 5.0))]
    live.gestures.on_mouse_down(40.0, 40.0)  # a drag is not a tap: nothing measured, nothing panned
    live.gestures.on_mouse_move(120.0, 40.0)
    live.gestures.on_mouse_up(120.0, 40.0)
    assert len(tools.overlay.points) == 2
    tap(live, 200.0, 100.0)
    assert len(tools.overlay.points) == 1
    tools.mode.value = "pan"
    assert live.gestures.picker is None and tools.overlay.points == []
    tools._on_mode({"new": ["garbage"]})  # whatever reaches the observer: treated as Pan
    assert live.gestures.picker is None


def test_pointer_coordinates_in_the_map_frame() -> None:
    live, tools = tools_on_map()
    live.gestures.on_mouse_move(80.0, 120.0)
    assert "x 2.00 m, y 2.00 m" in tools.pointer.value
    live.gestures.on_touch([[40.0, 160.0]])
    assert "x 1.00 m, y 1.00 m" in tools.pointer.value
    live.gestures.on_mouse_move("nan", None)  # garbage: ignored
    assert "x 1.00 m" in tools.pointer.value


def test_set_pose_tap_position_then_heading_publishes_once() -> None:
    live, tools = tools_on_map()
    link = FakeLink()
    tools.attach(link)
    tools.mode.value = "pose"
    tap(live, 80.0, 120.0)  # (2, 2)
    assert "now tap the way it faces" in tools.readout.value and link.poses == []
    tap(live, 80.0, 40.0)  # (2, 4): facing +y
    assert link.poses == [(pytest.approx(2.0), pytest.approx(2.0), pytest.approx(math.pi / 2))]
    assert "Initial pose sent" in tools.readout.value and "heading 90°" in tools.readout.value
    assert tools.mode.value == "pan" and live.gestures.picker is None
    tools.attach(FakeLink(connected=False))
    tools.mode.value = "pose"
    tap(live, 80.0, 120.0)
    tap(live, 120.0, 120.0)
    assert "not sent" in tools.readout.value and "preview" in tools.readout.value


def test_set_pose_is_refused_on_a_locked_kiosk() -> None:
    from pmk_nb.errors import KioskLocked

    class Ctx:
        def require_unlocked(self, action: str) -> None:
            raise KioskLocked("the kiosk is locked.", action=action, hint="Open the screen with the PIN first.")

    live = LiveView(400, 200)
    live.set_map(OccupancyGrid(np.zeros((100, 200), np.int8), 0.05, (0.0, 0.0, 0.0)))
    tools = MapTools(live, Ctx())  # type: ignore[arg-type]
    link = FakeLink()
    tools.attach(link)
    with pytest.raises(KioskLocked):
        tools.set_initial_pose(1.0, 1.0, 0.0)
    tools.mode.value = "pose"
    tap(live, 80.0, 120.0)
    tap(live, 120.0, 120.0)
    assert link.poses == [] and "locked" in tools.readout.value


def test_scale_bar_and_grid_are_drawn_and_follow_the_zoom(monkeypatch: Any) -> None:
    live, tools = tools_on_map()
    texts: list[str] = []
    segments: list[int] = []
    layer = live.map_layer  # a map overlay: drawn with the map, under the chair
    real_fill_text, real_segments = layer.fill_text, layer.stroke_line_segments
    monkeypatch.setattr(layer, "fill_text", lambda t, *a, **k: (texts.append(t), real_fill_text(t, *a, **k)))
    monkeypatch.setattr(layer, "stroke_line_segments", lambda p, *a: (segments.append(len(p)), real_segments(p, *a)))
    live.request_redraw()
    assert "2 m" in texts and "2 m" in tools.scale.value  # 40 px/m: 2 m = 80 px <= 120 px
    assert segments == []
    tools.grid.value = True
    assert segments and segments[-1] == 11 + 6  # x 0..10 and y 0..5 every metre
    live.zoom_in()
    live.zoom_in()  # 1.5^2 x 40 = 90 px/m: 2 m would be 180 px, more than the bar's 120
    assert "<b>1 m</b>" in tools.scale.value
    assert texts[-1] == "1 m"


def test_the_scale_bar_is_sent_with_the_map_not_in_every_frame_of_a_turning_chair(monkeypatch: Any) -> None:
    """A chair turning on the spot changes every frame, the view does not: the scale bar goes with
    the map layer once, and again only when the view changes (a zoom) or the tools do (Grid)."""
    from tests.ui.live.test_live import Source

    live, tools = tools_on_map()
    texts: list[str] = []
    real_fill_text = live.map_layer.fill_text
    monkeypatch.setattr(live.map_layer, "fill_text", lambda t, *a, **k: (texts.append(t), real_fill_text(t, *a, **k)))
    source = Source()
    source.set_scan()
    live._source = source
    drawn = 0
    for i in range(8):
        source.move(5.0, 2.5, 0.2 * i)
        drawn += live.render_frame()
    assert drawn == 8, "every turning frame is drawn"
    assert texts == ["2 m"], f"the scale bar went {len(texts)} times in 8 frames of a view that did not move"
    live.zoom_in()
    source.move(5.0, 2.5, 2.0)
    live.render_frame()
    assert len(texts) == 2, "a zoom sends it again"
    tools.grid.value = True
    source.move(5.0, 2.5, 2.2)
    live.render_frame()
    assert len(texts) == 3, "so does a change of the tools (Grid on)"


def test_the_scale_bar_stays_clear_of_the_panels_over_the_canvas(monkeypatch: Any) -> None:
    """Issue 40, item 7: Home's status pill (bottom left, 46 px high here) covered the scale bar."""
    from pmk_nb.viewport import Insets, insets_from_boxes

    live, _tools = tools_on_map()
    layer = live.map_layer
    lines: list[tuple[float, float, float, float]] = []
    real = layer.stroke_line
    monkeypatch.setattr(layer, "stroke_line", lambda *a: (lines.append(a), real(*a)))
    pill = (6.0, 148.0, 250.0, 46.0)  # x, y, width, height in canvas pixels: the status line's box
    live.set_insets(insets_from_boxes(400, 200, [pill]))
    assert live.viewport is not None and live.viewport.insets.bottom >= 46.0
    live.request_redraw()
    _x0, y0, _x1, y1 = lines[-1]  # the bar's white underlay: one line
    assert y0 == y1 and y0 < pill[1] - 3, f"the bar at y {y0} is under the pill (from y {pill[1]})"
    live.set_insets(Insets())
    live.request_redraw()
    assert lines[-1][1] == 200 - 14  # nothing over the canvas: the corner
