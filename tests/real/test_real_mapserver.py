"""Real-stack tier: the PMK map server node (rclpy) behind a real rosbridge server, seen by roslibpy."""

from __future__ import annotations

import hashlib
import threading

import numpy as np
import roslibpy

from pmk_nb.robot.mapstore import MapStore
from pmk_nb.wire import grid_sha256
from tests import fixtures_ros2
from tests.fixtures_ros2 import RealChair, close_client
from tests.fixtures_sim import room_grid, write_test_map
from tests.helpers import wait_until

# the real-stack fixtures (not in the root conftest's plugins)
ros2_stack, real_chair = fixtures_ros2.ros2_stack, fixtures_ros2.real_chair

INFO = ("/map_server/map_info", "map_server_pmk/srv/MapInfo")
NAV2 = ("/map_server/load_map", "nav2_msgs/srv/LoadMap")
UPDATE = ("/map_update", "map_server_pmk/srv/MapUpdate")


def test_store_refuses_paths_outside_its_folder(tmp_path) -> None:
    maps = tmp_path / "maps"
    maps.mkdir()
    write_test_map(room_grid(), maps, "room")
    (maps / "out.yaml").symlink_to(tmp_path / "elsewhere.yaml")
    store = MapStore(maps)
    assert store.load("room.yaml")[0] == 0
    assert store.load(str(maps / "room.yaml"))[0] == 0
    assert store.load("file://" + str(maps / "room.yaml"))[0] == 0
    for outside in ("/etc/passwd", "../room.yaml", "out.yaml"):
        code, text = store.load(outside)
        assert code == 1 and "outside" in text, outside
    assert store.load("missing.yaml")[0] == 3  # Nav2: the YAML cannot be opened


def test_map_server_offers_map_info_load_map_and_map_update(real_chair: RealChair) -> None:
    first = write_test_map(room_grid(), real_chair.maps, "room")
    second_grid = room_grid(8.0, 5.0, wall_x=4.0, door=(1.0, 2.0))
    write_test_map(second_grid, real_chair.maps, "second")
    real_chair.start_bridge()
    real_chair.start_map_server("room")
    info = real_chair.wait_service(*INFO)
    assert info["loaded"] is True and info["path"] == str(first)
    assert (info["info"]["width"], info["info"]["height"]) == (120, 80)
    assert info["header"]["frame_id"] == "map"
    assert info["sha256"] == grid_sha256(room_grid())

    ros = real_chair.client()
    try:
        meta: list[dict] = []
        grids: list[dict] = []
        roslibpy.Topic(ros, "/map_metadata", "nav_msgs/msg/MapMetaData").subscribe(meta.append)
        roslibpy.Topic(ros, "/map", "nav_msgs/msg/OccupancyGrid").subscribe(grids.append)
        wait_until(lambda: grids and meta, 15, "the latched /map and /map_metadata")
        assert len(grids[0]["data"]) == 120 * 80

        nav2 = roslibpy.Service(ros, *NAV2)
        reply = nav2.call(roslibpy.ServiceRequest({"map_url": "second.yaml"}), timeout=10)
        assert reply["result"] == 0 and reply["map"]["info"]["width"] == second_grid.width
        wait_until(lambda: grids[-1]["info"]["width"] == second_grid.width, 10, "/map republished")
        data = np.array(grids[-1]["data"], dtype=np.int8)
        assert hashlib.sha256(data.tobytes()).hexdigest() == grid_sha256(second_grid)
        for url, code in (("", 1), ("/etc/hostname", 1), ("nothere.yaml", 3)):
            assert nav2.call(roslibpy.ServiceRequest({"map_url": url}), timeout=10)["result"] == code, url

        update = roslibpy.Service(ros, *UPDATE)
        assert update.call(roslibpy.ServiceRequest({"path": str(first)}), timeout=10)["done"] is True
        assert update.call(roslibpy.ServiceRequest({"path": "/etc/hostname"}), timeout=10)["done"] is False
        info = roslibpy.Service(ros, *INFO).call(roslibpy.ServiceRequest({}), timeout=10)
        assert info["path"] == str(first) and info["sha256"] == grid_sha256(room_grid())
    finally:
        close_client(ros)


def test_late_subscriber_gets_the_map_once(real_chair: RealChair) -> None:
    """Transient local: a client that subscribes after the load still gets the map."""
    write_test_map(room_grid(), real_chair.maps, "room")
    real_chair.start_bridge()
    real_chair.start_map_server("room")
    real_chair.wait_service(*INFO)
    ros = real_chair.client()
    try:
        got = threading.Event()
        roslibpy.Topic(ros, "/map", "nav_msgs/msg/OccupancyGrid").subscribe(lambda m: got.set())
        assert got.wait(15), "no /map for a late subscriber"
    finally:
        close_client(ros)
