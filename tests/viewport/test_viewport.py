"""View maths of the live preview: zoom, follow, clamp, conversions (pure, no widgets)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pmk_nb.viewport import (
    MIN_CHAIR_RADIUS_PX,
    STILL_SPEED,
    Viewport,
    fit_canvas,
    heading_point,
    laser_segments,
)

sizes = st.integers(min_value=1, max_value=3000)
canvas = st.integers(min_value=50, max_value=1600)
resolutions = st.floats(min_value=0.01, max_value=1.0)
origins = st.floats(min_value=-500, max_value=500)
fractions = st.floats(min_value=-0.5, max_value=1.5)


@st.composite
def viewports(draw: st.DrawFn) -> Viewport:
    view = Viewport(
        draw(sizes),
        draw(sizes),
        draw(resolutions),
        (draw(origins), draw(origins), 0.3),
        draw(canvas),
        draw(canvas),
        zoom_step=draw(st.sampled_from([1.5, 2.0])),
        max_zoom=draw(st.integers(min_value=1, max_value=10)),
    )
    view.set_zoom(draw(st.integers(min_value=1, max_value=view.max_zoom)))
    return view


def world_point(view: Viewport, fu: float, fv: float) -> tuple[float, float]:
    """A world point at a fraction of the map's extent (fractions outside 0..1 leave the map)."""
    x = view.origin[0] + fu * view.map_width * view.resolution
    y = view.origin[1] + fv * view.map_height * view.resolution
    return x, y


@settings(max_examples=200, deadline=None)
@given(viewports(), fractions, fractions, fractions, fractions)
def test_world_pixel_world_round_trip(view: Viewport, fu: float, fv: float, cu: float, cv: float) -> None:
    view.follow(*world_point(view, cu, cv))
    x, y = world_point(view, fu, fv)
    px, py = view.world_to_pixel(x, y)
    bx, by = view.pixel_to_world(px, py)
    tol = 1e-6 * max(1.0, abs(x), abs(y), view.map_width * view.resolution)
    assert abs(bx - x) <= tol and abs(by - y) <= tol


@settings(max_examples=200, deadline=None)
@given(viewports(), fractions, fractions)
def test_clamp_keeps_view_inside_map_at_every_zoom(view: Viewport, fu: float, fv: float) -> None:
    view.follow(*world_point(view, fu, fv))
    for level in range(1, view.max_zoom + 1):
        view.set_zoom(level)
        u0, v0 = view.top_left
        vw, vh = view.view_size_cells
        eps = 1e-9 * max(view.map_width, view.map_height)
        for start, extent, size in ((u0, vw, view.map_width), (v0, vh, view.map_height)):
            if extent >= size:  # map narrower than the view: centred, both margins equal
                assert math.isclose(start + extent / 2, size / 2, rel_tol=1e-9, abs_tol=eps)
            else:
                assert start >= -eps and start + extent <= size + eps


@settings(max_examples=200, deadline=None)
@given(viewports(), fractions, fractions)
def test_followed_chair_is_centred_unless_clamped(view: Viewport, fu: float, fv: float) -> None:
    x, y = world_point(view, fu, fv)
    view.follow(x, y)
    px, py = view.world_to_pixel(x, y)
    u, v = view.world_to_cell(x, y)
    vw, vh = view.view_size_cells
    for p, c, extent, size, canvas_px in (
        (px, u, vw, view.map_width, view.canvas_width),
        (py, v, vh, view.map_height, view.canvas_height),
    ):
        free = extent < size and extent / 2 <= c <= size - extent / 2
        if free:
            assert abs(p - canvas_px / 2) < 1e-6 * max(1.0, canvas_px)
        else:  # clamped: the chair is off-centre towards the edge it is near (or the map is centred)
            assert not (extent < size and extent / 2 < c < size - extent / 2)


@settings(max_examples=100, deadline=None)
@given(viewports())
def test_zoom_in_then_out_returns_to_same_zoom(view: Viewport) -> None:
    before = view.zoom
    view.zoom_in()
    view.zoom_out()
    if before < view.max_zoom:
        assert view.zoom == before
    else:  # at the top, zoom_in is clamped and zoom_out steps down one
        assert view.zoom == before - 1 or view.max_zoom == 1


