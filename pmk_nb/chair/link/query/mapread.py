"""Reading the chair's current map: metadata (cheap, latched) and the full grid (heavy, on demand).

The map's facts come from the cheapest source the chair has, never from pulling a big grid when
something smaller answers: the PMK map server's ``/map_server/map_info`` service (header, metadata
and SHA-256, no grid), then ``/map_metadata``, then ``/map``. Without rosapi nobody can list the
topics, so ``/map_metadata`` gets a short head start (:data:`METADATA_GRACE`) before ``/map`` is
subscribed; what answered is remembered for the connection, so later calls go straight there.

One-shot subscriptions are serialised per link: roslibpy's ``Topic.unsubscribe`` removes every
listener of a topic name, so two overlapping one-shot reads of the same topic would cancel each other.
"""

from __future__ import annotations

import threading
import time
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import roslibpy

from pmk_nb.chair.link.streams.mapwatch import MapWatch
from pmk_nb.chair.link.streams.messages import MapInfo, parse_map_metadata
from pmk_nb.chair.link.transport.services import ServiceFailed
from pmk_nb.errors import ChairLinkError, ChairTimeout
from pmk_nb.grid import OccupancyGrid
from pmk_nb.wire import spell_type

if TYPE_CHECKING:
    from pmk_nb.chair.link.core import LinkCore

MAP_TOPIC = "/map"
METADATA_TOPIC = "/map_metadata"
GETMAP_SERVICES = ("/static_map", "/map_server/map")
MAP_INFO_SERVICE = "/map_server/map_info"
MAP_INFO_TYPE = "map_server_pmk/srv/MapInfo"
METADATA_GRACE = 0.25  # s: /map_metadata arrives in one round trip when it exists


@dataclass(frozen=True)
class MapFacts:
    """The PMK map server's MapInfo answer: the map now published, without its grid."""

    info: MapInfo
    sha256: str  # hex SHA-256 of the int8 cells as published (row 0 = bottom)
    path: str  # the YAML it was read from, on the chair
    stamp: float  # header stamp, s (changes with every load)
    loaded: bool = True  # False: the server runs but has no map yet (``info`` is all zeros then)


