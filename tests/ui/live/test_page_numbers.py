"""Issue 38: a page's numbers in canvas events and size messages are bounded: a 400-digit integer
(OverflowError in ``float()``) or a finite 1e300 (inf once subtracted) is ignored, never raised, and
never moves or zooms the map."""

from __future__ import annotations

import json
import math

import pytest

from pmk_nb.ui.common.page_numbers import PAGE_PX_LIMIT, page_number
from pmk_nb.ui.home.fit import parse_fit
from pmk_nb.ui.live.gestures import pinch_distance, touch_point
from pmk_nb.ui.live.view import LiveView
from tests.ui.live.test_live import frontend_event, sample_grid

HUGE = 10**400  # float(HUGE) raises OverflowError
FAR = 1e300  # finite, but FAR - (-FAR) is inf


def repr_short(value: object) -> str:
    return "huge" if value in (HUGE, -HUGE) else repr(value)


@pytest.mark.parametrize(
    "value", [HUGE, -HUGE, FAR, -FAR, math.inf, math.nan, True, None, "x", [1], PAGE_PX_LIMIT * 2], ids=repr_short
)
def test_a_page_number_out_of_bounds_is_none(value: object) -> None:
    assert page_number(value) is None


@pytest.mark.parametrize(("value", "number"), [(0, 0.0), (-12, -12.0), (3.5, 3.5), ("7", 7.0), (PAGE_PX_LIMIT, 1e6)])
def test_a_page_number_in_bounds_is_a_float(value: object, number: float) -> None:
    assert page_number(value) == number


@pytest.mark.parametrize("bad", [HUGE, FAR], ids=["huge", "far"])
def test_touch_helpers_take_no_unbounded_number(bad: object) -> None:
    assert touch_point([(bad, 1)]) is None and touch_point([(1, bad)]) is None
    assert pinch_distance([(0, 0), (bad, 0)]) is None and pinch_distance([(bad, 0), (0, 0)]) is None
    assert pinch_distance([(-FAR / 1e294, 0), (FAR / 1e294, 0)]) == pytest.approx(2e6)  # at the bound: finite


@pytest.mark.parametrize("bad", [HUGE, -HUGE, FAR], ids=["huge", "-huge", "far"])
def test_no_canvas_event_raises_or_moves_the_map_on_an_unbounded_number(bad: object) -> None:
    """The handlers are called as ipycanvas calls them (its dispatcher would swallow a raise)."""
    view = LiveView(320, 240, max_zoom=6)
    view.set_map(sample_grid())
    view.set_zoom(3)
    assert view.viewport is not None
    before = (view.zoom, tuple(view.viewport.center))
    g = view.gestures
    g.last_wheel = 0.0
    g.on_wheel(0, bad)
    g.on_mouse_down(10, 10)
    g.on_mouse_move(bad, 10)
    g.on_mouse_move(10, bad)
    g.on_mouse_up(bad, bad)
    g.on_mouse_down(-FAR, 10)
    g.on_mouse_move(bad, 20)
    g.on_mouse_up(20, 20)
    g.on_touch([(bad, 1)])
    g.on_touch([(1, bad)])
    g.on_touch([(0, 0), (100, 0)])
    g.on_touch([(0, 0), (bad, 0)])
    g.on_touch_end([(bad, 0)])
    g.on_touch_end([])
    frontend_event(view, {"event": "mouse_move", "x": bad, "y": 1})  # and through the widget's messages
    assert (view.zoom, tuple(view.viewport.center)) == before
    assert all(math.isfinite(v) for v in view.viewport.center)
    view.close()


@pytest.mark.parametrize(
    "message",
    [
        '{"w": 1' + "0" * 400 + ', "h": 700}',
        '{"w": 390, "h": -1' + "0" * 400 + "}",
        '{"w": 1e300, "h": 700}',
    ],
    ids=["huge-width", "huge-height", "far-width"],
)
def test_a_size_message_with_an_unbounded_number_is_ignored(message: str) -> None:
    assert parse_fit(message) is None


def test_a_box_with_an_unbounded_number_is_dropped() -> None:
    boxes = [[1, 2, 3, 4], [HUGE, 2, 3, 4], [1, 2, 3, -HUGE], [1, FAR, 3, 4], [5, 6, 7, 8]]
    fit = parse_fit(json.dumps({"w": 390, "h": 700, "boxes": boxes}))
    assert fit == (390, 700, [(1.0, 2.0, 3.0, 4.0), (5.0, 6.0, 7.0, 8.0)])
