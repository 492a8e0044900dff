"""Costmaps and markers on the live map (issue 40): RViz's costmap colours, placement, marker shapes."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pmk_nb.grid import OccupancyGrid
from pmk_nb.viewport import Transform2D, Viewport
from pmk_nb.viewport.costmap import COSTMAP_LUT, costmap_palette, costmap_placement, costmap_rgba, pooled_costs
from pmk_nb.viewport.markers import (
    ARROW,
    CUBE,
    LINE_LIST,
    LINE_STRIP,
    MESH_RESOURCE_KIND,
    POINTS,
    TEXT_VIEW_FACING,
    PlanarMarker,
    css_rgba,
    marker_draws,
)


def view_of(width_m: float = 10.0, height_m: float = 10.0, res: float = 0.1) -> Viewport:
    grid = OccupancyGrid(np.zeros((round(height_m / res), round(width_m / res)), np.int8), res, (0.0, 0.0, 0.0))
    return Viewport.for_grid(grid, 200, 200)


def test_the_palette_follows_rviz_costmap_colours() -> None:
    lut = costmap_palette(alpha=1.0)
    assert tuple(lut[0]) == (0, 0, 0, 0)  # free space: clear
    assert tuple(lut[100]) == (255, 0, 255, 255)  # lethal: magenta
    assert tuple(lut[99]) == (0, 255, 255, 255)  # inscribed: cyan
    assert lut[10, 2] > lut[10, 0] and lut[90, 0] > lut[90, 2]  # low costs blue, high costs red
    assert 0 < lut[255, 3] < 64  # unknown (-1): faint
    assert COSTMAP_LUT[100, 3] == round(255 * 0.7)  # drawn at RViz's default alpha


def test_costmap_image_is_rgba_top_row_first() -> None:
    data = np.zeros((3, 4), np.int8)
    data[0, 0] = 100  # bottom-left cell in ROS order
    data[2, 3] = -1
    img = costmap_rgba(data)
    assert img.shape == (3, 4, 4) and img.dtype == np.uint8 and img.flags.c_contiguous  # RGBA, never RGB
    assert tuple(img[2, 0]) == tuple(COSTMAP_LUT[100])  # ... is the image's last row
    assert tuple(img[0, 3]) == tuple(COSTMAP_LUT[255])
    with pytest.raises(ValueError):
        costmap_rgba(np.zeros(5, np.int8))


def test_a_big_costmap_is_pooled_and_no_lethal_cell_is_lost() -> None:
    data = np.zeros((5000, 3001), np.int8)
    data[4999, 3000] = 100  # the far corner: in a block of its own plus padding
    data[10, 10] = 99
    data[0:3, 2001:2004] = -1  # a block all unknown stays unknown
    data[0:2, 1998:2001] = -1  # one partly known shows what is known
    cells, factor = pooled_costs(data, max_side=2048)
    assert factor == 3 and cells.shape == (1667, 1001) and cells.dtype == np.int8
    assert cells[1666, 1000] == 100 and cells[3, 3] == 99 and cells[0, 667] == -1 and cells[0, 666] == 0
    small = np.zeros((10, 10), np.int8)
    assert pooled_costs(small)[0] is not None and pooled_costs(small)[1] == 1


def test_a_costmap_is_placed_at_its_origin_and_turned_by_its_yaw() -> None:
    view = view_of()
    place = costmap_placement(view, (2.0, 3.0, 0.0), 0.05, (40, 20))
    # the image's bottom-left corner is the costmap origin, its top-right the far corner
    assert place.to_canvas(0.0, place.height) == pytest.approx(tuple(float(v) for v in view.world_to_pixel(2.0, 3.0)))
    far = view.world_to_pixel(2.0 + 40 * 0.05, 3.0 + 20 * 0.05)
    assert place.to_canvas(place.width, 0.0) == pytest.approx(tuple(float(v) for v in far))
    # a local costmap in odom, odom placed in the map (x + 1, turned 90 degrees)
    turned = costmap_placement(view, (0.0, 0.0, 0.0), 0.1, (10, 10), Transform2D(5.0, 5.0, math.pi / 2))
    end_of_first_row = turned.to_canvas(turned.width, turned.height)  # costmap cell (10, 0) corner: odom (1, 0)
    assert end_of_first_row == pytest.approx(tuple(float(v) for v in view.world_to_pixel(5.0, 6.0)))


def test_line_strip_and_line_list_become_lines_and_segments_in_canvas_pixels() -> None:
    view = view_of()
    pts = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [5.0, 5.0]])
    strip = marker_draws(PlanarMarker(LINE_STRIP, (2.0, 2.0, 0.0), (0.1, 0, 0), (1, 0, 0, 1), pts), view)
    assert [d.op for d in strip] == ["lines"] and strip[0].xy.shape == (5, 2)
    assert tuple(strip[0].xy[1]) == pytest.approx(tuple(float(v) for v in view.world_to_pixel(3.0, 2.0)))
    assert strip[0].style == "rgba(255, 0, 0, 1)" and strip[0].size == pytest.approx(view.metres_to_px(0.1))
    pairs = marker_draws(PlanarMarker(LINE_LIST, points=pts), view)
    assert pairs[0].op == "segments" and pairs[0].xy.shape == (2, 2, 2)  # the odd point out is dropped


def test_points_text_arrow_and_cube() -> None:
    view = view_of()
    dots = marker_draws(PlanarMarker(POINTS, scale=(0.2, 0.2, 0), points=np.array([[1.0, 1.0], [2.0, 2.0]])), view)
    assert dots[0].op == "squares" and dots[0].xy.shape == (2, 2) and dots[0].size == pytest.approx(0.2 * view.px_per_m)
    label = marker_draws(PlanarMarker(TEXT_VIEW_FACING, (4.0, 4.0, 1.0), (0, 0, 0.5), text="goal"), view)
    assert label[0].op == "text" and label[0].text == "goal" and label[0].size >= 9
    assert tuple(label[0].xy[0]) == pytest.approx(tuple(float(v) for v in view.world_to_pixel(4.0, 4.0)))
    arrow = marker_draws(PlanarMarker(ARROW, (1.0, 1.0, math.pi / 2), (2.0, 0.2, 0.2)), view)
    tip = arrow[0].xy[np.argmin(arrow[0].xy[:, 1])]  # the highest point on screen: it points up (+y)
    assert arrow[0].op == "polygon" and tuple(tip) == pytest.approx(
        tuple(float(v) for v in view.world_to_pixel(1.0, 3.0))
    )
    two_points = marker_draws(
        PlanarMarker(ARROW, scale=(0.1, 0.2, 0.3), points=np.array([[0.0, 0.0], [0.0, -2.0]])), view
    )
    assert np.max(two_points[0].xy[:, 1]) == pytest.approx(float(view.world_to_pixel(0.0, -2.0)[1]))
    box = marker_draws(PlanarMarker(CUBE, (5.0, 5.0, 0.0), (2.0, 1.0, 1.0)), view)
    xs, ys = box[0].xy[:, 0], box[0].xy[:, 1]
    assert (xs.max() - xs.min(), ys.max() - ys.min()) == pytest.approx((2.0 * view.px_per_m, 1.0 * view.px_per_m))
    assert marker_draws(PlanarMarker(MESH_RESOURCE_KIND), view) == []
    assert marker_draws(PlanarMarker(LINE_STRIP, points=np.zeros((1, 2))), view) == []


def test_colours_are_clamped_and_nan_is_clear() -> None:
    assert css_rgba((2.0, -1.0, math.nan, 0.5)) == "rgba(255, 0, 0, 0.5)"
