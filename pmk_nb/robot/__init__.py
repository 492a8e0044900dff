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

import importlib
from typing import TYPE_CHECKING, Any

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


def __getattr__(name: str) -> Any:
    """The face is lazy: a name loads only its own module (no paramiko, roslibpy or ROS for one name)."""
    if name not in _WHERE:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(f"{__name__}.{_WHERE[name]}"), name)
    globals()[name] = value  # once is enough
    return value


def __dir__() -> list[str]:
    return sorted({*globals(), *__all__})
