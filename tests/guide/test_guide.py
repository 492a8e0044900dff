"""Rooms by name on the clinic sample: "you are here", search, routes over the graph, goals in rooms."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import shapely

from pmk_nb.errors import MapFormatError
from pmk_nb.grid import FREE
from pmk_nb.guide import NoAccessibleRoute, UnknownRoom, goal_in_room, load_rooms, plan_route
from pmk_nb.guide.errors import NotOnMap
from pmk_nb.guide.route import narrow_passages
from pmk_nb.library import convert_plan

SAMPLE = Path(__file__).resolve().parents[2] / "sample_maps" / "clinic_floor.gml"
D5 = "1550.0 890.0 1640.0 890.0 1640.0 910.0 1550.0 910.0 1550.0 890.0"
D5_NARROW = "1550.0 890.0 1600.0 890.0 1600.0 910.0 1550.0 910.0 1550.0 890.0"  # 0.5 m wide


@pytest.fixture(scope="module")
def clinic(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("clinic")
    return convert_plan(SAMPLE, out, "clinic", 0.05).maps[0].files.yaml


@pytest.fixture(scope="module")
def narrow_clinic(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The clinic with the treatment room's door cut to 0.5 m."""
    out = tmp_path_factory.mktemp("narrow")
    text = SAMPLE.read_text(encoding="utf-8")
    assert D5 in text
    gml = out / "narrow.gml"
    gml.write_text(text.replace(D5, D5_NARROW), encoding="utf-8")
    return convert_plan(gml, out, "narrow", 0.05).maps[0].files.yaml


def test_you_are_here_names_the_room(clinic: Path) -> None:
    rooms = load_rooms(clinic)
    assert rooms.room_at(15.0, 2.95).label == "Exam room 1"
    assert rooms.room_at(5.0, 4.0).label == "Waiting room"  # on the desk: still the waiting room
    assert rooms.room_at(15.0, 7.5).label == "Corridor"
    assert rooms.room_at(14.95, 6.0).label == "Door Exam room 1"  # in the doorway: the door
    assert rooms.room_at(-2.0, -2.0) is None


def test_search_lists_destinations_not_doors(clinic: Path) -> None:
    rooms = load_rooms(clinic)
    labels = [r.label for r in rooms.destinations()]
    assert labels == sorted(labels, key=str.casefold)
    assert "Treatment room" in labels and not any(lb.startswith("Door") for lb in labels)
    assert "Reception desk" not in " ".join(labels)  # an obstacle is no destination
    assert [r.label for r in rooms.search("exam")] == ["Exam room 1", "Exam room 2"]
    assert [r.label for r in rooms.search("room 2 EXAM")] == ["Exam room 2"]
    assert rooms.search("corr")[0].label == "Corridor"
    assert [r.label for r in rooms.search("room")][:2] == ["Exam room 1", "Exam room 2"]  # alphabetical
    assert rooms.room("  treatment   ROOM ").id == "R5"
    with pytest.raises(UnknownRoom) as err:
        rooms.room("Cafeteria")
    assert err.value.query == "Cafeteria"


def test_route_goes_door_to_door_through_the_corridor(clinic: Path) -> None:
    rooms = load_rooms(clinic)
    route = plan_route(rooms, (5.0, 2.0), "Treatment room")
    assert [r.label for r in route.rooms] == [
        "Waiting room",
        "Door Waiting room",
        "Corridor",
        "Door Treatment room",
        "Treatment room",
    ]
    door1, door5 = route.points[1], route.points[2]
    assert math.dist(door1, (4.95, 6.0)) < 0.1 and math.dist(door5, (15.95, 9.0)) < 0.1
    gx, gy, yaw = route.goal
    assert shapely.contains_xy(rooms.room("Treatment room").polygon, gx, gy)
    assert abs(yaw - math.atan2(gy - door5[1], gx - door5[0])) < 1e-6  # facing the way in
    assert 15.0 < route.length < 25.0
    assert not route.needs_waypoints and route.goal_waypoints == []  # every door fits: the goal alone
    assert len(route.waypoints) == 2
    same = plan_route(rooms, (15.0, 3.0), "Exam room 1")
    assert [r.label for r in same.rooms] == ["Exam room 1"] and len(same.points) == 2


def test_goal_is_free_and_clear_of_furniture(clinic: Path) -> None:
    rooms = load_rooms(clinic)
    grid = rooms.grid
    for room in rooms.destinations():
        spot = goal_in_room(rooms, room, 0.7)
        assert spot is not None
        x, y = spot
        assert shapely.contains_xy(room.polygon, x, y), room.label
        col = int((x - grid.origin[0]) / grid.resolution)
        row = int((y - grid.origin[1]) / grid.resolution)
        r = round(0.7 / grid.resolution)  # 0.7 m clear all round
        assert np.all(np.asarray(grid.data)[row - r : row + r + 1, col - r : col + r + 1] == FREE), room.label
    x, y = goal_in_room(rooms, rooms.room("Waiting room"), 0.7) or (0.0, 0.0)
    assert not (3.0 - 0.7 < x < 7.0 + 0.7 and 3.5 - 0.7 < y < 4.5 + 0.7)  # not at the desk


def test_narrow_door_blocks_the_room_and_is_named(narrow_clinic: Path) -> None:
    rooms = load_rooms(narrow_clinic)
    with pytest.raises(NoAccessibleRoute) as err:
        plan_route(rooms, (5.0, 2.0), "Treatment room")
    assert [name for name, _ in err.value.narrow] == ["Door Treatment room"]
    assert 0.3 < err.value.narrow[0][1] < 0.6
    assert "Door Treatment room" in str(err.value)
    assert plan_route(rooms, (5.0, 2.0), "Office").destination.label == "Office"  # the rest still works
    route = plan_route(rooms, (5.0, 2.0), "Exam room 2")
    assert route.needs_waypoints  # the storey has a passage the chair does not fit: doorways are sent
    assert len(route.goal_waypoints) == 2
    assert [n for n, _ in narrow_passages(rooms)] == ["Door Treatment room"] * 2


def test_a_wider_chair_is_stopped_by_every_door(clinic: Path) -> None:
    with pytest.raises(NoAccessibleRoute) as err:
        plan_route(load_rooms(clinic), (5.0, 2.0), "Exam room 2", chair_width=1.0)
    assert [n for n, _ in err.value.narrow] == ["Door Waiting room", "Door Exam room 2"]
    assert err.value.chair_width == 1.0


def test_off_the_map_and_missing_rooms_file(clinic: Path, tmp_path: Path) -> None:
    with pytest.raises(NotOnMap):
        plan_route(load_rooms(clinic), (-5.0, -5.0), "Office")
    with pytest.raises(MapFormatError):
        load_rooms(tmp_path / "nothing.yaml")
