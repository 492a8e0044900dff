"""The chair link with the real roslibpy client against the simulator (ROS 1 and ROS 2)."""

from __future__ import annotations

import math
import threading
import time
from collections.abc import Callable, Iterator
from typing import Any

import numpy as np
import pytest
import roslibpy

from pmk_nb.chair.link import ChairLink, LinkState, close_all_links, get_link
from pmk_nb.chair.link.registry import open_links
from pmk_nb.sim import SimChair
from tests.fixtures_sim import wait_until

ROS_VERSIONS = ["ros1", "ros2"]


@pytest.fixture
def links() -> Iterator[Callable[..., ChairLink]]:
    made: list[ChairLink] = []

    def make(sim: SimChair, **kw: Any) -> ChairLink:
        link = ChairLink("127.0.0.1", sim.port, **kw)
        made.append(link)
        return link

    yield make
    for link in made:
        link.close()


def _io_threads() -> list[threading.Thread]:
    return [t for t in threading.enumerate() if t.name.startswith("pmk-link-")]


@pytest.mark.parametrize("ros", ROS_VERSIONS)
def test_connection_report_matches_the_published_map(sim_factory, links, ros: str) -> None:
    sim = sim_factory(ros=ros)
    link = links(sim)
    report = link.test_connection(timeout=5.0)
    assert report.ok, report.reason
    assert report.reason == "connected"
    grid = sim.grid
    assert grid is not None and report.map_info is not None
    assert (report.map_info.width, report.map_info.height) == (grid.width, grid.height)
    assert report.map_info.resolution == pytest.approx(grid.resolution)
    assert report.map_info.origin[:2] == pytest.approx(grid.origin[:2])
    assert report.ros_version == (2 if ros == "ros2" else 1)
    assert report.elapsed < 5.0
    assert link.state is LinkState.CONNECTED
    assert link.map_info(timeout=3.0) == report.map_info


@pytest.mark.slow
@pytest.mark.parametrize("ros", ROS_VERSIONS)
def test_streams_flow_at_throttled_rates(sim_factory, links, ros: str) -> None:
    sim = sim_factory(ros=ros, odom_rate=50.0, scan_rate=20.0, rays=360, start_pose=(2.0, 1.5, 0.7))
    link = links(sim, throttle_ms={"odom": 40, "scan": 50})
    link.connect(timeout=5.0)
    link.start_streams()
    assert wait_until(lambda: link.latest_odom() is not None and link.latest_scan() is not None, 5.0)
    before, t0 = link.message_counts, time.monotonic()
    time.sleep(1.5)
    after, dt = link.message_counts, time.monotonic() - t0
    odom_hz = (after["odom"] - before["odom"]) / dt
    scan_hz = (after["scan"] - before["scan"]) / dt
    assert 8.0 < odom_hz <= 30.0, odom_hz  # sim 50 Hz, throttled to one per 40 ms (25 Hz)
    assert 5.0 < scan_hz <= 25.0, scan_hz
    odom = link.latest_odom()
    assert odom is not None
    x, y, theta = sim.pose
    assert (odom.x, odom.y) == pytest.approx((x, y), abs=0.05)
    assert math.cos(odom.theta - theta) == pytest.approx(1.0, abs=1e-3)
    assert time.monotonic() - odom.received < 1.0
    scan = link.latest_scan()
    assert scan is not None
    assert scan.ranges.dtype == np.float32 and scan.ranges.shape == (360,) == scan.at_max.shape
    assert np.isfinite(scan.ranges).any()
    # every ray is either a valid range or marked invalid/no-hit, never a raw inf
    assert not np.isinf(scan.ranges).any()
    pose = link.latest_pose()
    assert pose is not None and pose.frame == "odom" and pose.x == pytest.approx(odom.x, abs=0.2)


