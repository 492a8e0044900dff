"""The chair link: one rosbridge connection to one chair, through roslibpy's asyncio transport.

Threads (all daemon, all ended by :meth:`ChairLink.close`):

* the I/O thread ``pmk-link-io-HOST:PORT`` runs roslibpy's event loop; topic callbacks run there
  and only parse + store the latest message (see :mod:`pmk_nb.chair.link.streams`);
* the watchdog thread ``pmk-link-watchdog-HOST:PORT`` derives the state every 0.1 s (rosbridge
  never reports half-open sockets, so "stale" means: connected but no message for
  ``stale_after`` s) and runs the ``on_state_change`` callbacks. Callbacks run on that thread:
  keep them short, and do not call blocking link methods from them if you care about timely
  state updates.

Blocking calls (connect, services, map_info, fetch_map) run on the caller's thread with timeouts.

Typical notebook use::

    link = get_link("192.168.1.20", 9090, pose_source="tf")   # re-running the cell reuses it
    report = link.test_connection(timeout=5.0)                 # ok + map facts, or why not
    link.start_streams()
    link.latest_pose(), link.latest_scan()                      # never block
    link.reload_map("~/ALMA_MAPS/floor2.yaml")                  # raises MapReloadError(code=...)
"""

from __future__ import annotations

import dataclasses
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import roslibpy
from roslibpy.core import RosTimeoutError, ServiceException

from pmk_nb.chair.link.discovery import Discovery
from pmk_nb.chair.link.mapread import MapReader
from pmk_nb.chair.link.probe import probe_rosbridge
from pmk_nb.chair.link.registry import close_all_links, get_link
from pmk_nb.chair.link.state import LinkState, StateCallback, StateWatch
from pmk_nb.chair.link.streams import PoseSource, StreamConfig, StreamHub
from pmk_nb.chair.link.transport import LinkRos
from pmk_nb.chair.messages import (
    MapInfo,
    Odometry,
    Pose2D,
    Scan,
    make_stamp,
    quaternion_from_yaw,
    spell_type,
)
from pmk_nb.chair.reload import (
    KEEPS_OLD_MAP,
    Flavour,
    MapReloadError,
    ReloadService,
    build_request,
    check_response,
)
from pmk_nb.errors import ChairLinkError
from pmk_nb.grid import OccupancyGrid

__all__ = [
    "ChairLink",
    "ConnectionReport",
    "LinkState",
    "MapInfo",
    "MapReloadError",
    "Odometry",
    "Pose2D",
    "ReloadService",
    "Scan",
    "close_all_links",
    "get_link",
]


@dataclass(frozen=True)
class ConnectionReport:
    """What "Test connection" shows: ok + map facts, or the precise reason it failed."""

    ok: bool
    reason: str
    map_info: MapInfo | None
    ros_version: int | None
    elapsed: float