class MapReader:
    def __init__(self, link: LinkCore, map_topic: str = MAP_TOPIC, metadata_topic: str = METADATA_TOPIC) -> None:
        self._link = link
        self.map_topic, self.metadata_topic = map_topic, metadata_topic
        self._lock = threading.Lock()
        self._known: dict[str, Any] = {}  # what answered, for the connection in "protocol"
        #: the chair's own map, watched while a screen shows it (shares the lock: see its module)
        self.watch = MapWatch(map_topic, self._lock)

    def _learned(self) -> dict[str, Any]:
        """Facts learned on this connection (forgotten when the websocket is a new one)."""
        proto = getattr(self._link.ros, "protocol", None)
        if self._known.get("protocol") is not proto:
            self._known = {"protocol": proto}
        return self._known

    def map_facts(self, timeout: float) -> MapFacts | None:
        """MapInfo from the PMK map server (``loaded`` False when it has no map yet); None when the
        chair has no such service.

        Raises:
            ChairLinkError: not connected, or the service did not answer in time (a busy bridge).
        """
        known = self._learned()
        if known.get("map_info") is False:
            return None
        try:
            r = self._link.call(MAP_INFO_SERVICE, MAP_INFO_TYPE, {}, timeout)
        except ServiceFailed:  # no such service: the bridge says so at once
            known["map_info"] = False
            return None
        known["map_info"] = True
        if not r.get("loaded"):
            return MapFacts(MapInfo(0, 0, 0.0), "", "", 0.0, loaded=False)
        stamp = (r.get("header") or {}).get("stamp") or {}
        nanos = float(stamp.get("nanosec", stamp.get("nsecs", 0)))
        seconds = float(stamp.get("sec", stamp.get("secs", 0))) + 1e-9 * nanos
        info = parse_map_metadata(r.get("info") or {})
        return MapFacts(info, str(r.get("sha256") or ""), str(r.get("path") or ""), seconds)

    def _spell(self, type_name: str) -> str:
        return spell_type(type_name, self._link.ros_version)

    def _first(self, plan: list[tuple[str, str, float]], deadline: float) -> tuple[str, dict[str, Any]] | None:
        """Subscribe each (topic, type, start_delay) and return the first message, by plan order
        when several arrive together; None at the deadline.
        """
        ros = self._link.require_ros()
        got: dict[str, dict[str, Any]] = {}
        arrived = threading.Event()
        topics: dict[str, roslibpy.Topic] = {}
        t0 = time.monotonic()
        with self._lock:
            try:
                while True:
                    now = time.monotonic()
                    for name, type_name, delay in plan:
                        if name not in topics and now - t0 >= delay:
                            topic = roslibpy.Topic(
                                ros, name, self._spell(type_name), queue_length=1, reconnect_on_close=False
                            )

                            def on_msg(msg: dict[str, Any], name: str = name) -> None:
                                got.setdefault(name, msg)
                                arrived.set()

                            topic.subscribe(on_msg)
                            topics[name] = topic
                    if got:
                        for name, _t, _d in plan:
                            if name in got:
                                return name, got[name]
                    pending = [t0 + d for n, _t, d in plan if n not in topics]
                    wake = min([deadline, *pending])
                    if wake <= now and not pending:
                        return None
                    arrived.wait(max(0.0, wake - time.monotonic()))
                    if time.monotonic() >= deadline and not got:
                        return None
            finally:
                for topic in topics.values():
                    topic.unsubscribe()
                if self.map_topic in topics:
                    self.watch.relisten()  # the unsubscribe above removed the watch's listener too

    def _published(self, timeout: float) -> set[str] | None:
        if self._link.discovery.rosapi is False:
            return None  # known missing on this connection: do not ask again
        try:
            return set(self._link.discovery.topics(timeout))
        except ChairLinkError:
            return None  # no rosapi (or a busy one): just try the topics

    def _plan(self, timeout: float) -> list[tuple[str, str, float]]:
        meta = (self.metadata_topic, "nav_msgs/MapMetaData", 0.0)
        grid = (self.map_topic, "nav_msgs/OccupancyGrid", 0.0)
        source = self._learned().get("source")
        if source is not None:
            return [meta if source == self.metadata_topic else grid]
        published = self._published(max(0.05, min(self._link.rosapi_timeout, timeout / 2)))
        self._learned()["published"] = published
        if published is None:
            return [meta, (self.map_topic, "nav_msgs/OccupancyGrid", min(METADATA_GRACE, timeout / 3))]
        if self.metadata_topic in published:
            return [meta]  # never pull a (possibly huge) /map just for its size when metadata exists
        return [grid]

    def map_listed(self) -> bool:
        """Did rosapi list the map topic when map_info last asked (on this connection)?"""
        return self.map_topic in (self._learned().get("published") or ())

    def map_info(self, timeout: float, without_grid: bool = False) -> MapInfo:
        """Size, resolution and origin of the published map, from the cheapest source (see the module).

        ``without_grid``: only from MapInfo or /map_metadata, never /map (and without rosapi, waiting
        for /map_metadata no longer than twice its head start): a timeout rather than a big download.
        """
        deadline = time.monotonic() + timeout
        try:
            facts = self.map_facts(max(0.1, min(self._link.rosapi_timeout, timeout / 2)))
        except ChairTimeout:
            facts = None  # busy: the topics may still answer
        if facts is not None and facts.loaded:
            return facts.info
        plan = self._plan(deadline - time.monotonic())
        if without_grid:
            if len(plan) > 1:  # no rosapi: /map_metadata's head start only
                deadline = min(deadline, time.monotonic() + 2 * METADATA_GRACE)
            plan = [step for step in plan if step[0] == self.metadata_topic]
        first = self._first(plan, deadline) if plan else None
        if first is None and not without_grid and self._learned().pop("source", None) is not None:
            first = self._first(self._plan(deadline - time.monotonic()), deadline)  # the chair changed
        if first is None:
            raise ChairTimeout(
                f"connected but no map published within {timeout:.1f} s on {self.metadata_topic} or {self.map_topic} "
                "(is map_server running on the chair?)",
                operation="read the map metadata",
                seconds=timeout,
                host=self._link.host,
                port=self._link.port,
            )
        name, msg = first
        self._learned()["source"] = name
        return parse_map_metadata(msg if name == self.metadata_topic else msg["info"])

    def fetch_map(self, timeout: float) -> OccupancyGrid:
        deadline = time.monotonic() + timeout
        first = self._first([(self.map_topic, "nav_msgs/OccupancyGrid", 0.0)], time.monotonic() + timeout / 2)
        if first is not None:
            return self._grid(first[1])
        try:
            services = set(self._link.discovery.services())
        except ChairLinkError:
            services = set(GETMAP_SERVICES)
        for name in GETMAP_SERVICES:
            remaining = deadline - time.monotonic()
            if name in services and remaining > 0:
                r = self._link.call(name, "nav_msgs/GetMap", {}, remaining)
                return self._grid(r.get("map") or {})
        raise ChairTimeout(
            f"no map from the chair within {timeout:.1f} s: nothing on {self.map_topic} and no GetMap service "
            f"({', '.join(GETMAP_SERVICES)})",
            operation="fetch the map",
            seconds=timeout,
            host=self._link.host,
            port=self._link.port,
        )

    def _grid(self, msg: dict[str, Any]) -> OccupancyGrid:
        try:
            return OccupancyGrid.from_ros_msg(msg)
        except (KeyError, TypeError, ValueError) as err:
            raise ChairLinkError(
                f"the chair sent a malformed OccupancyGrid: {err}", host=self._link.host, port=self._link.port
            ) from err