@pytest.mark.parametrize("ros", ROS_VERSIONS)
def test_pose_from_tf_is_in_the_map_frame(sim_factory, links, ros: str) -> None:
    sim = sim_factory(ros=ros, start_pose=(3.0, 2.0, -0.5))
    link = links(sim, pose_source="tf")
    link.connect()
    link.start_streams()
    assert wait_until(lambda: link.latest_pose() is not None and link.latest_pose().frame == "map", 5.0)
    pose = link.latest_pose()
    x, y, theta = sim.pose
    assert (pose.x, pose.y) == pytest.approx((x, y), abs=0.05)
    assert math.cos(pose.theta - theta) == pytest.approx(1.0, abs=1e-3)


@pytest.mark.parametrize(
    ("ros", "type_name"),
    [("ros1", "geometry_msgs/PoseWithCovarianceStamped"), ("ros2", "geometry_msgs/msg/PoseStamped")],
)
def test_pose_from_a_pose_topic(sim_factory, links, ros_factory, ros: str, type_name: str) -> None:
    sim = sim_factory(ros=ros)
    other = ros_factory(sim)
    pub = roslibpy.Topic(other, "/amcl_pose", type_name)
    pub.advertise()
    link = links(sim, pose_source="pose_topic", pose_topic="/amcl_pose")
    link.start_streams()  # before connect: subscribed (with the type from rosapi) on connect
    link.connect()
    pose = {"position": {"x": 4.0, "y": -1.0, "z": 0.0}, "orientation": {"x": 0, "y": 0, "z": 1.0, "w": 0}}
    stamp = {"sec": 1, "nanosec": 0} if ros == "ros2" else {"secs": 1, "nsecs": 0}
    body = {"pose": pose, "covariance": [0.0] * 36} if "Covariance" in type_name else pose
    msg = {"header": {"frame_id": "map", "stamp": stamp}, "pose": body}

    def published() -> bool:
        pub.publish(roslibpy.Message(msg))
        return link.latest_pose() is not None

    assert wait_until(published, 5.0, interval=0.1)
    got = link.latest_pose()
    assert (got.x, got.y, got.frame) == (4.0, -1.0, "map")
    assert abs(got.theta) == pytest.approx(math.pi)


@pytest.mark.slow
def test_stale_when_the_chair_stops_publishing(sim_chair, links) -> None:
    link = links(sim_chair, stale_after=0.5)
    seen: list[LinkState] = []
    threads: set[str] = set()

    def record(state: LinkState) -> None:
        seen.append(state)
        threads.add(threading.current_thread().name)

    unsubscribe = link.on_state_change(record)
    link.connect()
    link.start_streams()
    assert wait_until(lambda: link.state is LinkState.CONNECTED and link.latest_odom() is not None, 5.0)
    sim_chair.pause()
    assert wait_until(lambda: link.state is LinkState.STALE, 3.0)
    assert wait_until(lambda: LinkState.STALE in seen, 1.0)  # callbacks follow within a watchdog tick
    assert link.latest_odom() is not None  # the last values stay readable, their age grows
    sim_chair.resume()
    assert wait_until(lambda: link.state is LinkState.CONNECTED, 3.0)
    assert wait_until(lambda: seen[-1:] == [LinkState.CONNECTED], 1.0)
    assert seen[:3] == [LinkState.CONNECTED, LinkState.STALE, LinkState.CONNECTED]
    assert all(name.startswith("pmk-link-watchdog") for name in threads)  # documented callback thread
    unsubscribe()
    count = len(seen)
    sim_chair.pause()
    assert wait_until(lambda: link.state is LinkState.STALE, 3.0)
    time.sleep(0.3)
    assert len(seen) == count  # no callback after unsubscribing


