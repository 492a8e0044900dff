"""The chair side: ROS nodes a lab installs on its chair, and the wheels stack that runs them here.

- ``mapserver`` (+ ``mapstore``): the PMK map server (``pmk robot map-server``): ``/map`` (transient
  local), ``/map_metadata``, ``MapUpdate``, Nav2 ``LoadMap`` and a header-only ``MapInfo``.
- ``simnode``: the simulated chair's physics, laser and tf behind real rclpy topics (``pmk robot sim-node``).
- ``goalwatch`` + ``watchdog_ros2`` / ``watchdog_ros1``: the goal watchdog (``pmk robot goal-watchdog``),
  which cancels navigation goals when the dashboard's goal heartbeat falls silent.
- ``wheels``: a ROS 2 Jazzy stack from wheels (venv, interfaces built with cmake, rosbridge server).

rclpy/rospy are imported lazily, inside the nodes: the rest of the package never needs ROS.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from pmk_nb.lazyface import lazy_face

if TYPE_CHECKING:
    from pmk_nb.robot.mapstore import DEFAULT_MAPS
    from pmk_nb.robot.watchdog_ros1 import CANCEL_TOPIC
    from pmk_nb.robot.watchdog_ros2 import ACTIONS

_WHERE = {
    "DEFAULT_MAPS": "mapstore",
    "CANCEL_TOPIC": "watchdog_ros1",
    "ACTIONS": "watchdog_ros2",
}

__all__ = [
    "ACTIONS",
    "CANCEL_TOPIC",
    "DEFAULT_MAPS",
    "mapserver",
    "ros1_mapserver",
    "simnode",
    "watchdog_ros2",
]


__getattr__, __dir__ = lazy_face(__name__, _WHERE, __all__)
