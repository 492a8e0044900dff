"""The bare-boundary door rule: a line covering only part of the straight wall it lies on is an opening."""

from __future__ import annotations

from shapely.geometry import LineString, MultiPolygon, Polygon, box

from pmk_nb.indoorgml.doors import partial_edge

ROOM = box(0, 0, 5, 4)
# the same room with its bottom wall split at door jambs (1.0 and 1.9), as editors write it
SPLIT = Polygon([(0, 0), (1.0, 0), (1.9, 0), (5, 0), (5, 4), (0, 4)])


def test_a_short_line_on_a_wall_is_an_opening() -> None:
    assert partial_edge(LineString([(1.0, 0), (1.9, 0)]), [ROOM])


def test_the_wall_run_spans_the_jambs_the_editor_split_it_at() -> None:
    assert partial_edge(LineString([(1.0, 0), (1.9, 0)]), [SPLIT])
    assert not partial_edge(LineString([(0, 0), (5, 0)]), [SPLIT])


def test_a_line_covering_the_whole_wall_is_a_wall() -> None:
    assert not partial_edge(LineString([(0, 0), (5, 0)]), [ROOM])
    assert not partial_edge(LineString([(5, 0.2), (5, 3.9)]), [ROOM])  # 3.7 of 4 m: over 90 %


def test_a_line_on_no_outline_is_not_an_opening() -> None:
    assert not partial_edge(LineString([(1.0, 2.0), (1.9, 2.0)]), [ROOM])
    assert not partial_edge(LineString([(1.0, 0), (1.9, 0)]), [])


def test_a_neighbour_whose_whole_wall_it_is_makes_it_a_wall() -> None:
    closet = box(1.0, -1.0, 1.9, 0)  # its top wall is exactly the line
    assert not partial_edge(LineString([(1.0, 0), (1.9, 0)]), [ROOM, closet])


def test_rings_of_holes_and_of_every_part_count() -> None:
    with_hole = Polygon(box(0, 0, 10, 10).exterior.coords, [box(3, 3, 7, 7).exterior.coords])
    assert partial_edge(LineString([(4, 3), (5, 3)]), [with_hole])  # on the hole's 4 m wall
    parts = MultiPolygon([box(20, 0, 25, 4), ROOM])
    assert partial_edge(LineString([(1.0, 4), (1.9, 4)]), [parts])


def test_a_hand_drawn_line_a_little_off_the_wall_still_lies_on_it() -> None:
    assert partial_edge(LineString([(1.0, 0.05), (1.9, 0.05)]), [ROOM])  # within 15 % of 0.9 m
    assert not partial_edge(LineString([(1.0, 0.3), (1.9, 0.3)]), [ROOM])
