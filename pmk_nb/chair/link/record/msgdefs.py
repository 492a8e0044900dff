"""The ROS 2 message definitions a recording writes into its MCAP schemas.

Each schema is the full concatenated definition with its dependencies, in the form ``ros2 bag`` writes
(``ros2msg`` schema encoding): Foxglove, ``ros2 bag`` and ``rosbags`` read a recording without the
message packages installed. Each message's own fields are written once (:data:`FIELDS`, from the rosbags
type store, ROS 2 Humble) and :func:`concatenated` adds its dependencies depth-first, each once, as
``ros2 bag`` does; bundled so the dashboard needs no ROS installation to record.
"""

from __future__ import annotations

import re
from collections.abc import Mapping

SEPARATOR = "=" * 80 + "\n"

#: each message's own fields (package/Name, as the definitions spell their field types)
FIELDS: dict[str, str] = {
    "nav_msgs/Odometry": (
        "std_msgs/Header header\n"
        "string child_frame_id\n"
        "geometry_msgs/PoseWithCovariance pose\n"
        "geometry_msgs/TwistWithCovariance twist\n"
    ),
    "std_msgs/Header": ("builtin_interfaces/Time stamp\nstring frame_id\n"),
    "builtin_interfaces/Time": ("int32 sec\nuint32 nanosec\n"),
    "geometry_msgs/PoseWithCovariance": ("geometry_msgs/Pose pose\nfloat64[36] covariance\n"),
    "geometry_msgs/Pose": ("geometry_msgs/Point position\ngeometry_msgs/Quaternion orientation\n"),
    "geometry_msgs/Point": ("float64 x\nfloat64 y\nfloat64 z\n"),
    "geometry_msgs/Quaternion": ("float64 x\nfloat64 y\nfloat64 z\nfloat64 w\n"),
    "geometry_msgs/TwistWithCovariance": ("geometry_msgs/Twist twist\nfloat64[36] covariance\n"),
    "geometry_msgs/Twist": ("geometry_msgs/Vector3 linear\ngeometry_msgs/Vector3 angular\n"),
    "geometry_msgs/Vector3": ("float64 x\nfloat64 y\nfloat64 z\n"),
    "sensor_msgs/LaserScan": (
        "std_msgs/Header header\n"
        "float32 angle_min\n"
        "float32 angle_max\n"
        "float32 angle_increment\n"
        "float32 time_increment\n"
        "float32 scan_time\n"
        "float32 range_min\n"
        "float32 range_max\n"
        "float32[] ranges\n"
        "float32[] intensities\n"
    ),
    "geometry_msgs/PoseWithCovarianceStamped": ("std_msgs/Header header\ngeometry_msgs/PoseWithCovariance pose\n"),
    "geometry_msgs/PoseStamped": ("std_msgs/Header header\ngeometry_msgs/Pose pose\n"),
    "tf2_msgs/TFMessage": ("geometry_msgs/TransformStamped[] transforms\n"),
    "geometry_msgs/TransformStamped": (
        "std_msgs/Header header\nstring child_frame_id\ngeometry_msgs/Transform transform\n"
    ),
    "geometry_msgs/Transform": ("geometry_msgs/Vector3 translation\ngeometry_msgs/Quaternion rotation\n"),
    "nav_msgs/OccupancyGrid": ("std_msgs/Header header\nnav_msgs/MapMetaData info\nint8[] data\n"),
    "nav_msgs/MapMetaData": (
        "builtin_interfaces/Time map_load_time\n"
        "float32 resolution\n"
        "uint32 width\n"
        "uint32 height\n"
        "geometry_msgs/Pose origin\n"
    ),
    "nav_msgs/Path": ("std_msgs/Header header\ngeometry_msgs/PoseStamped[] poses\n"),
    "geometry_msgs/TwistStamped": ("std_msgs/Header header\ngeometry_msgs/Twist twist\n"),
    "std_msgs/String": ("string data\n"),
}


def _dependencies(fields: str) -> list[str]:
    """The message types ``fields`` names (``pkg/Name`` field types, arrays included), in order."""
    found = []
    for line in fields.splitlines():
        kind = re.sub(r"\[.*\]$", "", line.split()[0]) if line.strip() else ""
        if "/" in kind:
            found.append(kind)
    return found


def concatenated(short: str, fields: Mapping[str, str] = FIELDS) -> str:
    """``short``'s full definition: its own fields, then each dependency once, depth-first.
    ``fields``: each type's own fields (default: the bundled ones; a bridge's, :mod:`.msgdetails`).

    Raises:
        KeyError: a type ``short`` uses has no entry in ``fields``.
    """
    seen: set[str] = set()
    order: list[str] = []

    def walk(name: str) -> None:
        for dep in _dependencies(fields[name]):
            if dep not in seen:
                seen.add(dep)
                order.append(dep)
                walk(dep)

    walk(short)
    return fields[short] + "".join(f"{SEPARATOR}MSG: {dep}\n{fields[dep]}" for dep in order)


#: the types a recording can write, by their ROS 2 name, with their concatenated definitions
DEFINITIONS: dict[str, str] = {
    name: concatenated(name.replace("/msg/", "/"))
    for name in (
        "nav_msgs/msg/Odometry",
        "sensor_msgs/msg/LaserScan",
        "geometry_msgs/msg/PoseWithCovarianceStamped",
        "geometry_msgs/msg/PoseStamped",
        "tf2_msgs/msg/TFMessage",
        "nav_msgs/msg/OccupancyGrid",
        "nav_msgs/msg/MapMetaData",
        "nav_msgs/msg/Path",
        "geometry_msgs/msg/Twist",
        "geometry_msgs/msg/TwistStamped",
        "std_msgs/msg/String",
    )
}
