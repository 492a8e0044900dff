"""The chair link: one rosbridge connection to one chair, through roslibpy's asyncio transport.

Threads (all daemon, all ended by :meth:`ChairLink.close`):

* the I/O thread ``pmk-link-io-HOST:PORT`` runs roslibpy's event loop; topic callbacks run there
  and only parse + store the latest message (see :mod:`pmk_nb.chair.link.streams.hub`);
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
    link.reload_map("/home/pmk/ALMA_MAPS/floor2.yaml")          # absolute, on the chair; MapReloadError
"""

from __future__ import annotations

import dataclasses
import os
import threading
import time
from collections.abc import Callable, Sequence
from typing import Any

import roslibpy

from pmk_nb.chair.link.goals.goal_stop import running, stop_goals
from pmk_nb.chair.link.goals.initialpose import publish_initial_pose
from pmk_nb.chair.link.goals.navigate import GoalHandle, GoalPolicy, navigate
from pmk_nb.chair.link.linkconfig import LinkConfig
from pmk_nb.chair.link.query.connectivity import ConnectFailure, ConnectionReport, run_connection_test
from pmk_nb.chair.link.query.discovery import Discovery
from pmk_nb.chair.link.query.mapread import MapFacts, MapReader
from pmk_nb.chair.link.query.reload import (
    MapReloadError,
    ReloadKind,
    ReloadService,
    check_remote_path,
)
from pmk_nb.chair.link.record.recording import Recording, RecordStats, Topics, resolve_definitions, resolve_topics
from pmk_nb.chair.link.streams.hub import StreamConfig, StreamHub
from pmk_nb.chair.link.streams.messages import MapInfo, Odometry, Pose2D, Scan
from pmk_nb.chair.link.transport.probe import probe_rosbridge
from pmk_nb.chair.link.transport.publish import Publishers
from pmk_nb.chair.link.transport.ros import LinkRos, ServerStatus
from pmk_nb.chair.link.transport.services import call_service
from pmk_nb.chair.link.transport.state import LinkState, StateCallback, StateWatch
from pmk_nb.errors import ChairLinkError
from pmk_nb.grid import OccupancyGrid
from pmk_nb.viewport import Transform2D

__all__ = ["ChairLink", "ConnectionReport", "LinkConfig", "LinkState", "MapInfo", "MapReloadError", "Odometry"]
__all__ += ["Pose2D", "ReloadService", "Scan"]  # get_link, close_all_links: pmk_nb.chair.link (registry)