@pytest.mark.slow
@pytest.mark.parametrize("ros", ROS_VERSIONS)
def test_reconnects_and_resubscribes_after_the_chair_restarts(sim_factory, links, ros: str) -> None:
    sim = sim_factory(ros=ros)
    link = links(sim, reconnect_initial=0.2, reconnect_max=1.0)
    seen: list[LinkState] = []
    link.on_state_change(seen.append)
    link.connect()
    link.start_streams()
    assert wait_until(lambda: link.latest_odom() is not None, 5.0)
    port = sim.port
    sim.stop()
    assert wait_until(lambda: link.state is LinkState.CONNECTING, 5.0)
    time.sleep(0.6)  # a few refused reconnect attempts
    sim.start()
    assert sim.port == port
    assert wait_until(lambda: link.state is LinkState.CONNECTED, 10.0)
    count = link.message_counts["odom"]
    assert wait_until(lambda: link.message_counts["odom"] > count + 5, 5.0)  # odom flows again
    assert LinkState.CONNECTING in seen and seen[-1] is LinkState.CONNECTED


@pytest.mark.parametrize("ros", ROS_VERSIONS)
def test_discovery_in_both_spellings(sim_factory, links, ros: str) -> None:
    sim = sim_factory(ros=ros)
    link = links(sim)
    link.connect()
    for spelling in ("nav_msgs/Odometry", "nav_msgs/msg/Odometry"):
        assert link.topics_of_type(spelling) == ["/odom"]
    assert "/scan" in link.topics_of_type("sensor_msgs/LaserScan")
    assert link.topics_of_type("nav_msgs/NoSuchType") == []
    services = link.services()
    assert "/rosapi/topics" in services and "/static_map" in services
    assert link.discovery.ros_version() == (2 if ros == "ros2" else 1)


@pytest.mark.parametrize(
    ("ros", "only", "name", "kind"),
    [
        ("ros1", "change_map", "/change_map", "ros1"),
        ("ros2", "load_map", "/map_server/load_map", "nav2"),
        ("ros1", "map_update", "/map_update", "mapupdate"),
        ("ros2", "map_update", "/map_update", "mapupdate"),
    ],
)
def test_detects_the_only_reload_service(sim_factory, links, ros, only, name, kind) -> None:
    sim = sim_factory(ros=ros, reload_services=[only])
    link = links(sim)
    link.connect()
    found = link.detect_reload_service()
    assert found is not None and (found.name, found.kind) == (name, kind)


def test_detection_prefers_change_map_and_reports_none(sim_factory, links) -> None:
    sim = sim_factory(reload_services=["map_update", "load_map", "change_map"])
    link = links(sim)
    link.connect()
    assert link.detect_reload_service().name == "/change_map"
    bare = sim_factory(reload_services=[])
    link2 = links(bare)
    link2.connect()
    assert link2.detect_reload_service() is None


def test_registry_reuses_one_link_per_chair(sim_chair) -> None:
    try:
        a = get_link("127.0.0.1", sim_chair.port)
        b = get_link("127.0.0.1", sim_chair.port)
        assert a is b
        a.connect()
        c = get_link("127.0.0.1", sim_chair.port, odom_topic="/odom", scan_topic="/scan")
        assert c is a and c.is_connected  # same settings: nothing reopened
        d = get_link("127.0.0.1", sim_chair.port, stale_after=1.0)
        assert d is a and d.stale_after == 1.0  # new settings applied to the same link
        assert a in open_links()
    finally:
        close_all_links()
    assert open_links() == [] and not a.is_connected


def test_close_and_reconnect_repeatedly_in_one_process(sim_chair) -> None:
    before = len(_io_threads())
    shared_loops = sum(t.name == "roslibpy-asyncio" for t in threading.enumerate())
    link = ChairLink("127.0.0.1", sim_chair.port)
    try:
        for _ in range(4):
            link.connect(timeout=5.0)
            link.start_streams()
            assert wait_until(lambda: link.latest_odom() is not None, 5.0)
            assert len(_io_threads()) == before + 2  # one I/O thread, one watchdog
            link.close()
            assert link.state is LinkState.DISCONNECTED
            assert link.latest_odom() is None
            assert len(_io_threads()) == before  # close released the threads
            assert wait_until(lambda: sim_chair.client_count == 0, 3.0)  # and the socket
        # the link never starts roslibpy's process-wide loop (it has a private one)
        assert sum(t.name == "roslibpy-asyncio" for t in threading.enumerate()) == shared_loops
    finally:
        link.close()


