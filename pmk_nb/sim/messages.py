"""ROS message dicts as rosbridge sends them, for ROS 1 and ROS 2.

The two ROS versions differ in exactly the places a client has to care about: type names
(``nav_msgs/Odometry`` vs ``nav_msgs/msg/Odometry``), stamps (``secs/nsecs`` vs ``sec/nanosec``)
and ``Header.seq`` (ROS 1 only). Everything else is built once here so the simulator, the map
server and rosapi agree on names.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from pmk_nb.sim.jsonfast import RawJSON, int8_array_json
from pmk_nb.wire import make_stamp, normalise_type, pose_msg, quaternion_from_yaw, vec3

if TYPE_CHECKING:
    from pmk_nb.grid import OccupancyGrid

RosVersion = Literal["ros1", "ros2"]
ROS_VERSIONS: tuple[str, ...] = ("ros1", "ros2")

_ZERO36 = [0.0] * 36


@dataclass(frozen=True)
class Names:
    """Type names and stamp layout for one ROS version."""

    ros: RosVersion

    @property
    def ros_version(self) -> int:
        return 1 if self.ros == "ros1" else 2

    def msg(self, pkg: str, name: str) -> str:
        return f"{pkg}/{name}" if self.ros == "ros1" else f"{pkg}/msg/{name}"

    def srv(self, pkg: str, name: str) -> str:
        return f"{pkg}/{name}" if self.ros == "ros1" else f"{pkg}/srv/{name}"

    def stamp(self, t: float) -> dict[str, int]:
        return make_stamp(t, self.ros_version)

    def header(self, frame_id: str, t: float, seq: int = 0) -> dict[str, Any]:
        h: dict[str, Any] = {"stamp": self.stamp(t), "frame_id": frame_id}
        if self.ros == "ros1":
            h = {"seq": seq, **h}
        return h

    @property
    def plan_topic(self) -> str:
        """Where the navigation stack publishes its global plan (nav_msgs/Path): Nav2's planner
        server on ``/plan``; move_base's default global planner (navfn) on its private topic."""
        return "/move_base/NavfnROS/plan" if self.ros == "ros1" else "/plan"

    # -- builders -----------------------------------------------------------------------------

    def path(self, points: list[tuple[float, float]], yaw: float | None, t: float, seq: int = 0) -> dict[str, Any]:
        """A nav_msgs/Path in the map frame: each pose faces the next point, the last the goal's yaw."""
        poses: list[dict[str, Any]] = []
        for i, (x, y) in enumerate(points):
            if i + 1 < len(points):
                heading = math.atan2(points[i + 1][1] - y, points[i + 1][0] - x)
            else:
                heading = yaw if yaw is not None else (poses[-1]["_yaw"] if poses else 0.0)
            poses.append({"header": self.header("map", t, seq), "pose": pose_msg(x, y, heading), "_yaw": heading})
        for p in poses:
            del p["_yaw"]
        return {"header": self.header("map", t, seq), "poses": poses}

    def odometry(self, pose: tuple[float, float, float], v: float, w: float, t: float, seq: int) -> dict[str, Any]:
        x, y, th = pose
        return {
            "header": self.header("odom", t, seq),
            "child_frame_id": "base_link",
            "pose": {"pose": pose_msg(x, y, th), "covariance": _ZERO36},
            "twist": {
                "twist": {"linear": vec3(v, 0.0, 0.0), "angular": vec3(0.0, 0.0, w)},
                "covariance": _ZERO36,
            },
        }

    def laser_scan(
        self,
        ranges: np.ndarray,
        angle_min: float,
        angle_increment: float,
        range_min: float,
        range_max: float,
        scan_time: float,
        t: float,
        seq: int,
    ) -> dict[str, Any]:
        n = int(ranges.shape[0])
        return {
            "header": self.header("base_link", t, seq),
            "angle_min": angle_min,
            "angle_max": angle_min + angle_increment * (n - 1),
            "angle_increment": angle_increment,
            "time_increment": 0.0,
            "scan_time": scan_time,
            "range_min": range_min,
            "range_max": range_max,
            "ranges": json_ranges(ranges),
            "intensities": [],
        }

    def transform(self, parent: str, child: str, pose: tuple[float, float, float], t: float) -> dict[str, Any]:
        x, y, th = pose
        return {
            "header": self.header(parent, t),
            "child_frame_id": child,
            "transform": {"translation": vec3(x, y, 0.0), "rotation": quaternion_from_yaw(th)},
        }

    def tf_message(self, transforms: list[dict[str, Any]]) -> dict[str, Any]:
        return {"transforms": transforms}

    def map_metadata(self, grid: OccupancyGrid, load_time: float) -> dict[str, Any]:
        ox, oy, oth = grid.origin
        return {
            "map_load_time": self.stamp(load_time),
            "resolution": grid.resolution,
            "width": grid.width,
            "height": grid.height,
            "origin": pose_msg(ox, oy, oth),
        }

    def occupancy_grid(self, grid: OccupancyGrid, load_time: float, t: float, seq: int = 0) -> dict[str, Any]:
        """The message with ``data`` pre-encoded (:class:`RawJSON`): encode it with ``jsonfast.dumps``.

        Heavy for big maps (about 0.2 s per 16 M cells): call it off the loop.
        """
        return {
            "header": self.header(grid.frame_id or "map", t, seq),
            "info": self.map_metadata(grid, load_time),
            "data": RawJSON(int8_array_json(grid.data)),
        }

    def empty_grid(self, t: float) -> dict[str, Any]:
        return {
            "header": self.header("", t),
            "info": {
                "map_load_time": self.stamp(0.0),
                "resolution": 0.0,
                "width": 0,
                "height": 0,
                "origin": pose_msg(0.0, 0.0, 0.0),
            },
            "data": [],
        }