class ChairLink:
    """A rosbridge link to one chair. Create through :func:`pmk_nb.chair.link.registry.get_link` in notebooks."""

    def __init__(self, host: str, port: int = 9090, config: LinkConfig | None = None, **options: Any) -> None:
        """``config``: the link's settings whole (defaults: :class:`LinkConfig`); ``options``: the same
        settings by name (``pose_source="tf"``), applied on top (TypeError names an unknown one)."""
        cfg = (config or LinkConfig()).with_options(**options)
        self.link_config = cfg  # as created: reconfigure() changes the streams' settings, not this
        self.host, self.port, self.tls = (
            host,
            int(port),
            cfg.tls,
        )  # tls: wss, trusted as pmk_nb.chair.link.transport.tls says
        self.auth = cfg.auth  # rosbridge authentication (pmk_nb.chair.link.transport.bridge_auth)
        self.stale_after = float(cfg.stale_after)
        self._publish = Publishers(cfg.cmd_vel_topic, cfg.goal_topic)
        self.reconnect_initial, self.reconnect_max = cfg.reconnect_initial, cfg.reconnect_max
        self.rosapi_timeout = cfg.rosapi_timeout
        # Websocket pings find half-open sockets (chair out of Wi-Fi range) and force a reconnect.
        self.ping_interval, self.ping_timeout = cfg.pings
        streams = StreamConfig(cfg.odom_topic, cfg.scan_topic, cfg.pose_source, cfg.pose_topic)
        self._hub = StreamHub(streams, cfg.throttle_ms or {})
        self._ros: LinkRos | None = None
        self._ros_version: int | None = None
        self._connected_at = 0.0
        self._streams_wanted = False
        self._streams_since = 0.0
        self._lock = threading.RLock()  # connect / close / streams bookkeeping
        self._watch = StateWatch(lambda: self.state, f"pmk-link-watchdog-{self.host}:{self.port}")
        self.discovery = Discovery(self.call, f"{self.host}:{self.port}")
        self._maps = MapReader(self, cfg.map_topic, cfg.map_metadata_topic)
        self.goal_policy = GoalPolicy()  # deadlines, and what a link loss does to goals (the profile's)
        #: asked before every goal: the wall time of a latched Stop (the goal is refused), else None;
        #: the dashboard sets it from the chair-wide Stop latch (pmk_nb.drive.stopwatch)
        self.goal_gate: Callable[[], float | None] | None = None

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
        """Connect (no-op when already connected).

        Raises:
            ChairTimeout: the websocket did not open within ``timeout`` s.
            ChairLinkError: the chair cannot be reached; the message says precisely why.
        """
        failure = self.try_connect(timeout)
        if failure is not None:
            raise failure.error(self.host, self.port)

    def try_connect(self, timeout: float = 5.0) -> ConnectFailure | None:
        """Connect; returns why not instead of raising (None when connected)."""
        deadline = time.monotonic() + timeout
        with self._lock:
            if self.is_connected:
                return None
            if self._ros is not None:  # half-way (reconnecting): start over cleanly
                self._teardown_ros()
            probe = probe_rosbridge(
                self.host, self.port, max(0.05, deadline - time.monotonic()), self.tls, auth=self.auth
            )
            if not probe.ok:
                return ConnectFailure(probe.reason, probe.timeout, probe.error)
            self._ros_version = probe.ros_version
            ros = LinkRos(
                self.host,
                self.port,
                thread_name=f"pmk-link-io-{self.host}:{self.port}",
                initial_delay=self.reconnect_initial,
                max_delay=self.reconnect_max,
                ping_interval=self.ping_interval,
                ping_timeout=self.ping_timeout,
                tls=self.tls,
                auth=self.auth,
            )
            ros.on("ready", self._on_ready)
            ros.connect()
            if not ros.settled.wait(max(0.05, deadline - time.monotonic())) or ros.refusal is not None:
                ros.shutdown(1.0)
                if ros.refusal is not None:  # the certificate changed between the probe and this socket
                    return ConnectFailure(str(ros.refusal), None, ros.refusal)
                return ConnectFailure(f"timed out opening the rosbridge websocket within {timeout:.1f} s", timeout)
            self._ros = ros
            self._connected_at = time.monotonic()
            self._publish.reset()
            if self._streams_wanted:
                self._subscribe_streams(ros)
            self._watch.start()
        return None

    def _on_ready(self, _proto: Any) -> None:  # I/O thread, on every (re)connect
        self._connected_at = time.monotonic()
        self.discovery.forget()  # the bridge may have restarted with other settings (rosapi)

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
            self._maps.watch.forget()  # its socket goes with this Ros: a later watch subscribes anew
            self._hub.unsubscribe()
            self._publish.unadvertise_all()
        finally:
            ros.shutdown()

    def __enter__(self) -> ChairLink:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def test_connection(self, timeout: float = 5.0) -> ConnectionReport:
        """Connect and read the published map's metadata; never raises for network trouble and
        never takes (much) longer than ``timeout``. Leaves the link connected on success.
        """
        return run_connection_test(self, timeout, self._maps.map_listed)

    # -- state -------------------------------------------------------------------------------------
    @property
    def state(self) -> LinkState:
        ros = self._ros
        if ros is None or ros.refusal is not None:  # a certificate refused: no reconnect will come
            return LinkState.DISCONNECTED
        if not ros.is_connected:
            return LinkState.CONNECTING
        if self._streams_wanted and self._hub.active:
            last = max(self._hub.last_message or 0.0, self._connected_at, self._streams_since)
            if time.monotonic() - last > self.stale_after:
                return LinkState.STALE
        return LinkState.CONNECTED

    def on_state_change(self, callback: StateCallback) -> Callable[[], None]:
        """Call ``callback(new_state)`` on every change, on the link's watchdog thread; returns its remover."""
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
            found = self.call("/rosapi/topic_type", "rosapi/TopicType", {"topic": cfg.pose_topic}, 2.0)
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

    def frame_transform(self, target: str, source: str) -> Transform2D | None:
        """``target`` <- ``source`` from the tf tree the streams fill (None while they are not connected):
        where a layer in ``odom`` (a local costmap, a marker) goes on the map."""
        found = self._hub.tf.lookup(target, source)
        return None if found is None else found[0]

    def add_listener(self, stream: str, fn: Callable[[Any], None]) -> Callable[[], None]:
        """Call ``fn(parsed)`` for every message of ``stream`` ("odom", "scan", "pose", "tf").

        Runs on the I/O thread: must be quick and must not call blocking link methods.
        """
        return self._hub.add_listener(stream, fn)

    @property
    def message_counts(self) -> dict[str, int]:
        return dict(self._hub.counts)

    # -- recording (pmk_nb.chair.link.record.recording) ---------------------------------------------------------
    def start_recording(self, path: str | os.PathLike[str], topics: Topics = None) -> Recording:
        """Start recording ``topics`` (default: odometry, scan, pose, tf, cmd_vel, map) to the MCAP file
        ``path``; ``.stop()`` finishes the file, ``.stats`` counts. Topics may map to their types. Any
        type the bridge describes (rosapi ``message_details``) is recorded with its schema.

        Raises:
            UnknownTopic, UnsupportedType, RecordDiskError (see :mod:`.record`); ChairLinkError.
        """
        self.require_ros()
        types = resolve_topics(self, topics, str(path))
        return Recording(self, path, types, definitions=resolve_definitions(self, types, str(path)))

    def record(
        self, path: str | os.PathLike[str], topics: Topics = None, seconds: float = 5.0, flow_timeout: float = 10.0
    ) -> RecordStats:
        """Record ``seconds`` of messages (blocks) and return the finished file's stats: the clock
        starts with the first message from any topic (at most ``flow_timeout`` s on); it never waits for
        a silent topic, and ``stats.silent`` names the topics that sent nothing."""
        recording = self.start_recording(path, topics)
        try:
            recording.wait_flowing(flow_timeout)
            time.sleep(max(0.0, seconds))
        finally:
            stats = recording.stop()
        return stats

    # -- publishing --------------------------------------------------------------------------------
    def publish_cmd_vel(self, v: float, w: float, topic: str | None = None) -> bool:
        """Send one velocity command (to ``topic``, default the link's). Returns False (and sends
        nothing) when not connected: a motion command must never be queued and delivered late.
        """
        return self._publish.cmd_vel(self._ros, self.ros_version, v, w, topic)

    def send_goal(self, x: float, y: float, theta: float, frame: str = "map") -> bool:
        """Publish a PoseStamped goal (default topic: Nav2 ``/goal_pose``, ROS 1 ``/move_base_simple/goal``).
        False (nothing sent) when not connected or while the ROS version is unknown."""
        return self._publish.goal(self._ros, self.ros_version, x, y, theta, frame)

    def set_initial_pose(self, x: float, y: float, yaw: float, frame: str = "map", topic: str = "/initialpose") -> bool:
        """Tell the chair's localisation (AMCL) where it is: ``/initialpose`` with RViz's covariance.
        False (nothing sent) when not connected or while the ROS version is unknown; ValueError if
        not finite. See :mod:`pmk_nb.chair.link.goals.initialpose`."""
        return publish_initial_pose(self._publish, self._ros, self.ros_version, (x, y, yaw), frame, topic)

    @property
    def cmd_vel_topic(self) -> str:
        """Where :meth:`publish_cmd_vel` sends by default."""
        return self._publish.cmd_vel_topic

    @property
    def goal_topic(self) -> str | None:
        """The goal topic configured for this chair; None: the ROS version's default."""
        return self._publish.goal_topic

    def navigate_to(
        self, x: float, y: float, yaw: float, frame: str = "map", waypoints: Sequence[tuple[float, float]] = ()
    ) -> GoalHandle:
        """Drive to (x, y, yaw) with the chair's navigation stack, detected: see :mod:`.navigate`."""
        return navigate(self, x, y, yaw, frame, waypoints)

    def stop_goals(self, cmd_vel_topic: str | None = None, *, wait: bool = False) -> list[GoalHandle]:
        """The Stop for goals: cancel every goal this link runs, cancel all goals natively where the
        route allows, tell ``pmk robot goal-watchdog``, zero velocity: see :mod:`.goal_stop`."""
        return stop_goals(self, cmd_vel_topic, wait=wait)

    def running_goals(self) -> list[GoalHandle]:
        """The goals this link started that have not ended."""
        return running(self)

    def server_statuses(self) -> list[ServerStatus]:
        """The rosbridge server's latest ``status`` messages (e.g. a subscription with a wrong type)."""
        return list(self._ros.statuses) if self._ros is not None else []

    # -- services ------------------------------------------------------------------------------------
    def require_ros(self) -> LinkRos:
        """The open connection, for a blocking call or a subscription; ChairLinkError when not connected
        or when called from the link's I/O thread (it would wait on itself)."""
        ros = self._ros
        if ros is None or not ros.is_connected:
            raise ChairLinkError(
                f"Not connected to the chair at {self.host}:{self.port} (state: {self.state.value}); connect first",
                host=self.host,
                port=self.port,
            )
        if threading.current_thread() is ros.loop_thread:
            raise ChairLinkError(
                "blocking chair-link call from the link's I/O thread (a topic callback)", host=self.host, port=self.port
            )
        return ros

    def call(self, name: str, type_name: str, args: dict[str, Any], timeout: float | None) -> dict[str, Any]:
        """Blocking service call; not connected -> error at once (never queued for a later reconnect)."""
        seconds = timeout or self.rosapi_timeout
        return call_service(self.require_ros(), (self.host, self.port), name, type_name, args, seconds)

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
        kind: ReloadKind | str | None = None,
        service: str | None = None,
        timeout: float = 30.0,
    ) -> ReloadService:
        """Ask the chair's map server to load ``remote_yaml_path`` (an absolute path on the chair);
        returns the service that loaded it.

        Map servers do not expand ``~`` and read relative paths from their own working folder
        (Noetic answers 255, Nav2 "map does not exist"), so such a path is refused here before
        anything is sent; :func:`pmk_nb.chair.deploy.deploy` works the absolute path out over SFTP.
        ``kind``/``service`` default to detection ("auto" means the same); without rosapi the known
        reload services are tried by name. Raises :class:`MapReloadError` (a ChairLinkError with
        ``code``; ``keeps_old_map`` None when the answer was lost) when the server refuses.
        """
        check_remote_path(remote_yaml_path)
        kind = None if kind in (None, "auto") else kind
        service = None if service in (None, "", "auto") else service
        return self.discovery.reload(remote_yaml_path, kind, service, timeout)

    # -- maps ----------------------------------------------------------------------------------------
    def map_info(self, timeout: float = 5.0, without_grid: bool = False) -> MapInfo:
        """The published map's size/resolution/origin (MapInfo, /map_metadata, else /map unless ``without_grid``)."""
        return self._maps.map_info(timeout, without_grid)

    def map_facts(self, timeout: float = 5.0) -> MapFacts | None:
        """The PMK map server's MapInfo (header, metadata, SHA-256; no grid), None without one."""
        return self._maps.map_facts(timeout)

    def watch_map(self, on: bool = True) -> None:
        """Keep the chair's own ``/map`` (latched) from now on, or stop (``on=False``); the
        newest is :meth:`latest_map`. Subscribing waits for a one-shot map read in progress."""
        if not on:
            self._maps.watch.stop()
            return
        self._maps.watch.start(self.require_ros(), self.ros_version)

    @property
    def watching_map(self) -> bool:
        """Is the map watch subscribed (on this connection)?"""
        return self._maps.watch.active

    @property
    def map_problem(self) -> str | None:
        """Why the newest watched map could not be read (malformed), else None."""
        return self._maps.watch.error

    def latest_map(self) -> tuple[int, OccupancyGrid | None]:
        """(maps received since :meth:`watch_map`, the newest as a grid or None); converts a new
        map on the caller's thread, once. Never blocks on the network."""
        return self._maps.watch.latest()

    def fetch_map(self, timeout: float = 15.0) -> OccupancyGrid:
        """The chair's current map (e.g. made by gmapping), from /map or the GetMap service."""
        return self._maps.fetch_map(timeout)
