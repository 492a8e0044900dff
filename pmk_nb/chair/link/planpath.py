"""The navigation stack's planned path (nav_msgs/Path), followed on its own throttled subscription.

Nav2's planner server publishes the global plan on ``/plan`` (and again each time its navigator
replans, 1 Hz by default); move_base publishes it on its global planner's private topic,
``/move_base/NavfnROS/plan`` (navfn, the default) or ``/move_base/GlobalPlanner/plan``. With the
profile's ``plan_topic`` "auto" all three are subscribed (a topic nobody publishes costs nothing);
a named topic is subscribed alone. A path is a few hundred poses: the subscription is throttled
(``throttle_rate`` 500 ms, ``queue_length`` 1) and the I/O thread only parses and stores the latest.
"""

from __future__ import annotations

import functools
import math
import threading
import time
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    import roslibpy

    from pmk_nb.chair.link.inspect import OwnSubscription

__all__ = ["AUTO", "PLAN_TOPICS", "PlanWatch", "PlannedPath", "parse_path"]

AUTO = "auto"
#: Where the navigation stacks publish their global plan: Nav2, then move_base's two global planners.
PLAN_TOPICS = ("/plan", "/move_base/NavfnROS/plan", "/move_base/GlobalPlanner/plan")
PATH_TYPE = "nav_msgs/Path"
THROTTLE_MS = 500


@dataclass(frozen=True)
class PlannedPath:
    """A planned path: ``points`` float64 (n, 2) in ``frame``, from ``topic``, ``received`` (monotonic)."""

    points: np.ndarray
    frame: str
    topic: str
    received: float


def parse_path(msg: dict[str, Any], topic: str, received: float) -> PlannedPath:
    """A nav_msgs/Path as JSON -> :class:`PlannedPath`; poses without finite x, y are dropped."""
    poses = msg.get("poses") if isinstance(msg, dict) else None
    xy: list[tuple[float, float]] = []
    for item in poses if isinstance(poses, list) else []:
        pos = ((item or {}).get("pose") or {}).get("position") or {} if isinstance(item, dict) else {}
        x, y = pos.get("x"), pos.get("y")
        if isinstance(x, int | float) and isinstance(y, int | float) and math.isfinite(x) and math.isfinite(y):
            xy.append((float(x), float(y)))
    header = msg.get("header") if isinstance(msg, dict) else None
    frame = str((header or {}).get("frame_id") or "map") if isinstance(header, dict) else "map"
    points = np.array(xy, dtype=np.float64).reshape(-1, 2)
    return PlannedPath(points, frame.lstrip("/"), topic, received)


class PlanWatch:
    """Subscribes the plan topic(s) on a link's ``roslibpy.Ros`` and keeps the latest path.

    ``follow(ros)`` is called from a timer with the link's current Ros (None when disconnected): a
    new Ros (a reconnect) is subscribed afresh. ``latest`` is safe from any thread.
    """

    def __init__(self, topic: str = AUTO) -> None:
        self.topics = PLAN_TOPICS if topic in ("", AUTO) else (topic,)
        self._lock = threading.Lock()
        self._ros: roslibpy.Ros | None = None
        self._subs: list[OwnSubscription] = []
        self._latest: PlannedPath | None = None
        self.count = 0

    @property
    def latest(self) -> PlannedPath | None:
        with self._lock:
            return self._latest

    def follow(self, ros: roslibpy.Ros | None) -> None:
        """Subscribe on ``ros`` unless already subscribed there; unsubscribe when it is None."""
        if ros is self._ros:
            return
        self.stop()
        if ros is None:
            return
        from pmk_nb.chair.link.inspect import OwnSubscription  # ends alone, see there

        subs = [
            OwnSubscription(ros, name, PATH_TYPE, functools.partial(self._on_path, name), THROTTLE_MS)
            for name in self.topics
        ]
        with self._lock:
            self._ros, self._subs = ros, subs

    def stop(self) -> None:
        """Unsubscribe (the latest path is forgotten: a new preview starts clean)."""
        with self._lock:
            subs, self._subs, self._ros, self._latest = self._subs, [], None, None
        for sub in subs:
            sub.stop()

    def _on_path(self, topic: str, msg: dict[str, Any]) -> None:  # I/O thread: parse and store
        path = parse_path(msg, topic, time.monotonic())
        with self._lock:
            self._latest = path
            self.count += 1
