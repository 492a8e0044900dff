"""Rooms and routes on real IndoorGML files (../shared/data/indoorgml), not only on our clinic sample.

Converted at 0.05 m as a user would (`pmk convert`), then the rooms file beside each map is used the
way Home's "Go to…" uses it: every destination offered must either get a route or say why, in a
specific error; doorways drawn as spaces are not destinations; a plan without transitions says so.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from pmk_nb.cli import main
from pmk_nb.guide import NoAccessibleRoute, NoGraph, load_rooms, plan_route
from pmk_nb.guide.rooms import MIN_ROOM_WIDTH
from tests.shared_data import INDOORGML_DATA


def converted(name: str, tmp_path: Path) -> list[Path]:
    out = tmp_path / "maps"
    assert main(["convert", str(INDOORGML_DATA / name), "--resolution", "0.05", "--out", str(out)]) == 0
    return sorted(out.glob("*.yaml"))


def routes_from_first_room(yaml: Path) -> tuple[int, list[Exception]]:
    rooms = load_rooms(yaml)
    first, *others = rooms.destinations()
    xy = first.polygon.representative_point().coords[0]
    ok, refused = 0, []
    for room in others:
        try:
            plan_route(rooms, xy, room, 0.70)
            ok += 1
        except (NoAccessibleRoute, NoGraph) as err:  # any other error type is a fault: the test fails
            refused.append(err)
    return ok, refused


def test_fzk_doorway_cells_are_not_destinations_and_every_room_is_reached(tmp_path: Path) -> None:
    ground = converted("fzk_haus_poslist.gml", tmp_path)[0]
    rooms = load_rooms(ground)
    thin = [r for r in rooms.rooms if r.kind.is_free and r.polygon.area < 1.0]
    assert len(thin) >= 4  # FZK-Haus draws its doorways as navigable cells 0.24-0.3 m deep
    assert not set(thin) & set(rooms.destinations())
    assert all(
        min(r.polygon.bounds[2] - r.polygon.bounds[0], r.polygon.bounds[3] - r.polygon.bounds[1]) >= MIN_ROOM_WIDTH
        for r in rooms.destinations()
    )
    ok, refused = routes_from_first_room(ground)
    assert (ok, refused) == (len(rooms.destinations()) - 1, [])


@pytest.mark.slow
@pytest.mark.parametrize("name", ["pnu201_3floors_navi_corrected.gml", "fjk_haus_v1_0_3.gml"])
def test_real_plans_route_or_name_the_narrow_door(name: str, tmp_path: Path) -> None:
    total_ok = 0
    for yaml in converted(name, tmp_path):
        ok, refused = routes_from_first_room(yaml)
        total_ok += ok
        for err in refused:  # a refusal is a finding the user can act on, never a bare failure
            assert isinstance(err, NoAccessibleRoute) and str(err).startswith("no accessible route to ")
    assert total_ok >= 10


def test_a_plan_without_transitions_says_it_has_no_graph(tmp_path: Path) -> None:
    (yaml,) = converted("pnu313_4F_2D_doors_subset.gml", tmp_path)
    ok, refused = routes_from_first_room(yaml)
    assert ok == 0 and refused and all(isinstance(e, NoGraph) for e in refused)
    assert "no navigation graph" in str(refused[0]) and "Tap the destination" in str(refused[0])
