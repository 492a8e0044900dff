"""Parse rosbridge JSON messages (ROS 1 and ROS 2 shapes) into small typed records.

Pure functions, no I/O: the link's topic callbacks call them on the I/O thread, so they stay cheap
(one numpy conversion per scan, no Python loop per ray). ROS 1 and ROS 2 differ in stamps
(``secs/nsecs`` vs ``sec/nanosec``) and type spellings (``pkg/Type`` vs ``pkg/msg/Type``); rosbridge
sends NaN/inf floats either as JSON ``NaN``/``Infinity`` literals or as ``null``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from pmk_nb.chair.link.streams import ranges as ranges_mod
from pmk_nb.viewport import normalise_frame
from pmk_nb.wire import stamp_to_sec, yaw_from_quaternion


@dataclass(frozen=True)
class Odometry:
    """Latest odometry: pose in the odometry frame and body velocities.

    ``stamp`` is the message header time in seconds (None if absent); ``received`` is
    ``time.monotonic()`` when the link got it, for ages that do not depend on the chair's clock.
    """

    x: float
    y: float
    theta: float
    v: float
    w: float
    stamp: float | None
    received: float
    frame: str = "odom"
    child_frame: str = "base_link"


@dataclass(frozen=True)
class Pose2D:
    """A planar pose of the chair in ``frame`` (``map`` when known, else ``odom``)."""

    x: float
    y: float
    theta: float
    frame: str
    received: float
    stamp: float | None = None


@dataclass(frozen=True)
class Scan:
    """A laser scan, each ray read as REP 117 says (:mod:`pmk_nb.chair.link.streams.ranges`).

    ``ranges`` is float32 with a value only for hits (NaN elsewhere); ``kinds`` gives each ray's
    meaning (``HIT``, ``NO_RETURN``, ``TOO_CLOSE``, ``INVALID``, ``UNKNOWN``); ``at_max`` marks rays
    that certainly saw nothing up to ``range_max`` (+inf), the only ones a UI may draw as free.
    A JSON ``null`` is UNKNOWN, never free: rosbridge sends NaN, +inf and -inf all as null.
    """

    angle_min: float
    angle_increment: float
    range_min: float
    range_max: float
    ranges: np.ndarray
    at_max: np.ndarray
    received: float
    stamp: float | None = None
    frame: str = "laser"
    kinds: np.ndarray | None = None
    #: The scanner's pose on the chair (base_link <- frame: x, y, yaw), from /tf_static; rays start there.
    mount: tuple[float, float, float] = (0.0, 0.0, 0.0)

    def __post_init__(self) -> None:
        if self.kinds is None:  # built by hand (tests, benchmarks): finite = hit, at_max = no return
            kinds = np.full(self.ranges.shape, ranges_mod.INVALID, dtype=np.uint8)
            kinds[np.isfinite(self.ranges)] = ranges_mod.HIT
            kinds[np.asarray(self.at_max, dtype=bool)[: kinds.size]] = ranges_mod.NO_RETURN
            object.__setattr__(self, "kinds", kinds)

    def angles(self) -> np.ndarray:
        """Angle of every ray in the laser frame (radians)."""
        return (self.angle_min + self.angle_increment * np.arange(self.ranges.size)).astype(np.float32)

    @property
    def blind(self) -> np.ndarray:
        """Rays that say nothing about the world (unknown or invalid): drawn as a grey tick, never free."""
        return np.isin(np.asarray(self.kinds), ranges_mod.BLIND_KINDS)

    @property
    def too_close(self) -> np.ndarray:
        """Rays that report an object closer than ``range_min`` (-inf)."""
        close: np.ndarray = np.asarray(self.kinds) == ranges_mod.TOO_CLOSE
        return close


@dataclass(frozen=True)
class MapInfo:
    """What the chair's map server publishes about its map (``nav_msgs/MapMetaData``)."""

    width: int
    height: int
    resolution: float
    origin: tuple[float, float, float] = (0.0, 0.0, 0.0)


@dataclass(frozen=True)
class TransformStamped2D:
    """One planar transform from a ``tf2_msgs/TFMessage``: ``child`` expressed in ``parent``."""

    parent: str
    child: str
    x: float
    y: float
    theta: float
    stamp: float | None = None


