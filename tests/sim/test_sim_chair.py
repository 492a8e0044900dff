"""The simulated chair seen through a real roslibpy client: odometry, laser, driving, goals."""

from __future__ import annotations

import json
import math
import threading
import time

import pytest
import roslibpy
from websockets.sync.client import connect

from pmk_nb.sim.chair import DriveLimits
from pmk_nb.sim.demo import sample_floor
from tests.fixtures_sim import room_grid, wait_until


class Collector:
    """Thread-safe message list for roslibpy callbacks."""

    def __init__(self) -> None:
        self.items: list[dict] = []
        self.times: list[float] = []
        self._lock = threading.Lock()

    def __call__(self, msg: dict) -> None:
        with self._lock:
            self.items.append(msg)
            self.times.append(time.monotonic())

    def __len__(self) -> int:
        with self._lock:
            return len(self.items)

    def last(self) -> dict:
        with self._lock:
            return self.items[-1]


def twist(v: float, w: float = 0.0) -> roslibpy.Message:
    return roslibpy.Message({"linear": {"x": v, "y": 0.0, "z": 0.0}, "angular": {"x": 0.0, "y": 0.0, "z": w}})


def drive_for(topic: roslibpy.Topic, v: float, seconds: float, w: float = 0.0) -> None:
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        topic.publish(twist(v, w))
        time.sleep(0.1)


@pytest.mark.slow
def test_odometry_rate_and_frames(sim_chair, ros_factory):
    ros = ros_factory(sim_chair)
    odom = Collector()
    roslibpy.Topic(ros, "/odom", "nav_msgs/Odometry").subscribe(odom)
    assert wait_until(lambda: len(odom) > 0, 3.0)
    start = len(odom)
    time.sleep(1.0)
    count = len(odom) - start
    assert 25 <= count <= 75, f"expected ~50 odometry messages in 1 s, got {count}"
    msg = odom.last()
    assert msg["header"]["frame_id"] == "odom" and msg["child_frame_id"] == "base_link"
    assert set(msg["header"]["stamp"]) == {"secs", "nsecs"}
    x, y, _ = sim_chair.pose
    assert msg["pose"]["pose"]["position"]["x"] == pytest.approx(x, abs=1e-6)
    assert msg["pose"]["pose"]["position"]["y"] == pytest.approx(y, abs=1e-6)
    assert "twist" in msg["twist"]


def test_scan_shape_and_walls(sim_factory, ros_factory):
    # 6 x 4 m room, chair at (1.5, 2.0) facing +x: the wall at x = 6 - 0.05 is 4.45 m ahead
    sim = sim_factory(grid=room_grid(6.0, 4.0), start_pose=(1.5, 2.0, 0.0))
    ros = ros_factory(sim)
    scans = Collector()
    roslibpy.Topic(ros, "/scan", "sensor_msgs/LaserScan").subscribe(scans)
    assert wait_until(lambda: len(scans) >= 3, 3.0)
    scan = scans.last()
    assert len(scan["ranges"]) == 720
    assert math.degrees(scan["angle_max"] - scan["angle_min"]) == pytest.approx(270.0, abs=0.01)
    assert scan["angle_increment"] == pytest.approx(math.radians(270.0) / 719)
    mid = scan["ranges"][360]  # straight ahead
    assert mid == pytest.approx(4.45, abs=0.06)
    left = scan["ranges"][round((math.pi / 2 - scan["angle_min"]) / scan["angle_increment"])]
    assert left == pytest.approx(1.95, abs=0.06)  # wall at y = 4 - 0.05
    assert all(scan["range_min"] <= r <= scan["range_max"] for r in scan["ranges"])  # closed room: all hit


def test_scan_no_return_and_blind_rays_are_null_like_a_real_bridge(sim_factory, ros_factory):
    sim = sim_factory(grid=room_grid(30.0, 4.0), start_pose=(1.0, 2.0, 0.0), rays=90)
    ros = ros_factory(sim)
    scans = Collector()
    roslibpy.Topic(ros, "/scan", "sensor_msgs/LaserScan").subscribe(scans)
    assert wait_until(lambda: len(scans) >= 1, 3.0)
    scan = scans.last()
    assert len(scan["ranges"]) == 90
    ahead = scan["ranges"][45]
    assert ahead is None, "a wall 28 m away is out of range: +inf, which rosbridge sends as null"
    assert all(r is None or scan["range_min"] <= r <= scan["range_max"] for r in scan["ranges"])
    sim.laser.blind = (math.radians(-100), math.radians(-80))  # a covered sensor to the right
    time.sleep(0.2)
    n = len(scans)
    assert wait_until(lambda: len(scans) > n, 3.0)
    side = scans.last()["ranges"]
    assert all(r is None for r in side[12:18]), "blind rays (NaN) are null on the wire"  # -100..-80 deg


@pytest.mark.slow
def test_cmd_vel_moves_and_times_out(sim_factory, ros_factory):
    sim = sim_factory(grid=room_grid(8.0, 4.0), start_pose=(1.0, 2.0, 0.0))
    ros = ros_factory(sim)
    cmd = roslibpy.Topic(ros, "/cmd_vel", "geometry_msgs/Twist")
    drive_for(cmd, 0.5, 0.6)
    last_command = time.monotonic()
    assert sim.velocity[0] == pytest.approx(0.5)
    assert wait_until(lambda: sim.velocity[0] == 0.0, 2.0, interval=0.01)
    waited = time.monotonic() - last_command
    assert 0.3 <= waited <= 1.0, f"the chair stopped {waited:.2f} s after the last command, expected ~0.5 s"
    x1 = sim.pose[0]
    assert x1 > 1.15, f"chair did not move forward: x = {x1}"
    time.sleep(0.3)
    assert sim.pose[0] == pytest.approx(x1, abs=1e-9), "chair kept moving after the command timeout"


