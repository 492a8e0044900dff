"""The link's live streams: subscriptions and the latest parsed message of each.

Threading contract: topic callbacks run on the link's I/O (asyncio) thread and only parse and
store (replacing one reference is atomic in CPython, so readers never take a lock and never block
the I/O thread). Readers (``latest_*``) may run on any thread.
"""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any, Literal

import roslibpy

from pmk_nb.chair.link.streams.messages import (
    Odometry,
    Pose2D,
    Scan,
    parse_odometry,
    parse_pose,
    parse_scan,
    parse_tf_message,
)
from pmk_nb.chair.link.streams.throttle import AUTO, AutoThrottle
from pmk_nb.viewport import TfTree
from pmk_nb.wire import spell_type, stamp_ros_version

LOG = logging.getLogger(__name__)

PoseSource = Literal["odometry", "pose_topic", "tf"]
POSE_SOURCES: tuple[str, ...] = ("odometry", "pose_topic", "tf")
STREAMS: tuple[str, ...] = ("odom", "scan", "pose", "tf")

# Milliseconds between messages rosbridge forwards (throttle_rate); AUTO: none unless the chair
# sends faster than a screen draws (see pmk_nb.chair.link.streams.throttle: a throttle costs latency).
# /tf is never throttled: rosbridge drops what it throttles, and a dropped map->odom from AMCL
# would be lost for seconds.
DEFAULT_THROTTLE_MS: dict[str, int] = {"odom": AUTO, "scan": AUTO, "pose": AUTO, "tf": 0}
TF_QUEUE_LENGTH = 50


@dataclass
class StreamConfig:
    odom_topic: str = "/odom"
    scan_topic: str = "/scan"
    pose_source: PoseSource = "odometry"
    pose_topic: str | None = None
    pose_type: str = "geometry_msgs/PoseWithCovarianceStamped"
    map_frame: str = "map"
    odom_frame: str = "odom"
    base_frame: str = "base_link"


Listener = Callable[[Any], None]