def test_commands_reach_the_chair(sim_factory, links) -> None:
    sim = sim_factory()
    link = links(sim)
    link.connect()
    assert wait_until(lambda: link.publish_cmd_vel(0.3, 0.2) and sim.velocity[0] > 0.05, 3.0, interval=0.1)
    assert link.send_goal(3.0, 2.0, 0.0)
    assert wait_until(lambda: sim.goal_status != "idle", 3.0)


@pytest.mark.parametrize("ros", ROS_VERSIONS)
def test_fetch_map_returns_the_published_grid(sim_factory, links, tmp_path, ros: str) -> None:
    from pmk_nb.rosmap import read_map, write_map

    sim = sim_factory(ros=ros)
    link = links(sim)
    link.connect()
    grid = link.fetch_map(timeout=10.0)
    assert grid.data.shape == sim.grid.data.shape
    assert np.array_equal(grid.data, sim.grid.data)
    assert grid.resolution == pytest.approx(sim.grid.resolution)
    # the robot's own map can be saved as map_server files
    files = write_map(grid, tmp_path, "robot_map", preview=False)
    assert np.array_equal(read_map(files.yaml).data, grid.data)


def test_map_info_falls_back_to_the_map_topic(sim_chair, links) -> None:
    link = links(sim_chair, map_metadata_topic="/no_metadata_here")
    report = link.test_connection(timeout=5.0)
    assert report.ok, report.reason
    assert (report.map_info.width, report.map_info.height) == (sim_chair.grid.width, sim_chair.grid.height)


@pytest.mark.slow
def test_connected_but_no_map(sim_chair, links) -> None:
    link = links(sim_chair, map_topic="/no_map", map_metadata_topic="/no_metadata")
    t0 = time.monotonic()
    report = link.test_connection(timeout=1.5)
    assert not report.ok
    assert report.reason == "connected but no map published within 1.5 s"
    assert report.ros_version == 1
    assert time.monotonic() - t0 < 2.5
    assert link.is_connected  # the link itself is fine; only the map is missing


def test_listeners_run_on_the_io_thread_and_cannot_block_it(sim_chair, links) -> None:
    link = links(sim_chair)
    got: list[tuple[str, Any]] = []
    errors: list[str] = []

    def on_odom(odom: Any) -> None:
        got.append((threading.current_thread().name, odom))
        if len(got) == 1:
            try:
                link.services()  # a blocking call here would deadlock the I/O thread
            except Exception as err:
                errors.append(str(err))

    remove = link.add_listener("odom", on_odom)
    link.connect()
    link.start_streams()
    assert wait_until(lambda: len(got) >= 3, 5.0)
    assert got[0][0].startswith("pmk-link-io")
    assert got[-1][1].x == pytest.approx(sim_chair.pose[0], abs=0.2)
    assert errors and "I/O thread" in errors[0]
    remove()
    n = len(got)
    time.sleep(0.2)
    assert len(got) == n
    assert link.message_counts["odom"] > n  # the stream itself keeps flowing


def test_reconfigure_while_streaming_switches_the_pose_source(sim_chair, links) -> None:
    link = links(sim_chair)
    link.connect()
    link.start_streams()
    assert wait_until(lambda: link.latest_pose() is not None, 5.0)
    assert link.latest_pose().frame == "odom"
    with pytest.raises(ValueError, match="pose_topic"):
        link.reconfigure(pose_source="pose_topic")  # rejected before anything changes
    assert link.config["pose_source"] == "odometry"
    odoms: list[Any] = []
    link.add_listener("odom", odoms.append)
    link.reconfigure(pose_source="tf")
    assert wait_until(lambda: link.latest_pose() is not None and link.latest_pose().frame == "map", 5.0)
    assert wait_until(lambda: len(odoms) > 2, 3.0)  # listeners survive a reconfigure
