"""Real-stack tier: the simulated chair as an rclpy node behind a real rosbridge server, seen by roslibpy."""

from __future__ import annotations

import math
import time

import roslibpy

from tests import fixtures_ros2
from tests.fixtures_ros2 import RealChair, close_client
from tests.fixtures_sim import room_grid, write_test_map
from tests.helpers import wait_until

# the real-stack fixtures (not in the root conftest's plugins)
ros2_stack, real_chair = fixtures_ros2.ros2_stack, fixtures_ros2.real_chair


def _latest(ros: roslibpy.Ros, topic: str, msg_type: str, **kw: object) -> list[dict]:
    got: list[dict] = []
    roslibpy.Topic(ros, topic, msg_type, **kw).subscribe(got.append)
    return got


def test_sim_node_streams_and_drives(real_chair: RealChair) -> None:
    write_test_map(room_grid(8.0, 6.0), real_chair.maps, "room")
    real_chair.start_bridge()
    real_chair.start_sim_node("--map", "room", "--laser-offset", "0.3,-0.1,0.5")
    ros = real_chair.client()
    try:
        odom = _latest(ros, "/odom", "nav_msgs/msg/Odometry")
        scans = _latest(ros, "/scan", "sensor_msgs/msg/LaserScan")
        tf = _latest(ros, "/tf", "tf2_msgs/msg/TFMessage", queue_length=10)
        static = _latest(ros, "/tf_static", "tf2_msgs/msg/TFMessage")
        wait_until(lambda: odom and scans and tf and static, 20, "odom, scan, tf and tf_static through the bridge")
        laser = static[0]["transforms"][0]
        assert (laser["header"]["frame_id"], laser["child_frame_id"]) == ("base_link", "laser")
        assert math.isclose(laser["transform"]["translation"]["x"], 0.3, abs_tol=1e-6)
        assert math.isclose(
            2 * math.atan2(laser["transform"]["rotation"]["z"], laser["transform"]["rotation"]["w"]), 0.5
        )
        assert scans[-1]["header"]["frame_id"] == "laser" and len(scans[-1]["ranges"]) == 720
        frames = {(t["header"]["frame_id"], t["child_frame_id"]) for m in tf for t in m["transforms"]}
        assert frames == {("map", "odom"), ("odom", "base_link")}

        start = odom[-1]["pose"]["pose"]["position"]["x"]
        cmd = roslibpy.Topic(ros, "/cmd_vel", "geometry_msgs/msg/Twist")
        for _ in range(10):  # 1 s of 0.4 m/s, then silence: the 0.5 s timeout stops the chair
            cmd.publish({"linear": {"x": 0.4, "y": 0.0, "z": 0.0}, "angular": {"x": 0.0, "y": 0.0, "z": 0.0}})
            time.sleep(0.1)
        time.sleep(1.0)
        stopped = odom[-1]
        assert stopped["twist"]["twist"]["linear"]["x"] == 0.0
        moved = stopped["pose"]["pose"]["position"]["x"] - start
        assert 0.2 < moved < 0.8, moved
    finally:
        close_client(ros)
