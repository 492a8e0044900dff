"""rosapi's ``message_details`` for the simulator's own message types: the type definitions a client reads
to know a message's fields before one arrives (the dashboard's Plots offer every numeric field from them).

Shapes follow rosapi: ``{typedefs: [{type, fieldnames, fieldtypes, fieldarraylen, examples, constnames,
constvalues}]}``, the asked type first, then every nested type once. ROS 1 spells a stamp as the
primitive ``time``; ROS 2 as ``builtin_interfaces/Time`` (``sec``, ``nanosec``). Types the simulator does
not publish answer an empty list, as rosapi does for an unknown type.
"""

from __future__ import annotations

from typing import Any

from pmk_nb.sim.messages import Names, canonical_type

Field = tuple[str, str, int]  # (name, type, array length: -1 variable, 0 not an array, n fixed)

_XYZ: list[Field] = [("x", "float64", 0), ("y", "float64", 0), ("z", "float64", 0)]
FIELDS: dict[str, list[Field]] = {
    "std_msgs/Header": [("stamp", "time", 0), ("frame_id", "string", 0)],
    "geometry_msgs/Point": _XYZ,
    "geometry_msgs/Vector3": _XYZ,
    "geometry_msgs/Point32": [("x", "float32", 0), ("y", "float32", 0), ("z", "float32", 0)],
    "geometry_msgs/Quaternion": [*_XYZ, ("w", "float64", 0)],
    "geometry_msgs/Pose": [("position", "geometry_msgs/Point", 0), ("orientation", "geometry_msgs/Quaternion", 0)],
    "geometry_msgs/PoseWithCovariance": [("pose", "geometry_msgs/Pose", 0), ("covariance", "float64", 36)],
    "geometry_msgs/Twist": [("linear", "geometry_msgs/Vector3", 0), ("angular", "geometry_msgs/Vector3", 0)],
    "geometry_msgs/TwistWithCovariance": [("twist", "geometry_msgs/Twist", 0), ("covariance", "float64", 36)],
    "geometry_msgs/PoseStamped": [("header", "std_msgs/Header", 0), ("pose", "geometry_msgs/Pose", 0)],
    "geometry_msgs/Polygon": [("points", "geometry_msgs/Point32", -1)],
    "geometry_msgs/PolygonStamped": [("header", "std_msgs/Header", 0), ("polygon", "geometry_msgs/Polygon", 0)],
    "nav_msgs/Odometry": [
        ("header", "std_msgs/Header", 0),
        ("child_frame_id", "string", 0),
        ("pose", "geometry_msgs/PoseWithCovariance", 0),
        ("twist", "geometry_msgs/TwistWithCovariance", 0),
    ],
    "sensor_msgs/LaserScan": [
        ("header", "std_msgs/Header", 0),
        *((name, "float32", 0) for name in ("angle_min", "angle_max", "angle_increment", "time_increment")),
        *((name, "float32", 0) for name in ("scan_time", "range_min", "range_max")),
        ("ranges", "float32", -1),
        ("intensities", "float32", -1),
    ],
    "nav_msgs/Path": [("header", "std_msgs/Header", 0), ("poses", "geometry_msgs/PoseStamped", -1)],
    "nav_msgs/MapMetaData": [
        ("map_load_time", "time", 0),
        ("resolution", "float32", 0),
        ("width", "uint32", 0),
        ("height", "uint32", 0),
        ("origin", "geometry_msgs/Pose", 0),
    ],
    "nav_msgs/OccupancyGrid": [
        ("header", "std_msgs/Header", 0),
        ("info", "nav_msgs/MapMetaData", 0),
        ("data", "int8", -1),
    ],
    "std_msgs/String": [("data", "string", 0)],
}
ROS2_TIME = "builtin_interfaces/Time"


def typedefs(names: Names, type_name: str) -> list[dict[str, Any]]:
    """The asked type's definition and its nested types' (each once), as rosapi answers them."""
    out: list[dict[str, Any]] = []
    seen: set[str] = set()
    todo = [canonical_type(type_name)]
    while todo:
        name = todo.pop(0)
        if name in seen:
            continue
        seen.add(name)
        if name == ROS2_TIME:
            fields: list[Field] = [("sec", "int32", 0), ("nanosec", "uint32", 0)]
        elif name in FIELDS:
            fields = FIELDS[name]
            if names.ros == "ros2":
                fields = [(n, ROS2_TIME if t == "time" else t, k) for n, t, k in fields]
        else:
            continue
        todo += [t for _n, t, _k in fields if "/" in t]
        out.append(
            {
                "type": name,
                "fieldnames": [n for n, _t, _k in fields],
                "fieldtypes": [t for _n, t, _k in fields],
                # rosapi's spelling: -1 not an array, 0 a variable-length one, n fixed
                "fieldarraylen": [-1 if k == 0 else 0 if k < 0 else k for _n, _t, k in fields],
                "examples": ["{}" if "/" in t else "0" for _n, t, _k in fields],
                "constnames": [],
                "constvalues": [],
            }
        )
    return out