def _f(value: Any) -> float:
    """A float from a JSON number that may be null (rosbridge's NaN/inf)."""
    return float("nan") if value is None else float(value)


def parse_odometry(msg: dict[str, Any], received: float) -> Odometry:
    """``nav_msgs/Odometry`` -> :class:`Odometry` (v = linear.x, w = angular.z of the twist)."""
    header = msg.get("header") or {}
    pose = (msg.get("pose") or {}).get("pose") or {}
    pos = pose.get("position") or {}
    twist = (msg.get("twist") or {}).get("twist") or {}
    return Odometry(
        x=_f(pos.get("x", 0.0)),
        y=_f(pos.get("y", 0.0)),
        theta=yaw_from_quaternion(pose.get("orientation")),
        v=_f((twist.get("linear") or {}).get("x", 0.0)),
        w=_f((twist.get("angular") or {}).get("z", 0.0)),
        stamp=stamp_to_sec(header.get("stamp")),
        received=received,
        frame=normalise_frame(header.get("frame_id") or "odom"),
        child_frame=normalise_frame(msg.get("child_frame_id") or "base_link"),
    )


def parse_pose(msg: dict[str, Any], received: float) -> Pose2D:
    """``PoseWithCovarianceStamped`` (pose.pose) or ``PoseStamped`` (pose) -> :class:`Pose2D`."""
    header = msg.get("header") or {}
    pose = msg.get("pose") or {}
    if "pose" in pose:  # PoseWithCovarianceStamped nests pose + covariance
        pose = pose["pose"] or {}
    pos = pose.get("position") or {}
    return Pose2D(
        x=_f(pos.get("x", 0.0)),
        y=_f(pos.get("y", 0.0)),
        theta=yaw_from_quaternion(pose.get("orientation")),
        frame=normalise_frame(header.get("frame_id") or "map"),
        received=received,
        stamp=stamp_to_sec(header.get("stamp")),
    )


def parse_scan(msg: dict[str, Any], received: float) -> Scan:
    """``sensor_msgs/LaserScan`` -> :class:`Scan`, every ray classified by REP 117 (null = unknown)."""
    header = msg.get("header") or {}
    range_min = _f(msg.get("range_min", 0.0))
    range_max = _f(msg.get("range_max", float("inf")))
    if not math.isfinite(range_min):
        range_min = 0.0
    if math.isnan(range_max):
        range_max = float("inf")
    ranges, kinds = ranges_mod.classify_ranges(msg.get("ranges"), range_min, range_max)
    return Scan(
        angle_min=_f(msg.get("angle_min", 0.0)),
        angle_increment=_f(msg.get("angle_increment", 0.0)),
        range_min=range_min,
        range_max=range_max,
        ranges=ranges,
        at_max=kinds == ranges_mod.NO_RETURN,
        kinds=kinds,
        received=received,
        stamp=stamp_to_sec(header.get("stamp")),
        frame=normalise_frame(header.get("frame_id") or "laser"),
    )


def parse_map_metadata(info: dict[str, Any]) -> MapInfo:
    """``nav_msgs/MapMetaData`` (or the ``info`` of an OccupancyGrid) -> :class:`MapInfo`."""
    origin = info.get("origin") or {}
    pos = origin.get("position") or {}
    return MapInfo(
        width=int(info["width"]),
        height=int(info["height"]),
        resolution=float(info["resolution"]),
        origin=(_f(pos.get("x", 0.0)), _f(pos.get("y", 0.0)), yaw_from_quaternion(origin.get("orientation"))),
    )


def parse_tf_message(msg: dict[str, Any]) -> list[TransformStamped2D]:
    """``tf2_msgs/TFMessage`` (or ROS 1 ``tf/tfMessage``) -> planar transforms."""
    out: list[TransformStamped2D] = []
    for item in msg.get("transforms") or []:
        header = item.get("header") or {}
        tf = item.get("transform") or {}
        tr = tf.get("translation") or {}
        out.append(
            TransformStamped2D(
                parent=normalise_frame(header.get("frame_id") or ""),
                child=normalise_frame(item.get("child_frame_id") or ""),
                x=_f(tr.get("x", 0.0)),
                y=_f(tr.get("y", 0.0)),
                theta=yaw_from_quaternion(tf.get("rotation")),
                stamp=stamp_to_sec(header.get("stamp")),
            )
        )
    return out