class ChairLink:
    """A rosbridge link to one chair. Create through :func:`pmk_nb.chair.link.registry.get_link` in notebooks."""

    def __init__(
        self,
        host: str,
        port: int = 9090,
        *,
        odom_topic: str = "/odom",
        scan_topic: str = "/scan",
        pose_source: PoseSource = "odometry",
        pose_topic: str | None = None,
        stale_after: float = 2.0,
        throttle_ms: dict[str, int] | None = None,
        cmd_vel_topic: str = "/cmd_vel",
        goal_topic: str = "/move_base_simple/goal",
        reconnect_initial: float = 0.5,
        reconnect_max: float = 10.0,
        rosapi_timeout: float = 3.0,
        map_topic: str = "/map",
        map_metadata_topic: str = "/map_metadata",
        ping_interval: float | None = None,
        ping_timeout: float | None = None,
    ) -> None:
        if stale_after <= 0:
            raise ValueError(f"stale_after must be > 0 s, got {stale_after}")
        self.host, self.port = host, int(port)
        self.stale_after = float(stale_after)
        self.cmd_vel_topic, self.goal_topic = cmd_vel_topic, goal_topic
        self.reconnect_initial, self.reconnect_max = reconnect_initial, reconnect_max
        self.rosapi_timeout = rosapi_timeout
        # Websocket pings find half-open sockets (chair out of Wi-Fi range) and force a reconnect.
        self.ping_interval = ping_interval if ping_interval is not None else max(2.0, 2 * stale_after)
        self.ping_timeout = ping_timeout if ping_timeout is not None else max(5.0, 2 * stale_after)
        cfg = StreamConfig(odom_topic, scan_topic, pose_source, pose_topic)
        self._hub = StreamHub(cfg, throttle_ms or {})
        self._ros: LinkRos | None = None
        self._ros_version: int | None = None
        self._connected_at = 0.0
        self._streams_wanted = False
        self._streams_since = 0.0
        self._publishers: dict[str, roslibpy.Topic] = {}
        self._lock = threading.RLock()  # connect / close / streams bookkeeping
        self._watch = StateWatch(lambda: self.state, f"pmk-link-watchdog-{self.host}:{self.port}")
        self.discovery = Discovery(self._call)
        self._maps = MapReader(self, map_topic, map_metadata_topic)

    def __repr__(self) -> str:
        return f"ChairLink({self.host!r}, {self.port}, state={self.state.value})"

    # -- configuration -------------------------------------------------------------------------
    @property
    def config(self) -> dict[str, Any]:
        cfg = self._hub.config
        return {
            "odom_topic": cfg.odom_topic,
            "scan_topic": cfg.scan_topic,
            "pose_source": cfg.pose_source,
            "pose_topic": cfg.pose_topic,
            "stale_after": self.stale_after,
            "throttle_ms": dict(self._hub.throttle_ms),
        }

    def reconfigure(self, **kw: Any) -> None:
        """Change stream settings (topics, pose source, throttle, stale_after); resubscribes if needed."""
        known = {"odom_topic", "scan_topic", "pose_source", "pose_topic", "stale_after", "throttle_ms"}
        unknown = set(kw) - known
        if unknown:
            raise TypeError(f"reconfigure() got unknown settings {sorted(unknown)}")
        with self._lock:
            cfg = dataclasses.replace(
                self._hub.config,
                **{k: kw[k] for k in ("odom_topic", "scan_topic", "pose_source", "pose_topic") if k in kw},
            )
            hub = StreamHub(cfg, kw.get("throttle_ms", self._hub.throttle_ms))  # validates before any change
            hub.adopt_listeners(self._hub)
            running = self._streams_wanted
            if running:
                self.stop_streams()
            self._hub = hub
            self.stale_after = float(kw.get("stale_after", self.stale_after))
            if running:
                self.start_streams()

    # -- connection ------------------------------------------------------------------------------
    @property
    def ros(self) -> roslibpy.Ros | None:
        """The underlying ``roslibpy.Ros`` (for advanced use), None when closed."""
        return self._ros

    @property
    def is_connected(self) -> bool:
        ros = self._ros
        return ros is not None and ros.is_connected

    @property
    def ros_version(self) -> int | None:
        """1 or 2 from rosapi's time spelling at connect, else from the first odometry stamp."""
        return self._ros_version or self._hub.ros_version_seen

    def connect(self, timeout: float = 5.0) -> None:
        """Connect (no-op when already connected). Raises ChairLinkError with the precise reason."""
        deadline = time.monotonic() + timeout
        with self._lock:
            if self.is_connected:
                return
            if self._ros is not None:  # half-way (reconnecting): start over cleanly
                self._teardown_ros()
            probe = probe_rosbridge(self.host, self.port, max(0.05, deadline - time.monotonic()))
            if not probe.ok:
                raise ChairLinkError(f"Cannot connect to the chair at {self.host}:{self.port}: {probe.reason}")
            self._ros_version = probe.ros_version
            ros = LinkRos(
                self.host,
                self.port,
                thread_name=f"pmk-link-io-{self.host}:{self.port}",
                initial_delay=self.reconnect_initial,
                max_delay=self.reconnect_max,
                ping_interval=self.ping_interval,
                ping_timeout=self.ping_timeout,
            )
            ready = threading.Event()
            ros.on("ready", self._on_ready)
            ros.factory.on_ready(lambda _proto: ready.set())
            ros.connect()
            if not ready.wait(max(0.05, deadline - time.monotonic())):
                ros.shutdown(1.0)
                raise ChairLinkError(
                    f"Cannot connect to the chair at {self.host}:{self.port}: timed out opening the "
                    f"rosbridge websocket within {timeout:.1f} s"
                )
            self._ros = ros
            self._connected_at = time.monotonic()
            self._publishers = {}
            if self._streams_wanted:
                self._subscribe_streams(ros)
            self._watch.start()

    def _on_ready(self, _proto: Any) -> None:  # I/O thread, on every (re)connect
        self._connected_at = time.monotonic()

    def close(self) -> None:
        """Release everything: subscriptions, publishers, socket, I/O and watchdog threads.

        The link can be connected again afterwards; the latest values are forgotten.
        """
        with self._lock:
            self._streams_wanted = False
            self._teardown_ros()
            self._hub.clear()
            self._watch.stop()

    def _teardown_ros(self) -> None:
        ros, self._ros = self._ros, None
        if ros is None:
            return
        try:
            self._hub.unsubscribe()
            for topic in self._publishers.values():
                topic.unadvertise()
        finally:
            self._publishers = {}
            ros.shutdown()

    def __enter__(self) -> ChairLink:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def test_connection(self, timeout: float = 5.0) -> ConnectionReport:
        """Connect and read the published map's metadata; never raises for network trouble and
        never takes (much) longer than ``timeout``. Leaves the link connected on success.
        """
        t0 = time.monotonic()
        deadline = t0 + timeout

        def report(ok: bool, reason: str, info: MapInfo | None = None) -> ConnectionReport:
            return ConnectionReport(ok, reason, info, self.ros_version, time.monotonic() - t0)

        try:
            self.connect(timeout)
        except ChairLinkError as err:
            reason = str(err).split(": ", 1)[-1]
            return report(False, reason)
        remaining = deadline - time.monotonic()
        try:
            info = self._maps.map_info(max(0.1, remaining))
        except ChairLinkError:
            return report(False, f"connected but no map published within {timeout:.1f} s")
        return report(True, "connected", info)

    # -- state -------------------------------------------------------------------------------------
    @property
    def state(self) -> LinkState:
        ros = self._ros
        if ros is None:
            return LinkState.DISCONNECTED
        if not ros.is_connected:
            return LinkState.CONNECTING
        if self._streams_wanted and self._hub.active:
            last = max(self._hub.last_message or 0.0, self._connected_at, self._streams_since)
            if time.monotonic() - last > self.stale_after:
                return LinkState.STALE
        return LinkState.CONNECTED

    def on_state_change(self, callback: StateCallback) -> Callable[[], None]:
        """Call ``callback(new_state)`` on every change, on the link's watchdog thread.

        Returns a function that removes the callback.
        """
        return self._watch.add(callback)

    # -- streams -----------------------------------------------------------------------------------
    def start_streams(self) -> None:
        """Subscribe odometry, scan and the pose source (now if connected, else on connect)."""
        with self._lock:
            self._streams_wanted = True
            self._streams_since = time.monotonic()
            if self._ros is not None:
                self._subscribe_streams(self._ros)

    def stop_streams(self) -> None:
        with self._lock:
            self._streams_wanted = False
            self._hub.unsubscribe()

    def _subscribe_streams(self, ros: LinkRos) -> None:
        if self._hub.config.pose_source == "pose_topic" and not self._hub.active:
            self._resolve_pose_type()
        self._hub.subscribe(ros, self.ros_version)

    def _resolve_pose_type(self) -> None:
        """PoseStamped or PoseWithCovarianceStamped? rosbridge needs the right type to subscribe."""
        cfg = self._hub.config
        try:
            found = self._call("/rosapi/topic_type", "rosapi/TopicType", {"topic": cfg.pose_topic}, 2.0)
            if found.get("type"):
                cfg.pose_type = found["type"]
        except ChairLinkError:
            pass  # keep the default (PoseWithCovarianceStamped, what AMCL publishes)

    def latest_odom(self) -> Odometry | None:
        return self._hub.latest_odom()

    def latest_scan(self) -> Scan | None:
        return self._hub.latest_scan()

    def latest_pose(self) -> Pose2D | None:
        return self._hub.latest_pose()

    def add_listener(self, stream: str, fn: Callable[[Any], None]) -> Callable[[], None]:
        """Call ``fn(parsed)`` for every message of ``stream`` ("odom", "scan", "pose", "tf").

        Runs on the I/O thread: must be quick and must not call blocking link methods.
        """
        return self._hub.add_listener(stream, fn)

    @property
    def message_counts(self) -> dict[str, int]:
        return dict(self._hub.counts)

    # -- publishing --------------------------------------------------------------------------------
    def _publisher(self, name: str, type_name: str) -> roslibpy.Topic | None:
        ros = self._ros
        if ros is None or not ros.is_connected:
            return None
        topic = self._publishers.get(name)
        if topic is None:
            topic = roslibpy.Topic(ros, name, spell_type(type_name, self.ros_version), queue_size=1)
            self._publishers[name] = topic
        return topic

    def publish_cmd_vel(self, v: float, w: float) -> bool:
        """Send one velocity command. Returns False (and sends nothing) when not connected: a
        motion command must never be queued and delivered late after a reconnect.
        """
        topic = self._publisher(self.cmd_vel_topic, "geometry_msgs/Twist")
        if topic is None:
            return False
        topic.publish(
            roslibpy.Message(
                {"linear": {"x": float(v), "y": 0.0, "z": 0.0}, "angular": {"x": 0.0, "y": 0.0, "z": float(w)}}
            )
        )
        return True

    def send_goal(self, x: float, y: float, theta: float, frame: str = "map") -> bool:
        """Publish a navigation goal (PoseStamped). False when not connected (nothing queued)."""
        topic = self._publisher(self.goal_topic, "geometry_msgs/PoseStamped")
        if topic is None:
            return False
        header = {"frame_id": frame, "stamp": make_stamp(time.time(), self.ros_version)}
        if self.ros_version != 2:
            header["seq"] = 0
        pose = {"position": {"x": float(x), "y": float(y), "z": 0.0}, "orientation": quaternion_from_yaw(theta)}
        topic.publish(roslibpy.Message({"header": header, "pose": pose}))
        return True

    # -- services ------------------------------------------------------------------------------------
    def _require_ros(self) -> LinkRos:
        ros = self._ros
        if ros is None or not ros.is_connected:
            raise ChairLinkError(
                f"Not connected to the chair at {self.host}:{self.port} (state: {self.state.value}); connect first"
            )
        if threading.current_thread() is ros.loop_thread:
            raise ChairLinkError("blocking chair-link call from the link's I/O thread (a topic callback)")
        return ros

    def _call(self, name: str, type_name: str, args: dict[str, Any], timeout: float | None) -> dict[str, Any]:
        """Blocking service call; not connected -> error at once (never queued for a later reconnect)."""
        ros = self._require_ros()
        service = roslibpy.Service(ros, name, type_name)
        try:
            result = service.call(roslibpy.ServiceRequest(args), timeout=timeout or self.rosapi_timeout)
        except RosTimeoutError:
            raise ChairLinkError(
                f"timed out: {name} on {self.host}:{self.port} did not answer within "
                f"{timeout or self.rosapi_timeout:.1f} s"
            ) from None
        except ServiceException as err:
            raise ChairLinkError(f"{name} on {self.host}:{self.port} failed: {err}") from err
        return dict(result)

    def topics_of_type(self, msg_type: str) -> list[str]:
        """Topics of a message type, in either ROS spelling (``nav_msgs/Odometry`` finds both)."""
        return self.discovery.topics_of_type(msg_type)

    def services(self) -> list[str]:
        return self.discovery.services()

    def detect_reload_service(self) -> ReloadService | None:
        """The map reload service: /change_map, /map_server/load_map, /map_update or any MapUpdate."""
        return self.discovery.detect_reload_service()

    def reload_map(
        self,
        remote_yaml_path: str,
        flavour: Flavour | str | None = None,
        service: str | None = None,
        timeout: float = 30.0,
    ) -> None:
        """Ask the chair's map server to load ``remote_yaml_path`` (a path on the chair).

        ``flavour``/``service`` default to detection ("auto" means the same). Raises
        :class:`MapReloadError` (a ChairLinkError with ``code``) when the server refuses.
        """
        flavour = None if flavour in (None, "auto") else flavour
        service = None if service in (None, "", "auto") else service
        target = self.discovery.reload_target(flavour, service, f"{self.host}:{self.port}")
        try:
            response = self._call(
                target.name, target.service_type, build_request(target.flavour, remote_yaml_path), timeout
            )
        except ChairLinkError as err:
            if str(err).startswith("timed out"):
                raise MapReloadError(
                    f"{err}. The chair may still be loading {remote_yaml_path}; check map_info() before retrying.",
                    service=target.name,
                ) from err
            raise MapReloadError(f"{err}. {KEEPS_OLD_MAP}", service=target.name) from err
        check_response(target, remote_yaml_path, response)

    # -- maps ----------------------------------------------------------------------------------------
    def map_info(self, timeout: float = 5.0) -> MapInfo:
        """The published map's size/resolution/origin (from /map_metadata, else /map)."""
        return self._maps.map_info(timeout)

    def fetch_map(self, timeout: float = 15.0) -> OccupancyGrid:
        """The chair's current map (e.g. made by gmapping), from /map or the GetMap service."""
        return self._maps.fetch_map(timeout)
