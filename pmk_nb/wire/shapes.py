"""Message shapes as rosbridge carries them, where ROS 1 and ROS 2 differ: stamps (``secs/nsecs`` vs
``sec/nanosec``) and type spellings (``nav_msgs/Odometry`` vs ``nav_msgs/msg/Odometry``); and the
pose dict both write. The link reads and writes these, the simulator writes and checks them.
"""

from __future__ import annotations

import math
from typing import Any

from pmk_nb.wire.angles import quaternion_from_yaw

#: The middle word of a ROS 2 type spelling.
ROS2_KINDS = ("msg", "srv", "action")


def make_stamp(t: float, ros_version: int | None) -> dict[str, int]:
    """A header stamp for time ``t`` (seconds) in the spelling of the given ROS version (ROS 1's when unknown)."""
    sec = math.floor(t)
    nsec = min(round((t - sec) * 1e9), 999_999_999)
    if ros_version == 2:
        return {"sec": sec, "nanosec": nsec}
    return {"secs": sec, "nsecs": nsec}


def stamp_to_sec(stamp: Any) -> float | None:
    """Seconds from a ROS 1 (``secs/nsecs``) or ROS 2 (``sec/nanosec``) stamp dict, else None."""
    if not isinstance(stamp, dict):
        return None
    if "sec" in stamp:
        return float(stamp["sec"]) + float(stamp.get("nanosec", 0)) * 1e-9
    if "secs" in stamp:
        return float(stamp["secs"]) + float(stamp.get("nsecs", 0)) * 1e-9
    return None


def stamp_ros_version(stamp: Any) -> int | None:
    """1 for ``secs/nsecs`` stamps, 2 for ``sec/nanosec``, None when it cannot tell."""
    if isinstance(stamp, dict):
        if "sec" in stamp or "nanosec" in stamp:
            return 2
        if "secs" in stamp or "nsecs" in stamp:
            return 1
    return None


def type_ros_version(type_name: str) -> int:
    """2 for ``pkg/msg/Type`` / ``pkg/srv/Type`` / ``pkg/action/Type`` spellings, 1 for ``pkg/Type``."""
    parts = type_name.strip("/").split("/")
    return 2 if len(parts) == 3 and parts[1] in ROS2_KINDS else 1


def type_spellings(type_name: str, kind: str = "msg") -> list[str]:
    """Both spellings of a type, the given one first: ``nav_msgs/Odometry`` <-> ``nav_msgs/msg/Odometry``."""
    parts = type_name.strip("/").split("/")
    if len(parts) == 3:
        other = f"{parts[0]}/{parts[2]}"
    elif len(parts) == 2:
        other = f"{parts[0]}/{kind}/{parts[1]}"
    else:
        return [type_name]
    return [type_name, other]


def normalise_type(type_name: str) -> str:
    """The ROS 1 spelling (``pkg/Type``), for comparing types across ROS versions: ROS 2 rosbridge
    accepts both spellings, so two names of one type compare equal in this form."""
    parts = type_name.strip().strip("/").split("/")
    return f"{parts[0]}/{parts[2]}" if len(parts) == 3 and parts[1] in ROS2_KINDS else "/".join(parts)


def spell_type(type_name: str, ros_version: int | None, kind: str = "msg") -> str:
    """The spelling a server of ``ros_version`` expects (ROS 1 spelling when unknown: ROS 2
    rosbridge accepts it too, ROS 1 rosbridge accepts nothing else).
    """
    if ros_version == 2:
        return type_name if type_ros_version(type_name) == 2 else type_spellings(type_name, kind)[1]
    return normalise_type(type_name)


def is_type_name(type_name: str) -> bool:
    """``pkg/Type`` or ``pkg/kind/Type`` with word characters only: what rosbridge accepts as a type."""
    parts = type_name.split("/")
    return len(parts) in (2, 3) and all(p and p.replace("_", "").isalnum() for p in parts)


def vec3(x: float, y: float, z: float) -> dict[str, float]:
    """A ``geometry_msgs/Vector3`` (or ``Point``) dict."""
    return {"x": x, "y": y, "z": z}


def pose_msg(x: float, y: float, yaw: float) -> dict[str, Any]:
    """A planar ``geometry_msgs/Pose`` dict."""
    return {"position": vec3(x, y, 0.0), "orientation": quaternion_from_yaw(yaw)}
