"""What a map server answers to a reload (``nav_msgs/LoadMap``, ``nav2_msgs/srv/LoadMap``): the result
codes and how a failed load becomes one. The simulator's map server and the chair's PMK map server
(rclpy and rospy) answer alike; the link reads the codes back (``chair/link/query/reload``).

Nav2 answers each failure with its own code; ROS 1's map_server knows only success and
:data:`UNDEFINED_FAILURE` (:func:`ros1_result`).
"""

from __future__ import annotations

from pmk_nb.errors import INVALID_MAP_DATA, INVALID_MAP_METADATA, MAP_DOES_NOT_EXIST, MapLoadError

__all__ = [
    "INVALID_MAP_DATA",
    "INVALID_MAP_METADATA",
    "LOAD_SUCCESS",
    "MAP_DOES_NOT_EXIST",
    "UNDEFINED_FAILURE",
    "LoadAnswer",
    "empty_request",
    "load_failure",
    "ros1_result",
]

LOAD_SUCCESS = 0
#: Nav2's "undefined failure", and ROS 1 map_server's only failure code.
UNDEFINED_FAILURE = 255

#: (result code, message for the log)
LoadAnswer = tuple[int, str]


def empty_request(request: str) -> LoadAnswer | None:
    """The answer to a request that names no map (empty or blank), else None."""
    return (MAP_DOES_NOT_EXIST, "empty map url") if not request or not request.strip() else None


def load_failure(err: Exception) -> LoadAnswer:
    """A failed load's answer: a :class:`MapLoadError` carries its Nav2 code; anything else is undefined."""
    if isinstance(err, MapLoadError):
        return err.code, str(err)
    return UNDEFINED_FAILURE, f"{type(err).__name__}: {err}"


def ros1_result(code: int) -> int:
    """The ROS 1 ``LoadMap`` result for a Nav2 code: success stays 0, every failure is 255."""
    return LOAD_SUCCESS if code == LOAD_SUCCESS else UNDEFINED_FAILURE
