"""The simulated chair as a ROS 2 node: the simulator's physics, laser and world behind rclpy topics.

Publishes ``/odom`` (nav_msgs/Odometry), ``/scan`` (sensor_msgs/LaserScan, frame ``laser``), ``/tf``
(map->odom identity unless ``map_odom`` is off, odom->base_link) and ``/tf_static`` (base_link->laser,
off centre by default, transient local, as robot_state_publisher does). Takes ``/cmd_vel`` (stops
0.5 s after the last one, like twist_mux and diff_drive_controller) and ``/goal_pose`` (Nav2's
topic: planned on the simulator's grid). Follows ``/map`` so a deployed map is the world the laser sees.
A real rosbridge server then bridges it exactly as on a chair. rclpy is imported here only.
"""

from __future__ import annotations

import math
import threading
from pathlib import Path
from typing import Any

import numpy as np

from pmk_nb.clock import MONOTONIC, Clock
from pmk_nb.grid import OccupancyGrid
from pmk_nb.rosmap import read_map
from pmk_nb.sim import Chair, Laser, World, demo_grid

READY_LINE = "pmk robot sim-node: ready"
Pose = tuple[float, float, float]


def compose(a: Pose, b: Pose) -> Pose:
    """Pose b expressed in a's frame, composed into a's parent frame."""
    c, s = math.cos(a[2]), math.sin(a[2])
    return a[0] + c * b[0] - s * b[1], a[1] + s * b[0] + c * b[1], a[2] + b[2]


def grid_from_msg(msg: Any) -> OccupancyGrid:
    """nav_msgs/OccupancyGrid -> OccupancyGrid (row 0 = bottom, as both store it)."""
    info = msg.info
    data = np.frombuffer(bytes(msg.data), dtype=np.int8).reshape(info.height, info.width).copy()
    q = info.origin.orientation
    yaw = 2.0 * math.atan2(q.z, q.w)
    return OccupancyGrid(
        data=data, resolution=info.resolution, origin=(info.origin.position.x, info.origin.position.y, yaw)
    )


def _fill_tf(t: Any, parent: str, child: str, pose: Pose, stamp: Any) -> Any:
    t.header.frame_id, t.child_frame_id, t.header.stamp = parent, child, stamp
    t.transform.translation.x, t.transform.translation.y = pose[0], pose[1]
    t.transform.rotation.z, t.transform.rotation.w = math.sin(pose[2] / 2.0), math.cos(pose[2] / 2.0)
    return t


class SimState:
    """The chair in its world; every method may be called from any rclpy callback (one lock). ``clock``
    times its physics (the node's timers call :meth:`step`; a ``VirtualClock`` in tests)."""

    def __init__(self, grid: OccupancyGrid, laser_offset: Pose, rays: int = 720, *, clock: Clock = MONOTONIC) -> None:
        self.clock = clock
        self.lock = threading.Lock()
        self.world = World(grid)
        x, y = self.world.open_spot()
        self.chair = Chair(self.world, (x, y, 0.0))
        self.laser = Laser(rays=rays)
        self.laser_offset = laser_offset
        self.last = clock.now()

    def step(self) -> tuple[Pose, float, float]:
        with self.lock:
            now = self.clock.now()
            self.chair.step(now - self.last, now)
            self.last = now
            return self.chair.pose, self.chair.v, self.chair.w

    def scan(self) -> np.ndarray:
        with self.lock:
            world, pose = self.world, compose(self.chair.pose, self.laser_offset)
        return self.laser.cast(world.hit, world.grid.resolution, world.grid.origin[:2], pose)

    def command(self, v: float, w: float) -> None:
        with self.lock:
            self.chair.command(v, w, self.clock.now())

    def goal(self, x: float, y: float, yaw: float | None) -> None:
        with self.lock:
            world, start = self.world, self.chair.pose[:2]
        path = world.plan(start, (x, y))
        with self.lock:
            if world is self.world:
                self.chair.follow(path, yaw)

    def install(self, grid: OccupancyGrid) -> None:
        world = World(grid)
        if not world.has_free:
            return
        with self.lock:
            self.world = self.chair.world = world
            x, y, th = self.chair.pose
            self.chair.teleport((x, y, th))
            if world.blocked_at(x, y):
                spot = world.nearest_free(x, y)
                if spot is not None:
                    self.chair.teleport((spot[0], spot[1], th))


