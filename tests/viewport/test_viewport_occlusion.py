"""Panels over the live canvas: the followed chair sits in the centre of the part they leave uncovered."""

from __future__ import annotations

import math

import pytest

from pmk_nb.viewport import Insets, Viewport, insets_from_boxes
from pmk_nb.viewport.occlusion import MIN_UNCOVERED_SHARE


def _view(w: int = 400, h: int = 300) -> Viewport:
    # a 100 m x 100 m map at 0.1 m per cell, origin at (0, 0)
    return Viewport(1000, 1000, 0.1, (0.0, 0.0), w, h)


def test_a_right_panel_puts_the_followed_chair_in_the_centre_of_the_left_part() -> None:
    view = _view()
    view.set_zoom(6)
    view.see_chair(50.0, 50.0)
    assert view.chair_pixel() == pytest.approx((200.0, 150.0))  # no panel: the canvas's centre
    view.set_insets(Insets(right=160.0))
    x, y = view.chair_pixel() or (math.nan, math.nan)
    assert x == pytest.approx((400 - 160) / 2) and y == pytest.approx(150.0)
    view.set_insets(Insets(left=160.0, top=60.0))  # the other hand, and a bar at the top
    x, y = view.chair_pixel() or (math.nan, math.nan)
    assert x == pytest.approx(160 + (400 - 160) / 2) and y == pytest.approx(60 + (300 - 60) / 2)
    view.set_insets(Insets())
    assert view.chair_pixel() == pytest.approx((200.0, 150.0))


def test_near_the_map_edge_the_chair_stays_out_from_under_the_panel() -> None:
    view = _view()
    view.set_zoom(6)
    view.set_insets(Insets(right=160.0))
    view.see_chair(99.5, 50.0)  # at the map's right edge: the view stops, the chair moves right
    x, _y = view.chair_pixel() or (math.nan, math.nan)
    assert x <= 400 - 160, "the chair is drawn under the panel"
    view.see_chair(0.5, 50.0)  # the left edge: the map's edge at the canvas's left edge
    x, _y = view.chair_pixel() or (math.nan, math.nan)
    assert 0 <= x < 40
    assert view.top_left[0] == pytest.approx(0.0)


def test_insets_survive_a_resize_and_never_cover_the_whole_canvas() -> None:
    view = _view()
    view.set_zoom(4)
    view.set_insets(Insets(right=390.0, left=390.0))  # nonsense from a page: most is kept free
    ins = view.insets
    assert ins.left + ins.right == pytest.approx(400 * (1 - MIN_UNCOVERED_SHARE))
    view.set_insets(Insets(right=100.0, top=float("nan"), bottom=-5.0))
    assert (view.insets.top, view.insets.bottom) == (0.0, 0.0)
    view.see_chair(50.0, 50.0)
    view.resize(800, 600)
    assert view.canvas_width == 800 and view.zoom == 4
    assert view.chair_pixel() == pytest.approx(((800 - 100) / 2, 300.0))
    with pytest.raises(ValueError):
        view.resize(0, 10)


def test_insets_from_the_boxes_the_page_reports() -> None:
    # a 200 px wide panel at the right edge, a 64 px bar along the top, one box off the canvas
    ins = insets_from_boxes(800, 600, [(590, 100, 200, 480), (0, 0, 800, 64), (900, 0, 10, 10), ("x", 0, 1, 1)])
    assert ins == Insets(left=0.0, top=64.0, right=210.0, bottom=0.0)
    # the same panel at the left edge
    assert insets_from_boxes(800, 600, [(10, 100, 200, 480)]).left == 210.0
    assert insets_from_boxes(800, 600, [(300, 560, 200, 40)]) == Insets(bottom=40.0)
    assert Insets(right=100.0).uncovered(800, 600) == (0.0, 0.0, 700.0, 600.0)


def test_a_drag_with_panels_moves_the_map_by_the_fingers_pixels_only() -> None:
    """A drag starts from where the view is (its target in the uncovered part), not from the view's
    inset-shifted centre: the map moves with the finger, with no jump by half a panel (stop 34)."""
    view = _view()
    view.set_zoom(6)
    view.set_insets(Insets(left=160.0, top=60.0))
    view.see_chair(50.0, 50.0)
    before = view.world_to_pixel(50.0, 50.0)
    view.pan_pixels(10.0, -4.0)
    after = view.world_to_pixel(50.0, 50.0)
    assert not view.following
    assert (float(after[0]) - float(before[0]), float(after[1]) - float(before[1])) == pytest.approx((10.0, -4.0))
