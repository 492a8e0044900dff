"""Real-stack tier (issue 29): ``ChairLink.set_initial_pose`` reaches a real rclpy node as AMCL would
receive it, and the map watch behind Home's own-map view gets the real map server's transient-local /map."""

from __future__ import annotations

import json
import math
import time

from pmk_nb.chair.link import ChairLink
from tests import fixtures_ros2
from tests.fixtures_ros2 import RealChair
from tests.helpers import wait_until

ros2_stack, real_chair = fixtures_ros2.ros2_stack, fixtures_ros2.real_chair

# AMCL's side, as small as it gets: print the first /initialpose received as one JSON line, then exit
LISTENER = r"""
import json, math, sys
import rclpy
from geometry_msgs.msg import PoseWithCovarianceStamped

rclpy.init()
node = rclpy.create_node("initialpose_listener")
got = []

def on_pose(msg):
    q = msg.pose.pose.orientation
    yaw = math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))
    got.append({"frame": msg.header.frame_id, "x": msg.pose.pose.position.x, "y": msg.pose.pose.position.y,
                "yaw": yaw, "cov": list(msg.pose.covariance), "sec": msg.header.stamp.sec})

node.create_subscription(PoseWithCovarianceStamped, "/initialpose", on_pose, 10)
print("LISTENER READY", flush=True)
while rclpy.ok() and not got:
    rclpy.spin_once(node, timeout_sec=0.1)
print("GOT " + json.dumps(got[0]), flush=True)
node.destroy_node()
rclpy.shutdown()
"""


def test_initial_pose_reaches_a_real_rclpy_subscriber(real_chair: RealChair) -> None:
    script = real_chair.tmp / "initialpose_listener.py"
    script.write_text(LISTENER)
    real_chair.start_bridge(rosapi=True)  # rosapi tells the link the ROS version at connect
    listener = real_chair._spawn(
        "listener", [str(real_chair.stack.python), str(script)], real_chair.stack.node_env(real_chair.domain), None
    )
    wait_until(lambda: "LISTENER READY" in listener.tail(), 30, "the rclpy listener to start")
    link = ChairLink("127.0.0.1", real_chair.port)
    try:
        link.connect(10)
        wait_until(lambda: link.ros_version == 2, 15, "the link to learn ROS 2 from rosapi")
        sent_at = [-math.inf]

        def received() -> bool:
            # resent every second until DDS has matched the bridge's publisher with the listener
            if time.monotonic() - sent_at[0] > 1.0:
                assert link.set_initial_pose(1.5, -0.5, math.pi / 2) is True
                sent_at[0] = time.monotonic()
            return "GOT " in listener.tail()

        wait_until(received, 40, "/initialpose at the rclpy listener")
    finally:
        link.close()
    line = next(x for x in listener.tail(4000).splitlines() if x.startswith("GOT "))
    msg = json.loads(line[4:])
    assert msg["frame"] == "map" and abs(msg["sec"] - time.time()) < 120
    assert (msg["x"], msg["y"]) == (1.5, -0.5) and abs(msg["yaw"] - math.pi / 2) < 1e-6
    cov = msg["cov"]
    assert cov[0] == cov[7] == 0.25 and abs(cov[35] - 0.0685) < 1e-3 and sum(1 for c in cov if c) == 3


def test_the_map_watch_gets_the_transient_local_map_and_each_reload(real_chair: RealChair) -> None:
    """Home's own-map source on a real ROS 2 map server: /map is transient local (a late subscriber
    gets it at once), and a reload publishes the new one to the same subscription."""
    from pmk_nb.rosmap import read_map
    from tests.fixtures_sim import room_grid, write_test_map

    room = write_test_map(room_grid(8.0, 6.0), real_chair.maps, "room")
    small = write_test_map(room_grid(3.0, 2.0), real_chair.maps, "small")
    real_chair.start_bridge()
    real_chair.start_map_server("room")
    real_chair.wait_service("/map_server/map_info", "map_server_pmk/srv/MapInfo")
    link = ChairLink("127.0.0.1", real_chair.port)
    try:
        link.connect(10)
        link.watch_map(True)
        wait_until(lambda: link.latest_map()[0] >= 1, 30, "the latched /map")
        grid = link.latest_map()[1]
        assert grid is not None and (grid.width, grid.height) == (read_map(room).width, read_map(room).height)
        assert (grid.data == read_map(room).data).mean() > 0.98
        link.reload_map(str(small))
        wait_until(
            lambda: (g := link.latest_map()[1]) is not None and g.width == read_map(small).width, 30, "the reload"
        )
    finally:
        link.close()


def test_the_sent_map_is_named_from_map_info_without_downloading_map(real_chair: RealChair) -> None:
    """Big maps: the PMK map server's MapInfo SHA-256 says the chair publishes the map sent from here,
    so Home shows that map's own file under its name and never subscribes /map; another map loaded
    on the chair is then watched on /map and shown as the chair's own."""
    from pmk_nb.rosmap import read_map
    from pmk_nb.ui.home.own_map import CHAIRS_MAP, OwnMap
    from tests.fixtures_sim import room_grid, write_test_map

    room = write_test_map(room_grid(8.0, 6.0), real_chair.maps, "room")
    small = write_test_map(room_grid(3.0, 2.0), real_chair.maps, "small")
    real_chair.start_bridge()
    real_chair.start_map_server("room")
    real_chair.wait_service("/map_server/map_info", "map_server_pmk/srv/MapInfo")
    link = ChairLink("127.0.0.1", real_chair.port)
    own = OwnMap()
    try:
        link.connect(10)
        local = read_map(room)
        own.set_local("room", local, room)
        own.attach(link)
        first = wait_until(own.take, 30, "the sent map named from MapInfo")
        assert first.is_sent_map and first.name == "room" and first.grid is local
        time.sleep(1.0)
        assert not link.watching_map and link.latest_map() == (0, None)  # no /map download
        link.reload_map(str(small))
        chair = wait_until(own.take, 30, "the chair's other map, from /map")
        assert link.watching_map and not chair.is_sent_map and chair.name == CHAIRS_MAP
        assert chair.grid.width == read_map(small).width
    finally:
        own.attach(None)
        link.close()