@settings(max_examples=200, deadline=None)
@given(viewports(), fractions, fractions)
def test_unzoomed_shows_the_whole_map(view: Viewport, fu: float, fv: float) -> None:
    view.set_zoom(1)
    view.follow(*world_point(view, fu, fv))
    corners_x, corners_y = world_point(view, np.array([0.0, 1.0]), np.array([0.0, 1.0]))  # type: ignore[arg-type]
    px, py = view.world_to_pixel(corners_x, corners_y)
    eps = 1e-6 * max(view.canvas_width, view.canvas_height)
    assert np.all(px >= -eps) and np.all(px <= view.canvas_width + eps)
    assert np.all(py >= -eps) and np.all(py <= view.canvas_height + eps)
    # and it fills the canvas along at least one axis
    span_x, span_y = abs(px[1] - px[0]), abs(py[1] - py[0])
    assert math.isclose(span_x, view.canvas_width, rel_tol=1e-9) or math.isclose(
        span_y, view.canvas_height, rel_tol=1e-9
    )


def test_y_is_flipped_and_origin_applied() -> None:
    view = Viewport(100, 50, 0.1, (-2.0, 3.0), 100, 50)  # 1 px per cell at zoom 1
    # lower-left corner of the map = bottom-left of the canvas
    px, py = view.world_to_pixel(-2.0, 3.0)
    assert (float(px), float(py)) == pytest.approx((0.0, 50.0))
    # top-right corner of the map = top-right of the canvas
    px, py = view.world_to_pixel(-2.0 + 10.0, 3.0 + 5.0)
    assert (float(px), float(py)) == pytest.approx((100.0, 0.0))
    # moving north (y up) moves up on screen
    assert float(view.world_to_pixel(0.0, 5.0)[1]) < float(view.world_to_pixel(0.0, 4.0)[1])


def test_vectorised_conversions_match_scalar() -> None:
    view = Viewport(300, 200, 0.05, (1.0, -1.0), 640, 480)
    view.set_zoom(4)
    view.follow(6.0, 3.0)
    xs = np.linspace(1.0, 16.0, 7)
    ys = np.linspace(-1.0, 9.0, 7)
    px, py = view.world_to_pixel(xs, ys)
    for i in range(7):
        sx, sy = view.world_to_pixel(xs[i], ys[i])
        assert (px[i], py[i]) == pytest.approx((float(sx), float(sy)))


def test_zoom_clamps_and_rejects_garbage() -> None:
    view = Viewport(100, 100, 0.05, (0, 0), 400, 400, max_zoom=5)
    assert view.set_zoom(99) == 5
    assert view.zoom_in() == 5
    assert view.set_zoom(-3) == 1
    assert view.zoom_out() == 1
    assert view.set_zoom(2.6) == 3
    assert view.set_zoom("4") == 4
    for bad in ("four", float("nan"), float("inf"), None):
        with pytest.raises(ValueError):
            view.set_zoom(bad)
    assert view.zoom == 4


def test_pinch_ratio_maps_to_levels() -> None:
    view = Viewport(100, 100, 0.05, (0, 0), 400, 400, zoom_step=2.0, max_zoom=6)
    assert view.zoom_for_pinch(2, 1.0) == 2
    assert view.zoom_for_pinch(2, 2.0) == 3
    assert view.zoom_for_pinch(2, 4.1) == 4
    assert view.zoom_for_pinch(3, 0.5) == 2
    assert view.zoom_for_pinch(3, 0.01) == 1
    assert view.zoom_for_pinch(3, 1000.0) == 6
    assert view.zoom_for_pinch(3, 0.0) == 3
    assert view.zoom_for_pinch(3, float("nan")) == 3


def test_small_map_axis_is_centred_when_zoomed() -> None:
    # a long corridor: 1000 x 20 cells in a 500 x 500 canvas -> zoom 2 still shows all 20 rows
    view = Viewport(1000, 20, 0.1, (0, 0), 500, 500, zoom_step=2.0)
    view.set_zoom(2)
    view.follow(95.0, 0.1)  # near the east end, at the bottom
    u0, v0 = view.top_left
    vw, vh = view.view_size_cells
    assert vh > 20 and math.isclose(v0 + vh / 2, 10.0)
    assert math.isclose(u0 + vw, 1000.0)  # clamped to the east edge


