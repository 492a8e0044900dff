"""Issue 31, linear cost: the wall steps' indexed searches give exactly what the all-pairs ones gave."""

from __future__ import annotations

import numpy as np
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st
from shapely import affinity
from shapely.geometry import box

from pmk_nb.raster.walls import door_jambs

TOL = 0.01


def _jambs_all_pairs(rooms: np.ndarray, doors: list, tol: float) -> list:
    """door_jambs as it was: every door measured against every other door."""
    tree = shapely.STRtree(rooms) if len(rooms) else None
    out = []
    for i, door in enumerate(doors):
        near = [d for j, d in enumerate(doors) if j != i and d.distance(door) <= tol]
        if tree is not None:
            near += list(rooms[tree.query(shapely.buffer(door, tol), predicate="intersects")])
        ring = shapely.boundary(door)
        if near:
            ring = shapely.difference(ring, shapely.buffer(shapely.union_all(near), tol))
        if not ring.is_empty:
            out.append(ring)
    return out


# door cells in a row, each a gap from the last: touching (0), exactly tol, just over, well apart
_gaps = st.lists(st.sampled_from([0.0, TOL / 2, TOL, TOL * 1.0001, 0.05, 1.0]), min_size=1, max_size=12)


@settings(max_examples=60, deadline=None)
@given(gaps=_gaps, turn=st.floats(0, 90), rooms_too=st.booleans())
def test_door_jambs_match_the_all_pairs_search(gaps: list[float], turn: float, rooms_too: bool) -> None:
    doors, x = [], 0.0
    for g in gaps:
        x += g
        doors.append(affinity.rotate(box(x, 0, x + 0.9, 0.2), turn, origin=(0, 0)))
        x += 0.9
    rooms = np.asarray(
        [affinity.rotate(box(-1, 0.2, x + 1, 4), turn, origin=(0, 0))] if rooms_too else [], dtype=object
    )
    got, want = door_jambs(rooms, doors, TOL), _jambs_all_pairs(rooms, doors, TOL)
    assert len(got) == len(want)
    assert all(shapely.equals_exact(a, b, 0.0) for a, b in zip(got, want, strict=True))


def test_door_jambs_cut_only_where_doors_meet() -> None:
    a, b, c = box(0, 0, 1, 0.2), box(1 + TOL / 2, 0, 2, 0.2), box(2.5, 0, 3.5, 0.2)  # a-b within tol, c apart
    jambs = door_jambs(np.asarray([], dtype=object), [a, b, c], TOL)
    assert jambs[2].length == c.boundary.length  # nothing near c: its whole outline stays
    assert jambs[0].length < a.boundary.length and jambs[1].length < b.boundary.length