def run(
    maps_dir: Path,
    map_request: str | None,
    *,
    odom_rate: float = 50.0,
    scan_rate: float = 20.0,
    laser_offset: Pose = (0.25, 0.1, 0.0),
    follow_map: bool = True,
    map_odom: bool = True,
    rays: int = 720,
) -> int:
    """Start the node and spin until shut down; prints READY_LINE once its topics exist."""
    import rclpy
    from rclpy.executors import ExternalShutdownException, MultiThreadedExecutor

    if map_request:
        path = Path(map_request) if map_request.startswith("/") else Path(maps_dir).expanduser() / map_request
        grid = read_map(path)
    else:
        grid = demo_grid()
    rclpy.init()
    try:
        node = _build(SimState(grid, laser_offset, rays), odom_rate, scan_rate, follow_map, map_odom)
        executor = MultiThreadedExecutor(num_threads=3)
        executor.add_node(node)
        print(READY_LINE, flush=True)
        executor.spin()
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        rclpy.try_shutdown()
    return 0


def _build(state: SimState, odom_rate: float, scan_rate: float, follow_map: bool, map_odom: bool) -> Any:
    from geometry_msgs.msg import PoseStamped, TransformStamped, Twist
    from nav_msgs.msg import OccupancyGrid as GridMsg
    from nav_msgs.msg import Odometry
    from rclpy.callback_groups import MutuallyExclusiveCallbackGroup
    from rclpy.node import Node
    from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy, qos_profile_sensor_data
    from sensor_msgs.msg import LaserScan
    from tf2_msgs.msg import TFMessage

    latched = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.TRANSIENT_LOCAL)
    node = Node("pmk_sim")
    odom_pub = node.create_publisher(Odometry, "/odom", 10)
    tf_pub = node.create_publisher(TFMessage, "/tf", 100)
    scan_pub = node.create_publisher(LaserScan, "/scan", qos_profile_sensor_data)
    static_pub = node.create_publisher(TFMessage, "/tf_static", latched)

    def static_tick() -> None:
        stamp = node.get_clock().now().to_msg()
        static_pub.publish(TFMessage(transforms=[_fill_tf(TransformStamped(), "base_link", "laser", offset, stamp)]))

    offset = state.laser_offset
    static_tick()
    # again every second: a bridge that subscribed before it discovered this publisher gets a
    # volatile subscription and would never see the one transient-local message
    node.create_timer(1.0, static_tick)

    def odom_tick() -> None:
        pose, v, w = state.step()
        stamp = node.get_clock().now().to_msg()
        odom = Odometry()
        odom.header.frame_id, odom.child_frame_id, odom.header.stamp = "odom", "base_link", stamp
        odom.pose.pose.position.x, odom.pose.pose.position.y = pose[0], pose[1]
        odom.pose.pose.orientation.z, odom.pose.pose.orientation.w = math.sin(pose[2] / 2.0), math.cos(pose[2] / 2.0)
        odom.twist.twist.linear.x, odom.twist.twist.angular.z = v, w
        odom_pub.publish(odom)
        transforms = [_fill_tf(TransformStamped(), "odom", "base_link", pose, stamp)]
        if map_odom:  # a perfect localiser; off when another node (AMCL, a test) publishes map->odom
            transforms.insert(0, _fill_tf(TransformStamped(), "map", "odom", (0.0, 0.0, 0.0), stamp))
        tf_pub.publish(TFMessage(transforms=transforms))

    laser = state.laser

    def scan_tick() -> None:
        ranges = state.scan()
        msg = LaserScan()
        msg.header.frame_id, msg.header.stamp = "laser", node.get_clock().now().to_msg()
        msg.angle_min, msg.angle_increment = float(laser.angle_min), float(laser.angle_increment)
        msg.angle_max = float(laser.angle_min + laser.angle_increment * (laser.rays - 1))
        msg.range_min, msg.range_max, msg.scan_time = float(laser.range_min), float(laser.range_max), 1.0 / scan_rate
        msg.ranges = ranges.astype(np.float32).tolist()
        scan_pub.publish(msg)

    def on_cmd_vel(msg: Any) -> None:
        state.command(float(msg.linear.x), float(msg.angular.z))

    def on_goal(msg: Any) -> None:
        q = msg.pose.orientation
        yaw = 2.0 * math.atan2(q.z, q.w) if (q.z or q.w) else None
        threading.Thread(target=state.goal, args=(msg.pose.position.x, msg.pose.position.y, yaw), daemon=True).start()

    node.create_timer(1.0 / odom_rate, odom_tick, callback_group=MutuallyExclusiveCallbackGroup())
    node.create_timer(1.0 / scan_rate, scan_tick, callback_group=MutuallyExclusiveCallbackGroup())
    node.create_subscription(Twist, "/cmd_vel", on_cmd_vel, 10)
    node.create_subscription(PoseStamped, "/goal_pose", on_goal, 10)
    if follow_map:
        node.create_subscription(GridMsg, "/map", lambda m: state.install(grid_from_msg(m)), latched)
    return node
