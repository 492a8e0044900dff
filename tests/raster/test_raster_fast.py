"""The fast paths of the rasteriser give the same cells as the plain per-shape rules they replace."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from shapely.geometry import LineString, box

from pmk_nb.grid import new_cells
from pmk_nb.raster.scanline import (
    Frame,
    axis_line_rects,
    fill_polygon,
    fill_segment_bands,
    line_segments,
    polygons_of,
    supercover_cells,
    write_rects,
)
from pmk_nb.raster.spans import fill_polygons
from pmk_nb.raster.wallcut import wall_segments
from pmk_nb.raster.walls import wall_lines

FRAME = Frame(-0.15, -0.35, 0.05, 260, 240)


def _shapes(rng: np.random.Generator) -> list[shapely.Geometry]:
    out: list[shapely.Geometry] = []
    for _ in range(40):
        x, y = rng.uniform(0, 10, 2)
        w, h = rng.uniform(0.02, 3, 2)
        kind = rng.integers(3)
        if kind == 0:
            out.append(box(x, y, x + w, y + h))  # an axis-aligned box: the rectangle path
        elif kind == 1:
            out.append(shapely.affinity.rotate(box(x, y, x + w, y + h), float(rng.uniform(0, 90))))
        else:  # a box with a hole, and a concave polygon: the general scan
            out.append(box(x, y, x + w + 1, y + h + 1).difference(box(x + 0.3, y + 0.3, x + w, y + h)))
    out.append(box(0.125, 0.125, 2.125, 2.125))  # edges exactly half a cell off the centres
    out.append(box(-5, -5, 0.5, 0.5))  # partly outside the frame
    return out


def _reference(shapes: list[shapely.Geometry]) -> np.ndarray:
    grid = np.zeros((FRAME.height, FRAME.width), np.int8)

    def op(block: np.ndarray, mask: np.ndarray) -> None:
        block[mask] = 1

    for g in shapes:
        for p in polygons_of(g):
            fill_polygon(grid, FRAME, p, op)
    return grid


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_fill_polygons_matches_the_per_polygon_scan(seed: int) -> None:
    shapes = _shapes(np.random.default_rng(seed))
    fast = np.zeros((FRAME.height, FRAME.width), np.int8)
    fill_polygons(fast, FRAME, shapes, 1)
    ref = _reference(shapes)
    assert ref.sum() > 1000
    assert np.array_equal(fast, ref)


def test_fill_polygons_spares_keep_values() -> None:
    grid = np.zeros((FRAME.height, FRAME.width), np.int8)
    grid[100:110, :] = 7
    fill_polygons(grid, FRAME, [box(0, 0, 10, 10)], 1, keep=(7,))
    assert (grid[100:110] == 7).all() and (grid[50, 50] == 1)


def test_axis_lines_match_the_supercover() -> None:
    rng = np.random.default_rng(3)
    pts = np.round(rng.uniform(-1, 12, (300, 2)), 2)  # on and off grid lines
    ends = pts + np.where(rng.random((300, 1)) < 0.5, [[1, 0]], [[0, 1]]) * rng.uniform(-3, 3, (300, 1))
    segs = np.hstack([pts, ends])
    segs[:5, 2:] = segs[:5, :2]  # zero-length segments too
    ref = np.zeros((FRAME.height, FRAME.width), np.int8)
    rows, cols = supercover_cells(segs, FRAME)
    ref[rows, cols] = 1
    axis, rest, rects = axis_line_rects(segs, FRAME)
    assert axis.all() and len(rest) == 0
    fast = np.zeros_like(ref)
    write_rects(fast, *rects, 1)
    assert ref.sum() > 500
    assert np.array_equal(fast, ref)


def test_axis_bands_match_the_per_row_rule() -> None:
    rng = np.random.default_rng(4)
    pts = np.round(rng.uniform(0, 11, (200, 2)), 3)
    ends = pts + np.where(rng.random((200, 1)) < 0.5, [[1, 0]], [[0, 1]]) * rng.uniform(-3, 3, (200, 1))
    segs = np.hstack([pts, ends])
    fast = np.zeros((FRAME.height, FRAME.width), np.int8)
    fill_segment_bands(fast, FRAME, segs, 0.05, 1)
    ref = np.zeros_like(fast)
    nudged = segs + np.array([0, 0, 1e-12, 1e-12])  # not axis-aligned: the per-row path
    fill_segment_bands(ref, FRAME, nudged, 0.05, 1)
    assert np.abs(fast.astype(int) - ref).sum() <= 2 * len(segs)  # same band up to the nudge at its ends
    assert fast.sum() > 1000


def test_wall_segments_match_the_geos_cuts() -> None:
    rooms = [box(i * 4, j * 4, (i + 1) * 4, (j + 1) * 4) for i in range(3) for j in range(3)]
    rooms.append(shapely.affinity.rotate(box(13, 1, 16, 3), 30))
    doors = [LineString([(4, 1.5), (4, 2.4)]), LineString([(1, 4), (1.9, 4)]), LineString([(8, 9), (8, 9.7)])]
    doors.append(LineString([(4, 5), (4, 5.5), (4.3, 5.5)]))  # a bent door line: the GEOS path
    door_polys = [box(5, 7.9, 5.9, 8.1)]
    gaps = np.array([0.0, 0.1, 0.0, 0.0])
    fast = wall_segments(rooms, door_polys, doors, gaps, 0.0125)
    ref = line_segments(wall_lines(rooms, door_polys, doors, gaps, 0.0125))
    a, b = (np.zeros((FRAME.height, FRAME.width), np.int8) for _ in range(2))
    fill_segment_bands(a, FRAME, fast, 0.05, 1)
    fill_segment_bands(b, FRAME, ref, 0.05, 1)
    assert np.array_equal(a, b)
    assert b.sum() > 1000


def test_new_cells_is_filled_writable_and_c_contiguous() -> None:
    for h, w in ((10, 20), (6000, 6000)):  # numpy's allocator, then an anonymous mapping
        cells = new_cells(h, w, -1)
        assert cells.shape == (h, w) and cells.dtype == np.int8 and cells.flags.c_contiguous
        assert cells.flags.writeable and (cells == -1).all()
        cells[0, 0] = 5
        assert cells[0, 0] == 5


def test_strip_erosion_and_run_labels_match_the_whole_grid_ones() -> None:
    from pmk_nb.pixels import erode, erode_rows, regions, run_regions

    rng = np.random.default_rng(5)
    mask = rng.random((203, 157)) < 0.8
    mask[50:60, :] = True
    owner = (np.arange(157)[None, :] // 40 + np.arange(203)[:, None] // 70).astype(np.int16)
    sizes = []
    for radius in (0.0, 1.5, 3.2):
        whole = erode(mask, radius)
        strips = list(erode_rows(lambda lo, hi: mask[lo:hi], 203, 157, radius, step=17))
        assert np.array_equal(np.vstack([s for _, s in strips]), whole)
        labels, owners, edges = regions(whole, owner)
        got, got_owner, got_edges = run_regions(((a, s, owner[a : a + len(s)]) for a, s in strips), 157)
        assert np.array_equal(got, np.unique(labels[labels > 0]))
        assert np.array_equal(got_owner[got], owners[got]) and np.array_equal(got_edges, edges)
        sizes.append((len(got), len(got_edges)))
    assert max(sizes) > (10, 5)  # enough regions and touching pairs to mean something


def test_run_labels_and_erosion_match_a_pixel_by_pixel_reference() -> None:
    """regions() against a flood fill, erode() against the disc test written out pixel by pixel."""
    import math
    from collections import deque

    from pmk_nb.pixels import erode, regions

    rng = np.random.default_rng(11)
    h, w = 41, 37
    mask = rng.random((h, w)) < 0.7
    owner = (np.arange(w)[None, :] // 9 + 3 * (np.arange(h)[:, None] // 13)).astype(np.uint8)
    comp = -np.ones((h, w), dtype=np.int64)
    n = 0
    for y, x in zip(*np.nonzero(mask), strict=True):
        if comp[y, x] >= 0:
            continue
        comp[y, x] = n
        todo = deque([(y, x)])
        while todo:
            cy, cx = todo.popleft()
            for ny, nx in ((cy + 1, cx), (cy - 1, cx), (cy, cx + 1), (cy, cx - 1)):
                if 0 <= ny < h and 0 <= nx < w and mask[ny, nx] and comp[ny, nx] < 0 and owner[ny, nx] == owner[cy, cx]:
                    comp[ny, nx] = comp[cy, cx]
                    todo.append((ny, nx))
        n += 1
    labels, label_owner, edges = regions(mask, owner)
    pairs = set(zip(labels[mask].tolist(), comp[mask].tolist(), strict=True))
    assert len(pairs) == n == len({a for a, _ in pairs})  # one label per flood-fill component and back
    to_comp = dict(pairs)
    assert all(label_owner[lab] == owner[comp == c][0] for lab, c in to_comp.items())
    want = set()
    for y in range(h):
        for x in range(w):
            for ny, nx in ((y + 1, x), (y, x + 1)):
                if ny < h and nx < w and mask[y, x] and mask[ny, nx] and owner[y, x] != owner[ny, nx]:
                    want.add(frozenset((int(comp[y, x]), int(comp[ny, nx]))))
    got = {frozenset((to_comp[a], to_comp[b])) for a, b in edges.tolist()}
    assert got == want and len(want) > 10
    for radius in (1.5, 2.9):
        r = math.floor(radius)
        ref = np.zeros_like(mask)
        for y in range(h):
            for x in range(w):
                ref[y, x] = all(
                    0 <= y + dy < h and 0 <= x + dx < w and mask[y + dy, x + dx]
                    for dy in range(-r, r + 1)
                    for dx in range(-r, r + 1)
                    if dx * dx + dy * dy <= radius * radius
                )
        assert np.array_equal(erode(mask, radius), ref)


def test_polygon_parts_takes_plain_polygons_as_they_are_and_flattens_the_rest() -> None:
    """The vectorised fast path and the per-geometry fallback give the parts :func:`polygons_of` gives."""
    from pmk_nb.geometry import polygon_parts, polygons_of

    plain = [box(0, 0, 1, 1), box(2, 0, 3, 1)]
    assert polygon_parts(plain) == plain and polygon_parts(plain)[0] is plain[0]
    mixed = [
        box(0, 0, 1, 1),
        shapely.MultiPolygon([box(2, 0, 3, 1), box(4, 0, 5, 1)]),
        shapely.Polygon(),
        None,
        shapely.GeometryCollection([box(6, 0, 7, 1), LineString([(0, 0), (1, 1)])]),
        LineString([(0, 0), (1, 0)]),
    ]
    parts = polygon_parts(mixed)
    assert parts == [p for g in mixed for p in polygons_of(g)]
    assert [p.bounds[0] for p in parts] == [0.0, 2.0, 4.0, 6.0]
    assert polygon_parts([]) == [] and polygon_parts([shapely.Polygon()]) == []
