"""Reading the chair's current map: metadata (cheap, latched) and the full grid (heavy, on demand).

One-shot subscriptions are serialised per link: roslibpy's ``Topic.unsubscribe`` removes every
listener of a topic name, so two overlapping one-shot reads of the same topic would cancel each other.
"""

from __future__ import annotations

import threading
import time
from typing import TYPE_CHECKING, Any

import roslibpy

from pmk_nb.chair.messages import MapInfo, parse_map_metadata, spell_type
from pmk_nb.errors import ChairLinkError, ChairTimeout
from pmk_nb.grid import OccupancyGrid

if TYPE_CHECKING:
    from pmk_nb.chair.link.client import ChairLink

MAP_TOPIC = "/map"
METADATA_TOPIC = "/map_metadata"
GETMAP_SERVICES = ("/static_map", "/map_server/map")


class MapReader:
    def __init__(self, link: ChairLink, map_topic: str = MAP_TOPIC, metadata_topic: str = METADATA_TOPIC) -> None:
        self._link = link
        self.map_topic, self.metadata_topic = map_topic, metadata_topic
        self._lock = threading.Lock()

    def _spell(self, type_name: str) -> str:
        return spell_type(type_name, self._link.ros_version)

    def _first(self, plan: list[tuple[str, str, float]], deadline: float) -> tuple[str, dict[str, Any]] | None:
        """Subscribe each (topic, type, start_delay) and return the first message, by plan order
        when several arrive together; None at the deadline.
        """
        ros = self._link._require_ros()
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

    def _published(self, timeout: float) -> set[str] | None:
        try:
            return set(self._link.discovery.topics(timeout))
        except ChairLinkError:
            return None  # no rosapi: just try the topics

    def map_info(self, timeout: float) -> MapInfo:
        deadline = time.monotonic() + timeout
        published = self._published(max(0.05, min(self._link.rosapi_timeout, timeout / 2)))
        if published is None:
            plan = [
                (self.metadata_topic, "nav_msgs/MapMetaData", 0.0),
                (self.map_topic, "nav_msgs/OccupancyGrid", min(1.0, timeout / 3)),
            ]
        elif self.metadata_topic in published:
            # Never pull a (possibly huge) /map just for its size when metadata exists.
            plan = [(self.metadata_topic, "nav_msgs/MapMetaData", 0.0)]
        else:
            plan = [(self.map_topic, "nav_msgs/OccupancyGrid", 0.0)]
        first = self._first(plan, deadline)
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
                r = self._link._call(name, "nav_msgs/GetMap", {}, remaining)
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