def test_heading_point_moving_and_still() -> None:
    x, y = heading_point(1.0, 2.0, math.pi / 2, 0.8, 0.35)
    assert (x, y) == pytest.approx((1.0, 2.8))
    x, y = heading_point(1.0, 2.0, 0.0, STILL_SPEED / 2, 0.35)  # still: dot on the footprint edge
    assert (x, y) == pytest.approx((1.35, 2.0))
    x, y = heading_point(0.0, 0.0, 0.0, -0.5, 0.35)  # reversing: dot behind
    assert (x, y) == pytest.approx((-0.5, 0.0))


def test_chair_radius_scales_with_zoom_and_has_a_minimum() -> None:
    view = Viewport(200, 200, 0.05, (0, 0), 400, 400)  # 2 px per cell = 40 px/m
    assert view.chair_radius_px(0.35) == pytest.approx(14.0)
    view.set_zoom(3)
    assert view.chair_radius_px(0.35) == pytest.approx(14.0 * 1.5**2)
    tiny = Viewport(20000, 20000, 0.05, (0, 0), 400, 400)
    assert tiny.chair_radius_px(0.35) == MIN_CHAIR_RADIUS_PX
    assert view.dot_radius_px(0.35) == pytest.approx(view.chair_radius_px(0.35) / 2)


def test_laser_segments_skip_nan_and_split_max_range() -> None:
    view = Viewport(200, 200, 0.05, (0, 0), 200, 200)  # 1 px per cell = 20 px/m, 10 m map
    ranges = np.array([1.0, np.nan, 2.0, 4.0, np.inf, -1.0], dtype=np.float32)
    at_max = np.array([False, False, False, True, True, False])
    segs = laser_segments(view, (5.0, 5.0, 0.0), 0.0, math.pi / 2, ranges, at_max, range_max=4.0)
    assert segs.hits.dtype == np.float32 and segs.hits.shape == (2, 2, 2)
    assert segs.max_rays.shape == (2, 2, 2)
    assert segs.count == 4
    cx, cy = (float(a) for a in view.world_to_pixel(5.0, 5.0))
    assert np.allclose(segs.hits[:, 0], [cx, cy])
    # ray 0: 1 m east -> +20 px in x; ray 2: angle pi -> 2 m west
    assert segs.hits[0, 1] == pytest.approx([cx + 20, cy])
    assert segs.hits[1, 1] == pytest.approx([cx - 40, cy], abs=1e-3)
    # ray 3 (3*pi/2 = south, 4 m): down on screen; ray 4 (inf, at max) drawn at range_max (2pi = east)
    assert segs.max_rays[0, 1] == pytest.approx([cx, cy + 80], abs=1e-3)
    assert segs.max_rays[1, 1] == pytest.approx([cx + 80, cy], abs=1e-3)


def test_image_window_crops_scales_and_letterboxes() -> None:
    img = np.arange(12, dtype=np.uint8).reshape(3, 4)  # 4 x 3 cells
    view = Viewport(4, 3, 1.0, (0, 0), 8, 8)  # fit: 2 px per cell, 6 rows -> 1 px letterbox top/bottom
    out, inside = view.image_window(img, fill=255)
    assert out.shape == (8, 8) and inside.shape == (8, 8)
    assert not inside[0].any() and not inside[7].any() and inside[1:7].all()
    assert (out[0] == 255).all()
    assert out[1, 0] == img[0, 0] and out[6, 7] == img[2, 3] and out[3, 2] == img[1, 1]
    view.set_zoom(3)  # x2.25: the view is inside the map, no letterbox
    view.center_on_cell(0, 3)
    out, inside = view.image_window(img)
    assert inside.all()
    assert out[-1, 0] == img[2, 0]  # bottom-left corner clamped
    with pytest.raises(ValueError, match="viewport expects"):
        view.image_window(np.zeros((4, 4), dtype=np.uint8))


def test_state_key_changes_only_with_the_view() -> None:
    view = Viewport(400, 400, 0.05, (0, 0), 200, 200)
    key = view.state_key()
    view.follow(3.0, 3.0)  # unzoomed: the whole map stays put
    assert view.state_key() == key
    view.zoom_in()
    zoomed = view.state_key()
    assert zoomed != key
    view.follow(8.0, 8.0)
    assert view.state_key() != zoomed


