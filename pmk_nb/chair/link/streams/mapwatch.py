"""Watching the chair's own map: ``/map`` subscribed for as long as a screen shows it.

``/map`` is latched (ROS 1) or transient-local (ROS 2 map servers, SLAM): rosbridge hands a new
subscriber the last map at once, and every later map as it is published. The callback runs on the
link's I/O thread and only stores the message with a counter; :meth:`MapWatch.latest` converts it
to an :class:`~pmk_nb.grid.OccupancyGrid` on the reader's thread (a big grid takes a while) and
caches the result, so each published map is converted once.

roslibpy's ``Topic.unsubscribe`` removes every listener of a topic *name*: a one-shot read of
``/map`` (:mod:`pmk_nb.chair.link.query.mapread`) would silence the watch. The watch therefore shares the
reader's lock for subscribing and unsubscribing, and the reader calls :meth:`MapWatch.relisten`
after its own unsubscribe (the bridge keeps the watch's subscription: it is unsubscribed by id).
"""

from __future__ import annotations

import contextlib
import logging
import threading
from typing import TYPE_CHECKING, Any

import roslibpy

from pmk_nb.grid import OccupancyGrid
from pmk_nb.wire import spell_type

if TYPE_CHECKING:
    from pmk_nb.chair.link.transport.ros import LinkRos

log = logging.getLogger(__name__)


class MapWatch:
    """The latest map the chair published on ``topic`` while watched.

    Args:
        topic: the map topic (the link's ``map_topic``).
        lock: the map reader's lock (see the module's note on one-shot reads).
    """

    def __init__(self, topic: str, lock: threading.Lock) -> None:
        self.topic_name = topic
        self._lock = lock
        self._topic: roslibpy.Topic | None = None
        self._ros: LinkRos | None = None
        self._msg: dict[str, Any] | None = None
        #: maps received since the watch started (a new number: a new map to show)
        self.received = 0
        self._converted: tuple[int, OccupancyGrid | None] = (0, None)
        self.error: str | None = None  # why the last map could not be read (malformed)

    @property
    def active(self) -> bool:
        return self._topic is not None

    def start(self, ros: LinkRos, ros_version: int | None) -> None:
        """Subscribe (once; roslibpy resubscribes by itself after a reconnect)."""
        with self._lock:
            if self._topic is not None:
                return
            topic = roslibpy.Topic(
                ros,
                self.topic_name,
                spell_type("nav_msgs/OccupancyGrid", ros_version),
                queue_length=1,
                reconnect_on_close=True,
            )
            topic.subscribe(self._on_map)
            self._topic, self._ros = topic, ros

    def stop(self) -> None:
        """Unsubscribe and forget the map (a later start shows what the chair publishes then)."""
        with self._lock:
            topic, self._topic, self._ros = self._topic, None, None
            if topic is not None:
                try:
                    topic.unsubscribe()
                except Exception as err:  # a closed socket: nothing left to unsubscribe
                    log.info("unsubscribing %s failed: %s", self.topic_name, err)
        self.forget()

    def forget(self) -> None:
        """Drop the subscription without a word to the bridge (its socket is closing); no lock taken."""
        self._topic = self._ros = None
        self._msg, self.received, self._converted, self.error = None, 0, (0, None), None

    def relisten(self) -> None:
        """Listen again after a one-shot read of the same topic removed every listener (caller holds the lock)."""
        ros = self._ros
        if self._topic is not None and ros is not None:
            with contextlib.suppress(KeyError):  # usually gone already; never listen twice
                ros.off(self.topic_name, self._on_map)
            ros.on(self.topic_name, self._on_map)

    def _on_map(self, msg: dict[str, Any]) -> None:  # I/O thread: store only
        self._msg = msg
        self.received += 1

    def latest(self) -> tuple[int, OccupancyGrid | None]:
        """(how many maps arrived, the newest as a grid or None); converts only a new one.

        A malformed map gives None and :attr:`error` says why (the previous grid is not kept: it is
        no longer what the chair uses).
        """
        count, msg = self.received, self._msg
        done, grid = self._converted
        if count == done or msg is None:
            return done, grid
        try:
            grid, self.error = OccupancyGrid.from_ros_msg(msg), None
        except (KeyError, TypeError, ValueError) as err:
            grid, self.error = None, f"the chair's map is malformed: {err}"
        self._converted = (count, grid)
        return count, grid
