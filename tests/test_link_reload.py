"""Hot map reload through each service flavour, against the simulator's map server."""

from __future__ import annotations

import pytest

from pmk_nb.chair.link.client import ChairLink
from pmk_nb.chair.reload import MapReloadError
from tests.fixtures_sim import room_grid, write_test_map

CASES = [
    # (sim flavour, the only reload service the sim offers, expected detected flavour)
    ("ros1", "change_map", "ros1"),
    ("ros2", "load_map", "nav2"),
    ("ros1", "map_update", "mapupdate"),
]


@pytest.mark.parametrize(("flavour", "only", "kind"), CASES)
def test_reload_map_through_each_service(sim_factory, flavour: str, only: str, kind: str) -> None:
    sim = sim_factory(flavour=flavour, reload_services=[only])
    grid = room_grid(3.0, 2.0, 0.05, origin=(-0.5, -0.25))
    write_test_map(grid, sim.maps_dir, "room")
    with ChairLink("127.0.0.1", sim.port) as link:
        link.connect()
        assert link.detect_reload_service().flavour == kind
        before = link.map_info(timeout=3.0)
        assert (before.width, before.height) != (grid.width, grid.height)
        link.reload_map("~/ALMA_MAPS/room.yaml", timeout=20.0)
        after = link.map_info(timeout=3.0)
        assert (after.width, after.height) == (grid.width, grid.height)
        assert after.resolution == pytest.approx(0.05)
        assert after.origin[:2] == pytest.approx((-0.5, -0.25))


@pytest.mark.parametrize(
    ("flavour", "only", "code"),
    # Nav2 answers INVALID_MAP_METADATA (3) for a YAML it cannot open, like nav2_map_server.
    [("ros1", "change_map", 255), ("ros2", "load_map", 3), ("ros1", "map_update", None)],
)
def test_failed_reload_raises_with_the_code_and_keeps_the_map(sim_factory, flavour, only, code) -> None:
    sim = sim_factory(flavour=flavour, reload_services=[only])
    with ChairLink("127.0.0.1", sim.port) as link:
        link.connect()
        before = link.map_info(timeout=3.0)
        with pytest.raises(MapReloadError) as info:
            link.reload_map("~/ALMA_MAPS/missing.yaml", timeout=10.0)
        assert info.value.code == code
        assert "missing.yaml" in str(info.value) and "keeps its previous map" in str(info.value)
        assert link.map_info(timeout=3.0) == before


def test_nav2_reports_invalid_metadata(sim_factory) -> None:
    sim = sim_factory(flavour="ros2", reload_services=["load_map"])
    (sim.maps_dir / "broken.yaml").write_text("image: broken.pgm\nresolution: [not, a, number]\n")
    with ChairLink("127.0.0.1", sim.port) as link:
        link.connect()
        with pytest.raises(MapReloadError) as info:
            link.reload_map("~/ALMA_MAPS/broken.yaml")
        assert info.value.code == 3
        assert "INVALID_MAP_METADATA" in str(info.value)
        with pytest.raises(MapReloadError) as info:
            link.reload_map("")
        assert info.value.code == 1 and "MAP_DOES_NOT_EXIST" in str(info.value)


def test_explicit_service_and_flavour(sim_factory) -> None:
    sim = sim_factory(flavour="ros1", reload_services=["change_map", "map_update"])
    write_test_map(room_grid(2.0, 2.0, 0.1), sim.maps_dir, "small")
    with ChairLink("127.0.0.1", sim.port) as link:
        link.connect()
        link.reload_map("~/ALMA_MAPS/small.yaml", service="/map_update")  # flavour from rosapi's type
        assert link.map_info(timeout=3.0).width == 20
        link.reload_map("~/ALMA_MAPS/small.yaml", flavour="mapupdate")
        with pytest.raises(MapReloadError, match="load_map"):
            link.reload_map("~/ALMA_MAPS/small.yaml", flavour="nav2")  # the sim has no Nav2 service


def test_no_reload_service(sim_factory) -> None:
    sim = sim_factory(reload_services=[])
    with ChairLink("127.0.0.1", sim.port) as link:
        link.connect()
        with pytest.raises(MapReloadError, match="no map reload service"):
            link.reload_map("~/ALMA_MAPS/x.yaml")