@pytest.mark.parametrize(
    "args",
    [
        (0, 10, 0.05),
        (10, 10, 0.0),
        (10, 10, float("nan")),
        (10, 10, 0.05, (0, 0), 0, 100),
    ],
)
def test_bad_geometry_is_rejected(args: tuple) -> None:
    with pytest.raises(ValueError):
        Viewport(*args)


def test_ray_stride_thins_dense_scans_only() -> None:
    from pmk_nb.viewport import ray_stride

    view = Viewport(200, 200, 0.05, (0, 0), 200, 200)  # 20 px/m
    ranges = np.full(1080, 3.0)
    inc = math.radians(0.25)
    # 3 m * 0.00436 rad * 20 px/m = 0.26 px apart -> every 8th ray for 2 px
    assert ray_stride(view, ranges, inc, 2.0) == 8
    assert ray_stride(view, ranges, inc, 0.0) == 1
    assert ray_stride(view, np.array([]), inc, 2.0) == 1
    view.set_zoom(view.max_zoom)
    assert ray_stride(view, ranges, inc, 2.0) == 1
    segs = laser_segments(view, (5.0, 5.0, 0.0), 0.0, inc, ranges, min_spacing_px=40.0)
    assert 0 < segs.hits.shape[0] < 1080


@settings(max_examples=200, deadline=None)
@given(sizes, sizes, canvas, canvas)
def test_fit_canvas_keeps_the_map_aspect_within_the_maximum(mw: int, mh: int, cw: int, ch: int) -> None:
    w, h = fit_canvas(mw, mh, cw, ch, min_px=40)
    assert 1 <= w <= cw and 1 <= h <= ch
    assert w == cw or h == ch or w == min(40, cw) or h == min(40, ch)  # one side touches a bound
    if min(w, h) > 40:  # not padded up to the minimum: the map fills the canvas, no letterbox
        view = Viewport(mw, mh, 0.05, (0, 0), w, h)
        u0, v0, u1, v1 = view.visible_cells()
        px0, py0 = view.cell_to_pixel(u0, v0)
        px1, py1 = view.cell_to_pixel(u1, v1)
        assert px0 <= 1 and py0 <= 1 and px1 >= w - 1 and py1 >= h - 1


def test_fit_canvas_examples_and_garbage() -> None:
    assert fit_canvas(1000, 500, 920, 560) == (920, 460)  # wide map: full width, no band below
    assert fit_canvas(300, 600, 920, 560) == (280, 560)  # tall map: full height
    assert fit_canvas(2000, 10, 920, 560) == (920, 160)  # a corridor still gets a usable height
    assert fit_canvas(2000, 10, 920, 100) == (920, 100)  # ... but never above the maximum
    with pytest.raises(ValueError, match="positive"):
        fit_canvas(0, 10, 100, 100)


# -- pan, follow on/off, centre -----------------------------------------------------------------------
def test_drag_pans_stops_following_and_centre_returns() -> None:
    view = Viewport(400, 200, 0.05, (0.0, 0.0), 200, 100)  # 20 x 10 m map
    view.set_zoom(4)
    view.see_chair(10.0, 5.0)  # following: centred on the chair
    assert view.world_to_pixel(10.0, 5.0) == pytest.approx((100.0, 50.0))
    view.pan_pixels(30.0, -10.0)  # the map moves with the finger
    assert not view.following
    assert view.world_to_pixel(10.0, 5.0) == pytest.approx((130.0, 40.0))
    view.see_chair(11.0, 5.0)  # not following: the view stays put
    assert view.world_to_pixel(10.0, 5.0) == pytest.approx((130.0, 40.0))
    view.centre()  # one-shot: on the chair, following stays off
    assert view.world_to_pixel(11.0, 5.0) == pytest.approx((100.0, 50.0)) and not view.following
    view.pan_pixels(5000.0, 5000.0)  # dragged far past the map's corner: clamped
    assert view.visible_cells()[:2] == (0.0, 0.0)
    view.pan_pixels(-10.0, 0.0)  # dragging back responds at once (no hidden overshoot)
    assert view.visible_cells()[0] > 0.0
    view.set_following(True)
    assert view.world_to_pixel(11.0, 5.0) == pytest.approx((100.0, 50.0))
    view.forget_chair()
    view.centre()  # no chair: the map's centre
    assert view.center == pytest.approx((200.0, 100.0))
    with pytest.raises(ValueError):
        view.pan_pixels(float("nan"), 0.0)