@pytest.mark.slow
def test_collision_stops_at_wall(sim_factory, ros_factory):
    sim = sim_factory(grid=room_grid(6.0, 4.0, wall_x=3.0), start_pose=(1.5, 2.0, 0.0))
    ros = ros_factory(sim)
    cmd = roslibpy.Topic(ros, "/cmd_vel", "geometry_msgs/Twist")
    deadline = time.monotonic() + 6.0  # ~1.5 s of driving; generous for a loaded machine
    while not sim.bumped and time.monotonic() < deadline:
        cmd.publish(twist(0.8))
        time.sleep(0.1)
    drive_for(cmd, 0.8, 0.3)  # keep pushing into the wall
    x = sim.pose[0]
    assert sim.bumped, f"no collision reported, chair at x = {x}"
    assert x < 3.0 - 0.35 + 0.05, f"chair centre at {x} overlaps the wall at 3.0"
    assert x > 3.0 - 0.35 - 0.15, f"chair stopped too early at {x}"
    assert sim.velocity[0] == 0.0


@pytest.mark.slow
def test_goal_reached(sim_factory, ros_factory):
    grid = room_grid(6.0, 4.0, wall_x=3.0, door=(2.3, 3.6))
    sim = sim_factory(grid=grid, start_pose=(1.5, 1.2, 0.0), limits=DriveLimits(v_max=1.5, w_max=2.5))
    ros = ros_factory(sim)
    goal = roslibpy.Topic(ros, "/move_base_simple/goal", "geometry_msgs/PoseStamped")
    goal.publish(
        roslibpy.Message(
            {
                "header": {"frame_id": "map"},
                "pose": {"position": {"x": 4.5, "y": 1.2, "z": 0.0}, "orientation": {"x": 0, "y": 0, "z": 0, "w": 1}},
            }
        )
    )
    assert wait_until(lambda: sim.goal_status == "reached", 12.0), f"goal status {sim.goal_status}"
    x, y, _ = sim.pose
    assert math.dist((x, y), (4.5, 1.2)) < 0.2


@pytest.mark.slow
def test_goal_through_a_real_door(sim_factory):
    grid = sample_floor()  # the converted sample clinic: 0.9 m doors for a 0.7 m chair
    assert grid is not None
    sim = sim_factory(grid=grid, start_pose=(15.0, 3.0, 0.0), limits=DriveLimits(v_max=1.5, w_max=2.5))
    with connect(sim.url, open_timeout=5) as ws:  # any rosbridge client can send a goal
        goal = {"header": {"frame_id": "map"}, "pose": {"position": {"x": 16.0, "y": 7.5, "z": 0.0}}}
        ws.send(json.dumps({"op": "publish", "topic": "/move_base_simple/goal", "msg": goal}))
        assert wait_until(lambda: sim.goal_status == "reached", 15.0), f"goal status {sim.goal_status}"
    assert math.dist(sim.pose[:2], (16.0, 7.5)) < 0.2


def test_manual_command_cancels_a_goal_topic_followers_goal(sim_factory, ros_factory):
    """A chair with goal topics only (a simple follower, no Nav2 / move_base) yields to /cmd_vel;
    with Nav2 or move_base it does not (tests/sim/test_sim_foreign_cmd_vel.py)."""
    sim = sim_factory(grid=room_grid(8.0, 4.0), start_pose=(1.0, 2.0, 0.0), nav_actions=False)
    ros = ros_factory(sim)
    goal = roslibpy.Topic(ros, "/move_base_simple/goal", "geometry_msgs/PoseStamped")
    goal.publish(roslibpy.Message({"pose": {"position": {"x": 7.0, "y": 2.0, "z": 0.0}}}))
    assert wait_until(lambda: sim.goal_status == "active", 3.0)
    roslibpy.Topic(ros, "/cmd_vel", "geometry_msgs/Twist").publish(twist(0.0))
    assert wait_until(lambda: sim.goal_status == "cancelled", 3.0)


@pytest.mark.slow
def test_patrol_moves_on_its_own(sim_factory):
    sim = sim_factory(patrol=True, limits=DriveLimits(v_max=1.2))
    start = sim.pose
    assert wait_until(lambda: math.dist(sim.pose[:2], start[:2]) > 0.5, 6.0)


def test_tf_tree(sim_chair, ros_factory):
    ros = ros_factory(sim_chair)
    tfs = Collector()
    roslibpy.Topic(ros, "/tf", "tf2_msgs/TFMessage").subscribe(tfs)
    assert wait_until(lambda: len(tfs) > 0, 3.0)
    pairs = {(t["header"]["frame_id"], t["child_frame_id"]) for t in tfs.last()["transforms"]}
    assert pairs == {("map", "odom"), ("odom", "base_link")}


@pytest.mark.slow
def test_pause_resume_and_restart_same_port(sim_chair, ros_factory):
    ros = ros_factory(sim_chair)
    odom = Collector()
    roslibpy.Topic(ros, "/odom", "nav_msgs/Odometry").subscribe(odom)
    assert wait_until(lambda: len(odom) > 5, 3.0)
    sim_chair.pause()
    time.sleep(0.1)
    paused_count = len(odom)
    time.sleep(0.4)
    assert len(odom) == paused_count, "messages kept coming while paused"
    assert ros.is_connected
    sim_chair.resume()
    assert wait_until(lambda: len(odom) > paused_count + 5, 3.0)

    port = sim_chair.port
    sim_chair.stop()
    assert wait_until(lambda: not ros.is_connected, 3.0)
    sim_chair.start()
    assert sim_chair.port == port
    ros2 = ros_factory(port)
    assert ros2.get_topics()
