"""Speed-ups of the converter (issue 31, cost) give the same floats and pixels as the calls they replace."""

from __future__ import annotations

import numpy as np
import shapely
import shapely.affinity

from pmk_nb.access.widths import _sample
from pmk_nb.raster import Frame, polygon_rects, polygon_rects_each


def test_free_width_samples_are_geos_own_points() -> None:
    """Numpy's interpolation on two-point lines is bit for bit GEOS's line_interpolate_point (ends and
    past-the-end samples included); lines with more points go through GEOS."""
    rng = np.random.default_rng(7)
    xy0 = np.round(rng.uniform(-300, 300, (400, 2)), 3)
    xy0[::3] = rng.uniform(-300, 300, xy0[::3].shape)  # and any float
    xy1 = xy0 + np.round(rng.normal(0, 1.5, (400, 2)), 3)
    xy1[:100, 1] = xy0[:100, 1]  # walls along the axes, as most are
    lines = [shapely.LineString(p) for p in np.stack([xy0, xy1], axis=1)]
    lines += [shapely.LineString([(0, 0), (1, 0), (1, 1.3)]), shapely.LineString([(2, 2), (2, 2)])]
    arr = np.asarray(lines, dtype=object)
    length = shapely.length(arr)
    n = np.maximum(2, (length / 0.0064).astype(np.int64) + 1)
    k = np.arange(int(n.sum())) - np.repeat(np.cumsum(n) - n, n)
    along = k * np.repeat(length / (n - 1), n)
    along[::97] += 0.01  # past the end of some lines: clamped to their end
    along[::89] = -0.0  # at the start
    want = shapely.get_coordinates(shapely.line_interpolate_point(np.repeat(arr, n), along))
    assert np.array_equal(_sample(arr, n, along), want)


def test_rectangles_of_each_polygon_at_once_are_its_own() -> None:
    """polygon_rects_each gives each shape the cells polygon_rects gives it alone: boxes, boxes off the grid
    or thinner than a cell, a rotated cell, a cell with a hole, a multipolygon, an empty shape."""
    frame = Frame(-1.0, -2.0, 0.05, 200, 160)
    shapes = [
        shapely.box(0, 0, 3.8, 3.8),
        shapely.box(3.8, 1.45, 4.0, 2.35),
        shapely.box(1.01, 1.01, 1.03, 1.2),  # thinner than a cell: no centre inside
        shapely.box(50, 50, 60, 60),  # off the grid
        shapely.box(-5, -5, 2, 2),  # over the edge
        shapely.affinity.rotate(shapely.box(2, 2, 4, 3), 17),
        shapely.box(0, 0, 4, 4).difference(shapely.box(1, 1, 2, 2)),
        shapely.MultiPolygon([shapely.box(0, 0, 1, 1), shapely.box(2, 2, 3, 3)]),
        shapely.Polygon(),
    ]
    for got, shape in zip(polygon_rects_each(frame, shapes), shapes, strict=True):
        want = polygon_rects(frame, [shape])
        assert len(got) == 4
        for a, b in zip(got, want, strict=True):
            assert np.array_equal(a, b) and a.dtype == b.dtype