def test_pixel_origin_is_the_rounded_top_left() -> None:
    view = Viewport(400, 200, 0.05, (0.0, 0.0), 200, 100)
    view.set_zoom(3)
    view.see_chair(7.03, 4.01)
    u0, v0 = view.top_left
    assert view.pixel_origin() == (round(u0 * view.scale), round(v0 * view.scale))


# -- the map at screen resolution ---------------------------------------------------------------------
def test_a_thin_wall_survives_any_reduction() -> None:
    from pmk_nb.viewport import pool_window

    data = np.zeros((1000, 3000), np.int8)  # 150 x 50 m at 0.05 m
    data[:, 1503:1505] = 100  # a 0.1 m wall, two cells
    data[400:402, :] = 100  # and a horizontal one
    for scale in (0.05, 0.13, 0.3, 0.5, 0.99, 1.0, 2.5):
        w, h = math.ceil(3000 * scale), math.ceil(1000 * scale)
        values, inside = pool_window(data, scale, 0, 0, w, h)
        cols = np.flatnonzero((values == 100).all(axis=0))
        rows = np.flatnonzero((values == 100).all(axis=1))
        assert cols.size >= 1 and rows.size >= 1, f"a wall vanished at {scale} px/cell"
        assert abs(cols[0] - 1503 * scale) <= 1.0 and abs(rows[0] - 400 * scale) <= 1.0
        assert inside.all()
    # the old sampling (one cell per pixel) loses the same wall at 0.3 px/cell
    view = Viewport(3000, 1000, 0.05, (0.0, 0.0), 900, 300)
    gray = np.where(data == 100, 0, 254).astype(np.uint8)
    img, _ = view.image_window(gray)
    assert not (img == 0).all(axis=0).any(), "the nearest sampling was expected to miss this wall"


def test_pooling_order_is_occupied_over_free_over_unknown() -> None:
    from pmk_nb.viewport import pool_window

    data = np.array([[-1, -1, 0, -1, 0, 100, -1, -1]], np.int8)
    values, inside = pool_window(data, 0.5, 0, 0, 4, 1)  # two cells per pixel
    assert values.tolist() == [[-1, 0, 100, -1]] and inside.all()
    values, inside = pool_window(data, 2.0, -2, 0, 20, 1)  # a cell over two pixels, map shifted
    assert values[0, :2].tolist() == [-1, -1] and not inside[0, :2].any()
    assert values[0, 2:18].tolist() == np.repeat(data[0], 2).tolist() and inside[0, 2:18].all()
    assert not inside[0, 18:].any()
    values, inside = pool_window(data, 0.5, 100, 100, 4, 2)  # nowhere near the map
    assert not inside.any() and (values == -1).all()
    with pytest.raises(ValueError):
        pool_window(data, 0.0, 0, 0, 4, 1)


