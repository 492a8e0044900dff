"""Hot map reload through each reload service, against the simulator's map server."""

from __future__ import annotations

import pytest

from pmk_nb.chair.link.client import ChairLink
from pmk_nb.chair.link.query.reload import MapReloadError
from tests.fixtures_sim import room_grid, write_test_map

CASES = [
    # (sim ROS version, the only reload service the sim offers, expected detected reload kind)
    ("ros1", "change_map", "ros1"),
    ("ros2", "load_map", "nav2"),
    ("ros1", "map_update", "mapupdate"),
]


@pytest.mark.parametrize(("ros", "only", "kind"), CASES)
def test_reload_map_through_each_service(sim_factory, ros: str, only: str, kind: str) -> None:
    sim = sim_factory(ros=ros, reload_services=[only])
    grid = room_grid(3.0, 2.0, 0.05, origin=(-0.5, -0.25))
    write_test_map(grid, sim.maps_dir, "room")
    with ChairLink("127.0.0.1", sim.port) as link:
        link.connect()
        assert link.detect_reload_service().kind == kind
        before = link.map_info(timeout=3.0)
        assert (before.width, before.height) != (grid.width, grid.height)
        link.reload_map("/home/pmk/ALMA_MAPS/room.yaml", timeout=20.0)
        after = link.map_info(timeout=3.0)
        assert (after.width, after.height) == (grid.width, grid.height)
        assert after.resolution == pytest.approx(0.05)
        assert after.origin[:2] == pytest.approx((-0.5, -0.25))


@pytest.mark.parametrize(
    ("ros", "only", "code"),
    # Nav2 answers INVALID_MAP_METADATA (3) for a YAML it cannot open, like nav2_map_server.
    [("ros1", "change_map", 255), ("ros2", "load_map", 3), ("ros1", "map_update", None)],
)
def test_failed_reload_raises_with_the_code_and_keeps_the_map(sim_factory, ros, only, code) -> None:
    sim = sim_factory(ros=ros, reload_services=[only])
    with ChairLink("127.0.0.1", sim.port) as link:
        link.connect()
        before = link.map_info(timeout=3.0)
        with pytest.raises(MapReloadError) as info:
            link.reload_map("/home/pmk/ALMA_MAPS/missing.yaml", timeout=10.0)
        assert info.value.code == code
        assert info.value.keeps_old_map is True
        assert "missing.yaml" in str(info.value) and "keeps its previous map" in str(info.value)
        assert link.map_info(timeout=3.0) == before


def test_nav2_reports_invalid_metadata(sim_factory) -> None:
    sim = sim_factory(ros="ros2", reload_services=["load_map"])
    (sim.maps_dir / "broken.yaml").write_text("image: broken.pgm\nresolution: [not, a, number]\n")
    with ChairLink("127.0.0.1", sim.port) as link:
        link.connect()
        with pytest.raises(MapReloadError) as info:
            link.reload_map("/home/pmk/ALMA_MAPS/broken.yaml")
        assert info.value.code == 3
        assert "INVALID_MAP_METADATA" in str(info.value)


@pytest.mark.parametrize("path", ["~/ALMA_MAPS/room.yaml", "ALMA_MAPS/room.yaml", ""])
def test_paths_a_map_server_cannot_read_are_refused_before_sending(sim_factory, path: str) -> None:
    """Noetic answers 255 and Nav2 "does not exist" for ``~`` paths: say why before asking."""
    sim = sim_factory(ros="ros1", reload_services=["change_map"])
    write_test_map(room_grid(3.0, 2.0, 0.05), sim.maps_dir, "room")
    with ChairLink("127.0.0.1", sim.port) as link:
        link.connect()
        before = link.map_info(timeout=3.0)
        with pytest.raises(MapReloadError) as info:
            link.reload_map(path)
        assert info.value.code is None and info.value.keeps_old_map is True
        assert "absolute path" in str(info.value) and "/ALMA_MAPS/" in info.value.hint
        assert link.map_info(timeout=3.0) == before


def test_explicit_service_and_kind(sim_factory) -> None:
    sim = sim_factory(ros="ros1", reload_services=["change_map", "map_update"])
    write_test_map(room_grid(2.0, 2.0, 0.1), sim.maps_dir, "small")
    with ChairLink("127.0.0.1", sim.port) as link:
        link.connect()
        link.reload_map("/home/pmk/ALMA_MAPS/small.yaml", service="/map_update")  # kind from rosapi's type
        assert link.map_info(timeout=3.0).width == 20
        link.reload_map("/home/pmk/ALMA_MAPS/small.yaml", kind="mapupdate")
        with pytest.raises(MapReloadError, match="load_map"):
            link.reload_map("/home/pmk/ALMA_MAPS/small.yaml", kind="nav2")  # the sim has no Nav2 service


def test_no_reload_service(sim_factory) -> None:
    sim = sim_factory(reload_services=[])
    with ChairLink("127.0.0.1", sim.port) as link:
        link.connect()
        with pytest.raises(MapReloadError, match="no map reload service"):
            link.reload_map("/home/pmk/ALMA_MAPS/x.yaml")
