"""Map server hot reload (all three dialects), rosapi discovery and the ROS 1 / ROS 2 message spellings."""

from __future__ import annotations

import math

import pytest
import roslibpy

from pmk_nb.grid import OccupancyGrid
from tests.fixtures_sim import room_grid, wait_until, write_test_map


def call(ros: roslibpy.Ros, name: str, type_name: str, args: dict | None = None) -> dict:
    return roslibpy.Service(ros, name, type_name).call(roslibpy.ServiceRequest(args or {}), timeout=10)


def latest_map(ros: roslibpy.Ros) -> OccupancyGrid:
    got: list[dict] = []
    topic = roslibpy.Topic(ros, "/map", "nav_msgs/OccupancyGrid")
    topic.subscribe(got.append)
    assert wait_until(lambda: bool(got), 3.0)
    topic.unsubscribe()
    return OccupancyGrid.from_ros_msg(got[-1])


@pytest.fixture
def maps(tmp_path):
    """Two maps in a chair's maps folder: a 4x3 m room and a 6x4 m room with a wall at x = 2 m."""
    folder = tmp_path / "ALMA_MAPS"
    small = write_test_map(room_grid(4.0, 3.0), folder, "small")
    walled = write_test_map(room_grid(6.0, 4.0, wall_x=2.0), folder, "walled")
    broken = folder / "broken.yaml"
    broken.write_text(
        "image: missing.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 0\n"
        "occupied_thresh: 0.65\nfree_thresh: 0.196\n"
    )
    return folder, small, walled


def test_change_map_ros1(sim_factory, ros_factory, maps):
    folder, small, _ = maps
    sim = sim_factory(maps_dir=folder, grid=room_grid(8.0, 8.0), start_pose=(6.0, 6.0, 0.0))
    ros = ros_factory(sim)
    reply = call(ros, "/change_map", "nav_msgs/LoadMap", {"map_url": str(small)})
    assert reply["result"] == 0
    assert reply["map"]["info"]["width"] == 80 and reply["map"]["info"]["height"] == 60
    grid = latest_map(ros)
    assert (grid.width, grid.height) == (80, 60)
    x, y, _ = sim.pose  # (6, 6) is outside the new 4 x 3 m room: moved to the nearest free cell
    assert 0.35 <= x <= 3.65 and 0.35 <= y <= 2.65
    assert any("not free on the new map" in note for note in sim.notes)
    # failures: ROS 1 knows only 255
    for bad in ("missing.yaml", "broken.yaml", ""):
        assert call(ros, "/change_map", "nav_msgs/LoadMap", {"map_url": bad})["result"] == 255
    assert latest_map(ros).width == 80, "a failed reload must keep the current map"


@pytest.mark.parametrize(
    ("url", "code"),
    [
        ("small.yaml", 0),
        ("", 1),
        ("broken.yaml", 2),
        ("missing.yaml", 3),
        ("/home/pmk/ALMA_MAPS/walled.yaml", 0),
        ("~/ALMA_MAPS/walled.yaml", 3),  # like Nav2: "~" is not expanded
    ],
)
def test_load_map_nav2_codes(sim_factory, ros_factory, maps, url, code):
    folder, _, _ = maps
    sim = sim_factory(ros="ros2", maps_dir=folder, grid=room_grid(3.0, 3.0))
    ros = ros_factory(sim)
    reply = call(ros, "/map_server/load_map", "nav2_msgs/srv/LoadMap", {"map_url": url})
    assert reply["result"] == code
    assert (reply["map"]["info"]["width"] > 0) == (code == 0)


def test_map_update_original_service(sim_factory, ros_factory, maps):
    folder, _, walled = maps
    ros = ros_factory(sim_factory(maps_dir=folder))  # the map server reads only its maps folder (issue 30)
    assert call(ros, "/map_update", "map_server_pmk/MapUpdate", {"path": str(walled)}) == {"done": True}
    assert latest_map(ros).width == 120
    assert call(ros, "/map_update", "map_server_pmk/MapUpdate", {"path": "/nowhere/x.yaml"}) == {"done": False}


def test_static_map_matches_topic(sim_chair, ros_factory):
    ros = ros_factory(sim_chair)
    reply = call(ros, "/static_map", "nav_msgs/GetMap")
    assert OccupancyGrid.from_ros_msg(reply["map"]).data.tolist() == sim_chair.grid.data.tolist()