@settings(max_examples=60, deadline=None)
@given(
    st.integers(1, 60),
    st.integers(1, 60),
    st.floats(0.05, 4.0),
    st.integers(-30, 30),
    st.integers(-30, 30),
    st.integers(0, 2**31),
)
def test_pooling_is_the_max_over_each_pixels_cells(
    rows: int, cols: int, scale: float, x0: int, y0: int, seed: int
) -> None:
    from pmk_nb.viewport import pool_window

    data = np.random.default_rng(seed).choice(np.array([-1, 0, 100], np.int8), size=(rows, cols))
    w, h = 40, 30
    values, inside = pool_window(data, scale, x0, y0, w, h)
    for j, i in [(0, 0), (h // 2, w // 2), (h - 1, w - 1), (3, 17)]:
        if scale < 1:  # the cells whose left / top edge lies in the pixel
            cs = [c for c in range(cols) if x0 + i <= c * scale + 1e-9 < x0 + i + 1]
            rs = [r for r in range(rows) if y0 + j <= r * scale + 1e-9 < y0 + j + 1]
        else:  # the cell under the pixel's centre
            cs = [c for c in range(cols) if c <= (x0 + i + 0.5) / scale < c + 1]
            rs = [r for r in range(rows) if r <= (y0 + j + 0.5) / scale < r + 1]
        if not cs or not rs:
            assert not inside[j, i] and values[j, i] == -1
        else:
            assert inside[j, i] and values[j, i] == data[np.ix_(rs, cs)].max()


def test_window_image_uses_the_map_file_greys_and_a_transparent_letterbox() -> None:
    from pmk_nb.grid import OccupancyGrid
    from pmk_nb.rosmap import grid_to_gray
    from pmk_nb.viewport import clean_occupancy, window_image
    from pmk_nb.viewport.mapimage import GRAY_LUT

    raw = np.arange(256, dtype=np.uint8).view(np.int8).reshape(16, 16)
    assert (GRAY_LUT[raw.view(np.uint8)] == grid_to_gray(OccupancyGrid(raw[::-1].copy(), 0.05))).all()
    cleaned = clean_occupancy(raw)
    assert cleaned.min() == -1 and cleaned.max() == 100  # 101..127 never win the max-pool
    ok = np.zeros((4, 4), np.int8)
    assert clean_occupancy(ok) is ok  # the usual case: no copy
    img = window_image(ok, 1.0, 0, 0, 4, 4)
    assert img.shape == (4, 4) and (img == 254).all()
    img = window_image(ok, 1.0, -1, 0, 4, 4)
    assert img.shape == (4, 4, 4) and (img[:, 0, 3] == 0).all() and (img[:, 1:, 3] == 255).all()


def test_tile_covers_the_canvas_until_the_view_leaves_it() -> None:
    from pmk_nb.viewport import plan_tile, tile_covers
    from pmk_nb.viewport.mapimage import tile_size_for

    size = tile_size_for((200, 100), 0.5)
    assert size == (400, 200)
    tile = plan_tile((1000, 500), (200, 100), size, 2.0)
    assert (tile.x0, tile.y0, tile.width, tile.height) == (900, 450, 400, 200)
    assert tile_covers(tile, (1000, 500), (200, 100), 2.0)
    assert tile_covers(tile, (900, 450), (200, 100), 2.0) and tile_covers(tile, (1100, 550), (200, 100), 2.0)
    assert not tile_covers(tile, (1101, 550), (200, 100), 2.0)
    assert not tile_covers(tile, (1000, 500), (200, 100), 3.0)  # another zoom
    assert not tile_covers(None, (1000, 500), (200, 100), 2.0)
    same = plan_tile((10, 20), (200, 100), (50, 50), 1.0)  # no margin: exactly the canvas
    assert (same.x0, same.y0, same.width, same.height) == (10, 20, 200, 100)


# -- the laser as the room it sees ---------------------------------------------------------------------
def test_laser_outline_thins_hits_to_pixels_and_pulls_unknown_back() -> None:
    from pmk_nb.viewport import laser_outline

    view = Viewport(400, 400, 0.05, (0.0, 0.0), 200, 200)  # 20 x 20 m, 10 px/m at zoom 1
    n = 1080
    ranges = np.full(n, 3.0)
    at_max = np.zeros(n, bool)
    unknown = np.zeros(n, bool)
    ranges[100:200] = np.nan
    unknown[100:200] = True
    at_max[500:600] = True
    ranges[500:600] = np.nan
    out = laser_outline(view, (10.0, 10.0, 0.0), -math.pi, 2 * math.pi / n, ranges, at_max, 8.0, unknown=unknown)
    assert out.hits.dtype == np.float32 and out.polygon.dtype == np.float32
    # 880 hits on a 30 px circle: at most one per pixel, and no pixel twice
    assert out.hits.shape[0] <= 2 * math.pi * 30 + 10
    assert len({(float(x), float(y)) for x, y in out.hits}) == out.hits.shape[0]
    assert out.at_max == 100 and out.blind == 100
    cx, cy = (float(v) for v in view.world_to_pixel(10.0, 10.0))
    r = np.hypot(out.polygon[:, 0] - cx, out.polygon[:, 1] - cy)
    assert r.max() == pytest.approx(80.0, abs=1.5)  # the max-range rays reach range_max
    assert (r < 1.0).any()  # the unknown sector goes back to the scanner
    # at most one vertex per pixel of the outline (3 m circle + 8 m arc + the pinch)
    outline_px = 2 * math.pi * 30 + (100 / n) * 2 * math.pi * 80 + 2 * 80
    assert out.polygon.shape[0] <= outline_px
    # no free space claimed in the unknown sector: the polygon has no vertex out there
    ang = np.arctan2(-(out.polygon[:, 1] - cy), out.polygon[:, 0] - cx)
    sector = (ang > -math.pi + 101 * 2 * math.pi / n) & (ang < -math.pi + 199 * 2 * math.pi / n)
    assert (r[sector] < 1.0).all()


def test_simplify_ring_collapses_straight_walls_only() -> None:
    from pmk_nb.viewport.outline import dedupe_ring, simplify_ring

    t = np.linspace(0, 1, 400, endpoint=False)
    zero, up, down = 0 * t, t * 100, 100 - t * 100
    square = np.concatenate([np.c_[up, zero], np.c_[zero + 100, up], np.c_[down, zero + 100], np.c_[zero, down]])
    simple = simplify_ring(square)
    assert 4 <= simple.shape[0] <= 8
    for corner in ((0, 0), (100, 0), (100, 100), (0, 100)):
        assert np.min(np.hypot(*(simple - corner).T)) < 1.0
    ang = np.linspace(0, 2 * math.pi, 2000, endpoint=False)
    circle = np.c_[200 + 100 * np.cos(ang), 200 + 100 * np.sin(ang)]
    ring = dedupe_ring(circle)
    assert ring.shape[0] <= 2 * math.pi * 100 * 1.5  # about one vertex per pixel of outline
    simple = simplify_ring(ring)
    assert simple.shape[0] >= 20  # a curve keeps its shape
    assert np.abs(np.hypot(*(simple - 200).T) - 100).max() < 3.0


def test_tick_segments_are_thinned_on_screen() -> None:
    from pmk_nb.viewport.outline import tick_segments

    view = Viewport(400, 400, 0.05, (0.0, 0.0), 200, 200)  # 10 px/m
    mask = np.zeros(1080, bool)
    mask[:180] = True
    ticks = tick_segments(view, (10.0, 10.0, 0.0), -math.pi, 2 * math.pi / 1080, mask, 0.35, 0.95, 3.0)
    # a 60 deg sector, ticks ending 9.5 px from the chair: a 10 px arc, one tick per 3 px
    assert ticks.dtype == np.float32 and 3 <= ticks.shape[0] <= 5
    lengths = np.hypot(*(ticks[:, 1] - ticks[:, 0]).T)
    assert np.allclose(lengths, 6.0, atol=0.01)


def test_unique_pixels_keeps_one_point_per_dot_and_drops_far_off_points() -> None:
    from pmk_nb.viewport.outline import unique_pixels

    x = np.array([10.2, 10.7, 11.4, 12.6, -50.0, 30.0, np.nan], dtype=np.float64)
    y = np.array([5.1, 5.9, 5.5, 5.5, 5.0, 500.0, 1.0])
    one = unique_pixels(x, y, 100, 100)
    assert sorted(map(tuple, one.tolist())) == [(10.5, 5.5), (11.5, 5.5), (12.5, 5.5)]
    four = unique_pixels(x, y, 100, 100, cell=4.0)  # 4 px dots: a 4 x 4 grid, one point per square
    assert sorted(map(tuple, four.tolist())) == [(10.0, 6.0), (14.0, 6.0)]


def test_simplify_ring_stays_within_its_tolerance_on_a_gentle_curve() -> None:
    """Every vertex dropped lies within the tolerance of the outline kept (Douglas-Peucker's bound);
    the earlier passes could drift a tolerance per pass on a gently curving outline."""
    import shapely

    from pmk_nb.viewport.outline import simplify_ring

    ang = np.linspace(0.0, 1.5, 1200)
    arc = np.c_[500 + 500 * np.cos(ang), 500 + 500 * np.sin(ang)]  # 0.3 px steps: each nearly straight
    simple = simplify_ring(arc, 0.5)
    assert simple.shape[0] < arc.shape[0] / 4
    kept = shapely.linestrings(simple.astype(np.float64))
    worst = max(shapely.distance(kept, shapely.points(arc)))
    assert worst <= 0.5 + 1e-3, f"a dropped vertex lies {worst:.2f} px from the outline kept"
    assert tuple(simple[0]) == pytest.approx(tuple(arc[0])) and tuple(simple[-1]) == pytest.approx(tuple(arc[-1]))
