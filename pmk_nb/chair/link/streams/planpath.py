"""The navigation stack's planned path (nav_msgs/Path), followed on its own throttled subscription.

Nav2's planner server publishes the global plan on ``/plan`` (and again each time its navigator
replans, 1 Hz by default); move_base publishes it on its global planner's private topic,
``/move_base/NavfnROS/plan`` (navfn, the default) or ``/move_base/GlobalPlanner/plan``. With the
profile's ``plan_topic`` "auto" the chair's topics are looked up (rosapi, off the caller's thread,
again every few seconds until one is there) and only those of the three it has are subscribed: a
subscription names its type, so on a ROS 2 chair a guessed ROS 1 topic would appear in its topic list
(issue 40). Without rosapi nothing is guessed: name the topic in the profile. A named topic is
subscribed alone. A path is a few hundred poses: the subscription is throttled
(``throttle_rate`` 500 ms, ``queue_length`` 1) and the I/O thread only parses and stores the latest.
"""

from __future__ import annotations

import functools
import math
import threading
import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from pmk_nb.chair.link.streams.inspect import OwnSubscription  # a subscription that ends alone
from pmk_nb.errors import PmkError

if TYPE_CHECKING:
    import roslibpy


__all__ = ["AUTO", "PLAN_TOPICS", "PlanWatch", "PlannedPath", "parse_path"]

AUTO = "auto"
#: Where the navigation stacks publish their global plan: Nav2, then move_base's two global planners.
PLAN_TOPICS = ("/plan", "/move_base/NavfnROS/plan", "/move_base/GlobalPlanner/plan")
PATH_TYPE = "nav_msgs/Path"
THROTTLE_MS = 500
RELOOK_S = 5.0  # "auto": seconds between lookups while the chair lists no plan topic


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

    def __init__(
        self, topic: str = AUTO, lookup: Callable[[], Iterable[str]] | None = None, relook_s: float = RELOOK_S
    ) -> None:
        """``lookup``: the chair's topic names (``link.discovery.topics``), for "auto"; ``relook_s``: how often
        it is asked again while none of :data:`PLAN_TOPICS` is there (the planner may start later)."""
        self.auto = topic in ("", AUTO)
        self.topics = PLAN_TOPICS if self.auto else (topic,)
        self._lookup = lookup
        self._relook_s = relook_s
        self._looked: float | None = None  # monotonic time of the last lookup started on this Ros
        self._looking = False
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
        """Subscribe on ``ros`` unless already subscribed there; unsubscribe when it is None.

        "auto" subscribes only the plan topics the chair has: looked up on a thread of its own (the
        caller is a screen's timer), again every ``relook_s`` while none is there.
        """
        if ros is not self._ros:
            self.stop()
            if ros is None:
                return
            with self._lock:
                self._ros, self._looked = ros, None
            if not self.auto:
                self._subscribe(ros, self.topics)
                return
        if ros is None or not self.auto:
            return
        now = time.monotonic()
        with self._lock:
            stale = self._looked is None or now - self._looked >= self._relook_s
            due = not self._subs and not self._looking and stale
            if due:
                self._looking, self._looked = True, now
        if due:
            threading.Thread(target=self._look_up, args=(ros,), name="pmk-plan-lookup", daemon=True).start()

    def _look_up(self, ros: roslibpy.Ros) -> None:
        """The plan topics the chair lists, subscribed if ``ros`` is still the one followed."""
        try:
            listed = set(self._lookup()) if self._lookup is not None else set()
        except PmkError:  # no rosapi, busy, reconnecting: nothing is guessed; asked again later
            listed = set()
        finally:
            with self._lock:
                self._looking = False
        found = tuple(t for t in PLAN_TOPICS if t in listed)
        if found:
            self._subscribe(ros, found)

    def _subscribe(self, ros: roslibpy.Ros, topics: tuple[str, ...]) -> None:
        with self._lock:
            if ros is not self._ros or self._subs:
                return  # followed another Ros meanwhile, or already subscribed
            self._subs = [
                OwnSubscription(ros, name, PATH_TYPE, functools.partial(self._on_path, name), THROTTLE_MS)
                for name in topics
            ]

    @property
    def subscribed(self) -> tuple[str, ...]:
        """The plan topics subscribed now."""
        with self._lock:
            return tuple(sub.topic for sub in self._subs)

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