def test_reload_changes_what_the_laser_sees(sim_factory, ros_factory, maps):
    folder, _, _walled = maps
    sim = sim_factory(maps_dir=folder, grid=room_grid(6.0, 4.0), start_pose=(1.0, 2.0, 0.0))
    ros = ros_factory(sim)
    scans: list[dict] = []
    roslibpy.Topic(ros, "/scan", "sensor_msgs/LaserScan").subscribe(scans.append)
    assert wait_until(lambda: bool(scans), 3.0)
    assert scans[-1]["ranges"][360] == pytest.approx(4.95, abs=0.06)
    assert sim.load_map("walled.yaml") == 0
    scans.clear()
    assert wait_until(lambda: len(scans) >= 2, 3.0)
    assert scans[-1]["ranges"][360] == pytest.approx(1.0, abs=0.06)  # the new wall at x = 2


@pytest.mark.parametrize(
    ("services", "present", "absent"),
    [
        (("map_update",), ["/map_update"], ["/change_map", "/map_server/load_map"]),
        (("change_map", "load_map"), ["/change_map", "/map_server/load_map"], ["/map_update"]),
        ((), [], ["/change_map", "/map_server/load_map", "/map_update"]),
    ],
)
def test_reload_services_are_configurable(sim_factory, ros_factory, services, present, absent):
    ros = ros_factory(sim_factory(reload_services=services))
    listed = ros.get_services()
    assert all(s in listed for s in present)
    assert not any(s in listed for s in absent)
    assert "/static_map" in listed


def test_rosapi_discovery_ros1(sim_chair, ros_factory):
    ros = ros_factory(sim_chair)
    topics = call(ros, "/rosapi/topics", "rosapi/Topics")
    pairs = dict(zip(topics["topics"], topics["types"], strict=True))
    assert pairs["/odom"] == "nav_msgs/Odometry"
    assert pairs["/scan"] == "sensor_msgs/LaserScan"
    assert pairs["/map"] == "nav_msgs/OccupancyGrid"
    assert pairs["/cmd_vel"] == "geometry_msgs/Twist"
    assert ros.get_topic_type("/tf") == "tf2_msgs/TFMessage"
    assert ros.get_topic_type("/nope") == ""
    assert ros.get_topics_for_type("nav_msgs/Odometry") == ["/odom"]
    assert ros.get_service_type("/change_map") == "nav_msgs/LoadMap"
    assert ros.get_service_type("/map_update") == "map_server_pmk/MapUpdate"
    assert "/rosapi/get_time" in ros.get_services()
    now = ros.get_time()  # roslibpy parses secs/nsecs: ROS 1 stamps
    assert now.secs > 1_600_000_000


def test_ros2_names_and_stamps(sim_factory, ros_factory):
    sim = sim_factory(ros="ros2")
    ros = ros_factory(sim)
    assert ros.get_topic_type("/odom") == "nav_msgs/msg/Odometry"
    assert ros.get_service_type("/map_server/load_map") == "nav2_msgs/srv/LoadMap"
    assert ros.get_service_type("/rosapi/topics") == "rosapi_msgs/srv/Topics"
    assert "/change_map" not in ros.get_services()
    now = call(ros, "/rosapi/get_time", "rosapi_msgs/srv/GetTime")["time"]
    assert set(now) == {"sec", "nanosec"}
    odom: list[dict] = []
    # ROS 2 rosbridge accepts both type spellings on subscribe
    roslibpy.Topic(ros, "/odom", "nav_msgs/Odometry").subscribe(odom.append)
    assert wait_until(lambda: bool(odom), 3.0)
    header = odom[-1]["header"]
    assert set(header) == {"stamp", "frame_id"} and set(header["stamp"]) == {"sec", "nanosec"}
    assert call(ros, "/rosapi/get_ros_version", "rosapi_msgs/srv/GetROSVersion")["version"] == 2


def test_ros1_header_has_seq(sim_chair, ros_factory):
    ros = ros_factory(sim_chair)
    odom: list[dict] = []
    roslibpy.Topic(ros, "/odom", "nav_msgs/Odometry").subscribe(odom.append)
    assert wait_until(lambda: len(odom) >= 2, 3.0)
    assert odom[-1]["header"]["seq"] > odom[0]["header"]["seq"]
    q = odom[-1]["pose"]["pose"]["orientation"]
    assert math.isclose(q["x"] ** 2 + q["y"] ** 2 + q["z"] ** 2 + q["w"] ** 2, 1.0)
