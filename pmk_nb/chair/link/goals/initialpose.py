"""Setting the chair's initial pose: ``/initialpose`` (``geometry_msgs/PoseWithCovarianceStamped``).

AMCL (ROS 1 and Nav2) re-localises from this message after a map change. It is built as RViz's
"2D Pose Estimate" builds it, so AMCL treats it the same: frame ``map``, variance 0.25 m^2 in x and
y (0.5 m standard deviation) and 0.0685 rad^2 in yaw (about 15 degrees), every other entry zero;
the header stamp in the chair's ROS version's spelling (a wrong spelling is dropped by the bridge,
silently). Like every link publisher it sends nothing when not connected.
"""

from __future__ import annotations

import math
import time
from typing import TYPE_CHECKING, Any

import roslibpy

from pmk_nb.wire import make_stamp, quaternion_from_yaw

if TYPE_CHECKING:
    from pmk_nb.chair.link.transport.publish import Publishers

TOPIC = "/initialpose"
TYPE = "geometry_msgs/PoseWithCovarianceStamped"
VARIANCE_XY = 0.25  # m^2, as RViz
VARIANCE_YAW = 0.06853891945200942  # rad^2, as RViz: (pi / 12)^2


def initial_pose_message(
    x: float, y: float, yaw: float, ros_version: int, stamp: float, frame: str = "map"
) -> dict[str, Any]:
    """The message for a pose (x, y in metres, yaw in radians) in ``frame``; ValueError if not finite."""
    if ros_version not in (1, 2):
        raise ValueError(f"ros_version must be 1 or 2, got {ros_version!r}")
    if not all(math.isfinite(float(v)) for v in (x, y, yaw)):
        raise ValueError(f"an initial pose must be finite, got ({x}, {y}, {yaw})")
    covariance = [0.0] * 36
    covariance[0] = covariance[7] = VARIANCE_XY  # x, y
    covariance[35] = VARIANCE_YAW  # rotation about z
    header: dict[str, Any] = {"frame_id": frame, "stamp": make_stamp(stamp, ros_version)}
    if ros_version == 1:
        header["seq"] = 0
    pose = {"position": {"x": float(x), "y": float(y), "z": 0.0}, "orientation": quaternion_from_yaw(float(yaw))}
    return {"header": header, "pose": {"pose": pose, "covariance": covariance}}


def publish_initial_pose(
    publishers: Publishers,
    ros: roslibpy.Ros | None,
    ros_version: int | None,
    pose: tuple[float, float, float],
    frame: str = "map",
    topic: str = TOPIC,
) -> bool:
    """Publish ``pose`` (x, y, yaw) on ``topic``; False (nothing sent) when not connected or while
    the ROS version is unknown."""
    if ros_version not in (1, 2):
        return False
    message = initial_pose_message(*pose, ros_version, time.time(), frame)
    advertised = publishers.topic(ros, topic, TYPE, ros_version)
    if advertised is None:
        return False
    advertised.publish(roslibpy.Message(message))
    return True