class StreamHub:
    """Subscribes the configured topics on a ``roslibpy.Ros`` and keeps the latest of each."""

    def __init__(self, config: StreamConfig, throttle_ms: dict[str, int]) -> None:
        if config.pose_source not in POSE_SOURCES:
            raise ValueError(f"pose_source must be one of {POSE_SOURCES}, got {config.pose_source!r}")
        if config.pose_source == "pose_topic" and not config.pose_topic:
            raise ValueError('pose_source="pose_topic" needs pose_topic (e.g. "/amcl_pose")')
        self.config = config
        self.throttle_ms = {**DEFAULT_THROTTLE_MS, **throttle_ms}
        self.tf = TfTree()
        self._odom: Odometry | None = None
        self._scan: Scan | None = None
        self._pose_msg: Pose2D | None = None
        self.last_message: float | None = None  # monotonic time of the last message on any stream
        self.counts: dict[str, int] = dict.fromkeys(STREAMS, 0)
        self.ros_version_seen: int | None = None
        self._topics: list[roslibpy.Topic] = []
        # AUTO streams: their rate watch, topic and handler (a throttle is set by resubscribing)
        self._auto: dict[str, tuple[AutoThrottle, roslibpy.Topic, Callable[[dict[str, Any]], None]]] = {}
        self._listeners: dict[str, list[Listener]] = {s: [] for s in STREAMS}
        self._listeners_lock = threading.Lock()

    # -- subscriptions ---------------------------------------------------------------------------
    @property
    def active(self) -> bool:
        return bool(self._topics)

    def subscribe(self, ros: roslibpy.Ros, ros_version: int | None) -> None:
        """Subscribe every stream (roslibpy resubscribes by itself after a reconnect)."""
        if self._topics:
            return
        cfg = self.config
        plan: list[tuple[str, str, str, Callable[[dict[str, Any]], None]]] = [
            ("odom", cfg.odom_topic, "nav_msgs/Odometry", self._on_odom),
            ("scan", cfg.scan_topic, "sensor_msgs/LaserScan", self._on_scan),
        ]
        if cfg.pose_source == "pose_topic" and cfg.pose_topic:
            plan.append(("pose", cfg.pose_topic, cfg.pose_type, self._on_pose))
        if cfg.pose_source == "tf":
            plan.append(("tf", "/tf", "tf2_msgs/TFMessage", self._on_tf))
        # always: base_link -> laser says where the rays start (an off-centre or rotated lidar)
        plan.append(("tf", "/tf_static", "tf2_msgs/TFMessage", self._on_tf_static))
        for stream, name, type_name, handler in plan:
            topic = roslibpy.Topic(
                ros,
                name,
                spell_type(type_name, ros_version),
                throttle_rate=max(0, self.throttle_ms[stream]),
                # /tf carries different transforms from several publishers: queue_length 1 would
                # drop one publisher's message whenever another's arrives in the same instant
                queue_length=TF_QUEUE_LENGTH if stream == "tf" else 1,
                reconnect_on_close=True,
            )
            topic.subscribe(handler)
            self._topics.append(topic)
            if self.throttle_ms[stream] == AUTO:
                self._auto[stream] = (AutoThrottle(), topic, handler)

    def throttles_in_use(self) -> dict[str, int]:
        """The throttle_rate (ms) each subscribed stream has now (AUTO streams: 0 until too fast)."""
        used = {s: max(0, ms) for s, ms in self.throttle_ms.items()}
        return used | {s: auto.current_ms for s, (auto, _t, _h) in self._auto.items()}

    def _retune(self, stream: str, throttle_ms: int) -> None:
        """Resubscribe an AUTO stream with a throttle (I/O thread: roslibpy only queues the ops)."""
        _auto, topic, handler = self._auto[stream]
        LOG.info("%s arrives faster than a screen draws: throttled to %d ms", topic.name, throttle_ms)
        topic.unsubscribe()
        topic.throttle_rate = throttle_ms
        topic.subscribe(handler)

    def unsubscribe(self) -> None:
        self._auto = {}
        topics, self._topics = self._topics, []
        for topic in topics:
            topic.unsubscribe()

    def clear(self) -> None:
        """Forget the latest values (after close: old data must not look current)."""
        self._odom = self._scan = self._pose_msg = None
        self.last_message = None
        self.tf.clear()

    # -- listeners -------------------------------------------------------------------------------
    def adopt_listeners(self, other: StreamHub) -> None:
        """Keep the listeners of the hub this one replaces (reconfigure)."""
        with other._listeners_lock:
            self._listeners = {k: list(v) for k, v in other._listeners.items()}

    def add_listener(self, stream: str, fn: Listener) -> Callable[[], None]:
        if stream not in self._listeners:
            raise ValueError(f"stream must be one of {STREAMS}, got {stream!r}")
        with self._listeners_lock:
            self._listeners[stream] = [*self._listeners[stream], fn]

        def remove() -> None:
            with self._listeners_lock:
                self._listeners[stream] = [f for f in self._listeners[stream] if f is not fn]

        return remove

    def _notify(self, stream: str, value: Any) -> None:
        for fn in self._listeners[stream]:  # a copy-on-write list: no lock on the I/O thread
            try:
                fn(value)
            except Exception:  # a UI bug must not kill the I/O thread
                logging.getLogger(__name__).exception("stream listener failed")

    # -- callbacks (I/O thread) -----------------------------------------------------------------
    def _mark(self, stream: str) -> float:
        now = time.monotonic()
        self.last_message = now
        self.counts[stream] += 1
        auto = self._auto.get(stream)
        if auto is not None:
            throttle = auto[0].note(now)
            if throttle is not None:
                self._retune(stream, throttle)
        return now

    def _on_odom(self, msg: dict[str, Any]) -> None:
        now = self._mark("odom")
        if self.ros_version_seen is None:
            self.ros_version_seen = stamp_ros_version((msg.get("header") or {}).get("stamp"))
        self._odom = parse_odometry(msg, now)
        self._notify("odom", self._odom)

    def _on_scan(self, msg: dict[str, Any]) -> None:
        scan = parse_scan(msg, self._mark("scan"))
        mount = self.laser_mount(scan.frame)
        self._scan = scan if mount == scan.mount else replace(scan, mount=mount)
        self._notify("scan", self._scan)

    def laser_mount(self, frame: str) -> tuple[float, float, float]:
        """base_link <- ``frame`` (x, y, yaw) from tf, or the identity while it is unknown."""
        found = self.tf.lookup(self.config.base_frame, frame) if frame else None
        if found is None:
            return (0.0, 0.0, 0.0)
        tf = found[0]
        return (tf.x, tf.y, tf.theta)

    def _on_pose(self, msg: dict[str, Any]) -> None:
        self._pose_msg = parse_pose(msg, self._mark("pose"))
        self._notify("pose", self._pose_msg)

    def _on_tf(self, msg: dict[str, Any], static: bool = False) -> None:
        now = self._mark("tf")
        transforms = parse_tf_message(msg)
        for t in transforms:
            self.tf.set(t, now, static=static)
        self._notify("tf", transforms)

    def _on_tf_static(self, msg: dict[str, Any]) -> None:
        self._on_tf(msg, static=True)

    # -- readers (any thread, never block) ----------------------------------------------------
    def latest_odom(self) -> Odometry | None:
        return self._odom

    def latest_scan(self) -> Scan | None:
        return self._scan

    def latest_pose(self) -> Pose2D | None:
        """The chair's pose per ``pose_source``; ``frame`` says whether it is in map or odom."""
        cfg = self.config
        if cfg.pose_source == "pose_topic":
            return self._pose_msg
        if cfg.pose_source == "tf":
            for frame in (cfg.map_frame, cfg.odom_frame):
                found = self.tf.lookup(frame, cfg.base_frame)
                if found is not None:
                    tf, received = found
                    if received == float("inf"):  # static-only chain: as old as the last /tf message
                        received = self.last_message or time.monotonic()
                    return Pose2D(tf.x, tf.y, tf.theta, frame, received)
            return None
        odom = self._odom
        if odom is None:
            return None
        return Pose2D(odom.x, odom.y, odom.theta, odom.frame, odom.received, odom.stamp)
