"""Issue 31, rule 8: a door made from a transition keeps its width.

Where the file gives no door geometry (rules line / middle), the 0.9 m opening lies on one straight
stretch of the shared wall, clear of its corners, never laid round a corner (FZK-Haus's attic door was
0.9 m long round a corner and 0.63 m clear); where no stretch is long enough the opening's width is
the longest straight stretch, and the report names it narrower. Room B pokes its corner (5, 3.4) into room
A's inner corner, so the A-B boundary is an L.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy import ndimage

from pmk_nb.grid import FREE
from pmk_nb.openings import plan_openings
from tests.access.test_access_rules import RES, _cell, _graph, _grid_and_report, _plan, _poly_cell

V = pytest.mark.parametrize("v2", [False, True], ids=["1.0-state-transition", "2.0-node-edge"])


def _clear_joined(grid, a: tuple[float, float], b: tuple[float, float], half_width: float) -> bool:
    """Independent of the converter: the free cells at least ``half_width`` from any other cell
    (scipy's distance transform) join the points ``a`` and ``b``."""
    free = np.asarray(grid.data) == FREE
    lab, _ = ndimage.label(ndimage.distance_transform_edt(free) * grid.resolution > half_width)

    def at(p: tuple[float, float]) -> int:
        return int(lab[int((p[1] - grid.origin[1]) / grid.resolution), int((p[0] - grid.origin[0]) / grid.resolution)])

    return at(a) != 0 and at(a) == at(b)


def _free_run(grid, xs: np.ndarray, ys: np.ndarray) -> float:
    """The longest run of free cells along the sampled points (metres, one cell per point)."""
    best = run = 0
    for x, y in zip(xs.tolist(), ys.tolist(), strict=True):
        run = run + 1 if grid.value_at(x, y) == FREE else 0
        best = max(best, run)
    return best * RES


@V
def test_a_door_by_the_transition_line_slides_off_the_corner(tmp_path: Path, v2: bool) -> None:
    """The line crosses the shared wall 0.2 m from its corner: the opening slides along that leg."""
    a = _poly_cell("A", [(0, 0), (9, 0), (9, 3.4), (5, 3.4), (5, 7), (0, 7)])
    cells = a + _cell("B", (5, 3.4, 9, 7))
    line = "3 3.8 6 3.5"  # crosses x = 5 at y = 3.6, 0.2 m above the corner (5, 3.4)
    b, grid, report = _grid_and_report(_plan(tmp_path, cells, _graph([("A", "B")], {0: line}, v2=v2), v2=v2))
    [o] = plan_openings(b, b.storeys[0].name).openings
    assert o.rule == "line" and o.width == pytest.approx(0.9)
    [seg] = o.segments
    assert len(seg.coords) == 2  # straight, not laid round the corner
    ys = np.arange(3.4 + RES / 2, 5.0, RES)
    assert _free_run(grid, np.full(len(ys), 5.0 - RES / 2), ys) >= 0.9 - RES
    assert _clear_joined(grid, (2.0, 2.0), (7.0, 5.5), 0.35)  # a 0.70 m chair passes in the written grid
    [k] = report.links
    assert k.chair and k.free_width >= 0.9 - RES


@V
def test_a_door_in_the_middle_of_a_short_bent_wall_is_named_narrower(tmp_path: Path, v2: bool) -> None:
    """The A-B boundary is 1.1 m long but bent (legs 0.6 m and 0.5 m): no straight 0.9 m fits, so the
    opening takes the longer leg and says so, instead of claiming 0.9 m round the corner."""
    a = _poly_cell("A", [(0, 0), (5.6, 0), (5.6, 3.4), (5, 3.4), (5, 3.9), (0, 3.9)])
    c, d = _cell("C", (0, 3.9, 5, 7)), _cell("D", (5.6, 0, 9, 3.4))
    cells = a + _cell("B", (5, 3.4, 9, 7)) + c + d
    graph = _graph([("A", "B"), ("A", "C"), ("A", "D")], v2=v2)
    b, grid, report = _grid_and_report(_plan(tmp_path, cells, graph, v2=v2))
    opening = next(o for o in plan_openings(b, b.storeys[0].name).openings if {o.link.a, o.link.b} == {"A", "B"})
    assert opening.rule == "middle"
    assert opening.width == pytest.approx(0.6)  # the longer leg, not 0.9
    xs = np.arange(5.0 + RES / 2, 5.6, RES)
    assert abs(_free_run(grid, xs, np.full(len(xs), 3.4 - RES / 2)) - opening.width) <= 2 * RES  # as written
    link = next(k for k in report.links if set(k.cells) == {"A", "B"})
    assert not link.chair and "narrower than the chair" in link.describe()
    assert not _clear_joined(grid, (2.0, 2.0), (7.0, 5.5), 0.35)