# Field names of the message types clients may publish to the simulator. A published message with a
# field not listed here does not conform to the topic's type and is refused (rosbridge does the same).
_VEC3 = {"x": None, "y": None, "z": None}
_QUAT = {"x": None, "y": None, "z": None, "w": None}
_STAMP = {"secs": None, "nsecs": None, "sec": None, "nanosec": None}
_HEADER = {"seq": None, "stamp": _STAMP, "frame_id": None}
_POSE = {"position": _VEC3, "orientation": _QUAT}
SCHEMAS: dict[str, dict[str, Any]] = {
    "geometry_msgs/Twist": {"linear": _VEC3, "angular": _VEC3},
    "geometry_msgs/PoseStamped": {"header": _HEADER, "pose": _POSE},
    "geometry_msgs/PoseWithCovarianceStamped": {
        "header": _HEADER,
        "pose": {"pose": _POSE, "covariance": None},
    },
    "std_msgs/String": {"data": None},
}


def conformance_error(type_name: str, msg: Any) -> str | None:
    """Why ``msg`` does not fit ``type_name``, or None (unknown types are accepted as they are)."""
    schema = SCHEMAS.get(normalise_type(type_name))
    if schema is None:
        return None if isinstance(msg, dict) else "msg must be a JSON object"
    return _check(schema, msg, "msg")


def _check(schema: dict[str, Any], value: Any, where: str) -> str | None:
    if not isinstance(value, dict):
        return f"{where} must be a JSON object"
    for key, item in value.items():
        if key not in schema:
            return f"{where} has no field {key!r}"
        sub = schema[key]
        if isinstance(sub, dict):
            err = _check(sub, item, f"{where}.{key}")
            if err:
                return err
        elif sub is None and isinstance(item, dict):
            return f"{where}.{key} must be a value, not an object"
        elif key in ("x", "y", "z", "w") and not isinstance(item, int | float):
            return f"{where}.{key} must be a number"
    return None


def json_ranges(ranges: np.ndarray) -> list[float | None]:
    """Ranges as a JSON list: NaN and ±inf become ``null``, as every rosbridge server sends them."""
    values = ranges.astype(np.float64).round(4)
    finite = np.isfinite(values)
    out: list[float | None] = values.tolist()
    if not finite.all():
        for i in np.flatnonzero(~finite):
            out[i] = None
    return out
