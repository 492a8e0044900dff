"""The witness's own pixel fill agrees with shapely's point-in-polygon on every pixel centre."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from pmk_nb.grid import OccupancyGrid
from pmk_nb.witness.frame import MapFrame, Window, outline

coord = st.floats(min_value=-3.0, max_value=13.0, allow_nan=False).map(lambda v: round(v, 3))


@st.composite
def shapes(draw: st.DrawFn) -> shapely.Geometry:
    """Random polygons (convex hulls of points, some with a hole, some in two parts)."""
    pts = draw(st.lists(st.tuples(coord, coord), min_size=3, max_size=9))
    poly = shapely.MultiPoint(pts).convex_hull
    assume(poly.geom_type == "Polygon")  # collinear points give a line: cells are polygons
    if draw(st.booleans()):
        poly = poly.difference(poly.centroid.buffer(draw(st.floats(0.1, 2.0))))
    if draw(st.booleans()):
        poly = poly.union(shapely.box(*draw(st.tuples(coord, coord)), 14.0, 14.0))
    return poly


@pytest.mark.slow
@settings(max_examples=150, deadline=None)
@given(
    shape=shapes(),
    res=st.sampled_from([0.05, 0.1, 0.137]),
    window=st.tuples(st.integers(0, 40), st.integers(41, 120), st.integers(0, 40), st.integers(41, 120)),
)
def test_the_fill_is_shapely_point_in_polygon(shape: shapely.Geometry, res: float, window: tuple[int, ...]) -> None:
    frame = MapFrame(-1.0, -2.0, res, 120, 120)
    win = Window(*window)
    xs, ys = frame.centres(win)
    expected = shapely.contains_xy(shape, xs, ys) if not shape.is_empty else np.zeros(win.shape, bool)
    got = frame.mask(win, shape)
    on_edge = shapely.dwithin(shape.boundary, shapely.points(xs, ys), 1e-9) if not shape.is_empty else expected
    assert not np.any((got != expected) & ~on_edge)


def test_the_frame_of_a_grid_is_its_origin_resolution_and_size() -> None:
    grid = OccupancyGrid(np.zeros((30, 40), dtype=np.int8), 0.05, (1.5, -2.0, 0.0))
    frame = MapFrame.of(grid)
    assert (frame.x0, frame.y0, frame.resolution, frame.width, frame.height) == (1.5, -2.0, 0.05, 40, 30)
    win = frame.window((1.5, -2.0, 1.6, -1.9))
    assert frame.point(win, 0, 0) == (1.525, -1.975)


@pytest.mark.slow
@settings(max_examples=200, deadline=None)
@given(
    corners=st.tuples(coord, coord, coord, coord),
    res=st.sampled_from([0.05, 0.1, 0.137]),
    window=st.tuples(st.integers(0, 40), st.integers(41, 120), st.integers(0, 40), st.integers(41, 120)),
)
def test_an_upright_rectangle_fills_as_any_polygon(
    corners: tuple[float, ...], res: float, window: tuple[int, ...]
) -> None:
    """The rectangle's shortcut (a slice) sets the pixels the general fill sets: the same box with one more
    vertex on its left side takes the general way."""
    x0, x1 = sorted(corners[:2])
    y0, y1 = sorted(corners[2:])
    assume(x1 - x0 > 1e-3 and y1 - y0 > 1e-3)
    frame = MapFrame(-1.0, -2.0, res, 120, 120)
    win = Window(*window)
    box = shapely.box(x0, y0, x1, y1)
    same = shapely.Polygon([(x0, y0), (x1, y0), (x1, y1), (x0, y1), (x0, (y0 + y1) / 2)])
    np.testing.assert_array_equal(frame.mask(win, box), frame.mask(win, same))
    xs, ys = frame.centres(win)
    on_edge = shapely.dwithin(box.boundary, shapely.points(xs, ys), 1e-9)
    assert not np.any((frame.mask(win, box) != shapely.contains_xy(box, xs, ys)) & ~on_edge)


def test_a_rectangle_below_the_window_sets_nothing() -> None:
    """A window starting a row or two above an upright rectangle (inside the rows its bounds may touch,
    as a strip of rows does) gets none of it: the rectangle's shortcut once set a row there, as a slice
    with a negative end wraps round."""
    frame = MapFrame(0.0, 0.0, 0.1, 50, 50)
    box = shapely.box(0.2, 0.0, 1.0, 0.93)  # pixel rows 0..8 (centres 0.05..0.85)
    win = Window(10, 12, 0, 20)
    assert not frame.mask(win, box).any()
    whole = frame.mask(Window(0, 12, 0, 20), box)
    assert whole[:9, 2:10].all() and whole.sum() == 9 * 8


def test_the_rectangle_window_is_what_the_mask_sets() -> None:
    """MapFrame.rectangle: the pixels an upright rectangle's mask sets, as a window (clipped to the grid);
    None for any other shape."""
    frame = MapFrame(-1.0, -2.0, 0.1, 120, 120)
    whole = Window(0, 120, 0, 120)
    for box in (shapely.box(0.23, -0.4, 3.01, 2.96), shapely.box(-3.0, -5.0, 0.5, 0.5), shapely.box(0.0, 0.0, 0.04, 1)):
        rect = frame.rectangle(outline(box))
        assert rect is not None
        want = frame.mask(whole, box)
        got = np.zeros_like(want)
        got[rect.r0 : rect.r1, rect.c0 : rect.c1] = True
        np.testing.assert_array_equal(got, want)
    slanted = shapely.Polygon([(0, 0), (1, 0), (1.2, 1), (0, 1)])
    assert frame.rectangle(outline(slanted)) is None
    assert frame.rectangle(outline(shapely.Polygon([(0, 0), (1, 0), (1, 1), (0, 1), (0, 0.5)]))) is None
