"""The topic inspector's link side: which topics there are, how often one arrives, its latest message.

The list comes from rosapi (``/rosapi/topics``, names and types) where the bridge has it, else from
the topics the link itself knows (odometry, laser, pose, tf, the plan). Only the one topic being
inspected is subscribed, throttled (``throttle_rate`` :data:`THROTTLE_MS`, ``queue_length`` 1: a
page showing a 4 MB map or a 20 Hz scan costs at most two messages a second), and unsubscribed when
the inspector closes or moves to another topic. The I/O thread only stores the message and its
arrival; the text is made on the page's timer.

A throttled subscription cannot see a rate above 1000 / THROTTLE_MS Hz by counting arrivals; a ROS 1
header's ``seq`` still counts every message, so with it the true rate is known; without it (ROS 2)
the rate at the cap is shown as "at least".
"""

from __future__ import annotations

import itertools
import json
import math
import threading
import time
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import roslibpy

__all__ = [
    "THROTTLE_MS",
    "OwnSubscription",
    "Rate",
    "RateMeter",
    "TopicProbe",
    "pretty_message",
    "rate_text",
    "topic_rows",
]

THROTTLE_MS = 500
#: Longest message text shown (characters); longer text ends in a note of how much was cut.
TEXT_LIMIT = 4000
#: Longest list shown item by item (a scan's 720 ranges, a map's million cells): the rest is counted.
LIST_LIMIT = 12


@dataclass(frozen=True)
class Rate:
    """A measured rate: ``hz`` (None: fewer than two messages), ``at_least`` when the throttle hides
    the true rate, ``silent_s`` seconds since the last message (None: none yet)."""

    hz: float | None
    at_least: bool
    silent_s: float | None


class RateMeter:
    """Arrival times (and ROS 1 ``seq`` numbers) of the last ``keep`` messages of one topic."""

    def __init__(self, throttle_ms: int = THROTTLE_MS, keep: int = 20) -> None:
        self.throttle_ms = throttle_ms
        self._arrivals: deque[tuple[float, int | None]] = deque(maxlen=keep)
        self._lock = threading.Lock()

    def add(self, t: float, seq: int | None = None) -> None:
        with self._lock:
            self._arrivals.append((t, seq))

    def rate(self, now: float) -> Rate:
        with self._lock:
            items = list(self._arrivals)
        if not items:
            return Rate(None, False, None)
        silent = max(0.0, now - items[-1][0])
        if len(items) < 2 or items[-1][0] <= items[0][0]:
            return Rate(None, False, silent)
        span = items[-1][0] - items[0][0]
        seqs = [s for _, s in items]
        if all(isinstance(s, int) for s in seqs) and seqs[-1] > seqs[0]:  # type: ignore[operator]
            return Rate((seqs[-1] - seqs[0]) / span, False, silent)  # type: ignore[operator]
        hz = (len(items) - 1) / span
        cap = 1000.0 / self.throttle_ms if self.throttle_ms > 0 else math.inf
        return Rate(hz, hz >= 0.8 * cap, silent)


def rate_text(rate: Rate) -> str:
    """The rate in words: "10.0 Hz", "at least 2.0 Hz", "no messages yet", "silent for 12 s"."""
    if rate.silent_s is None:
        return "no messages yet"
    if rate.hz is not None and rate.silent_s > max(3.0, 3.0 / rate.hz):
        return f"silent for {rate.silent_s:.0f} s"
    if rate.hz is None:
        return "1 message"
    return f"{'at least ' if rate.at_least else ''}{rate.hz:.1f} Hz"


def _shorten(value: Any, depth: int = 0) -> Any:
    """Long lists shortened to their first items and a count; deep nesting cut (never recursion-bound)."""
    if depth > 12:
        return "…"
    if isinstance(value, dict):
        return {str(k): _shorten(v, depth + 1) for k, v in value.items()}
    if isinstance(value, list):
        head = [_shorten(v, depth + 1) for v in value[:LIST_LIMIT]]
        if len(value) > LIST_LIMIT:
            head.append(f"… {len(value) - LIST_LIMIT} more of {len(value)}")
        return head
    if isinstance(value, str) and len(value) > 200:
        return value[:200] + f"… ({len(value)} characters)"
    return value


def _lines(value: Any, indent: int, out: list[str], lead: str) -> None:
    """Indented JSON; a list of plain values (ranges, a covariance) stays on one line."""
    pad = "  " * indent
    if isinstance(value, dict) and value:
        out.append(f"{pad}{lead}{{")
        items = list(value.items())
        for i, (key, item) in enumerate(items):
            _lines(item, indent + 1, out, f"{json.dumps(key, ensure_ascii=False)}: ")
            if i < len(items) - 1:
                out[-1] += ","
        out.append(f"{pad}}}")
    elif isinstance(value, list) and any(isinstance(v, dict | list) for v in value):
        out.append(f"{pad}{lead}[")
        for i, item in enumerate(value):
            _lines(item, indent + 1, out, "")
            if i < len(value) - 1:
                out[-1] += ","
        out.append(f"{pad}]")
    else:
        out.append(f"{pad}{lead}{json.dumps(value, ensure_ascii=False, default=str)}")


def pretty_message(msg: Any, limit: int = TEXT_LIMIT) -> str:
    """A message as indented JSON, long lists shortened, the whole cut to ``limit`` characters."""
    out: list[str] = []
    _lines(_shorten(msg), 0, out, "")
    text = "\n".join(out)
    if len(text) > limit:
        text = text[:limit] + f"\n… (cut: {len(text) - limit} more characters)"
    return text


def topic_rows(rosapi: dict[str, str] | None, known: dict[str, str]) -> list[tuple[str, str]]:
    """(topic, type) rows sorted by name: rosapi's list where there is one (types filled from
    ``known`` where rosapi left them empty), else the link's ``known`` topics."""
    rows = dict(known) if rosapi is None else {name: typ or known.get(name, "") for name, typ in rosapi.items()}
    return sorted(rows.items())


class OwnSubscription:
    """A subscription that ends alone: roslibpy's ``Topic.unsubscribe`` removes *every* callback of
    the topic's name on that ``Ros`` (``ros.off(name)``), which would silence the link's own /odom
    stream when an inspected /odom is closed. This registers its one callback and subscribes with
    its own id (rosbridge keeps subscriber ids apart), through roslibpy's public ``on`` / ``off`` /
    ``send_on_ready``; :meth:`stop` removes exactly those.
    """

    _ids = itertools.count(1)

    def __init__(
        self,
        ros: roslibpy.Ros,
        topic: str,
        type_name: str | None,
        callback: Callable[[Any], None],
        throttle_ms: int = THROTTLE_MS,
        queue_length: int = 1,
    ) -> None:
        import roslibpy

        self.ros, self.topic, self.callback = ros, topic, callback
        self.id = f"subscribe:{topic}:pmk-{next(self._ids)}"
        op = {
            "op": "subscribe",
            "id": self.id,
            "topic": topic,
            "throttle_rate": throttle_ms,
            "queue_length": queue_length,
        }
        if type_name:
            op["type"] = type_name
        self._op = roslibpy.Message(op)
        ros.on(topic, callback)
        ros.on("close", self._resubscribe)  # the link's Ros reconnects by itself: subscribe again then
        ros.send_on_ready(self._op)

    def _resubscribe(self, _proto: Any) -> None:
        # as roslibpy's own Topic does after a close: queue the subscribe for the next connection
        self.ros.call_later(1, lambda: self.ros.send_on_ready(self._op))

    def stop(self) -> None:
        """Remove this callback and this subscriber id only (best effort: the socket may be gone)."""
        import roslibpy

        try:
            self.ros.off("close", self._resubscribe)
            self.ros.off(self.topic, self.callback)
            self.ros.send_on_ready(roslibpy.Message({"op": "unsubscribe", "id": self.id, "topic": self.topic}))
        except Exception:  # a closed link has nothing left to unsubscribe
            return


class TopicProbe:
    """One throttled subscription: its rate and latest message, until :meth:`stop`."""

    def __init__(self, ros: roslibpy.Ros, topic: str, type_name: str, throttle_ms: int = THROTTLE_MS) -> None:
        self.topic = topic
        self.type_name = type_name
        self.meter = RateMeter(throttle_ms)
        self._lock = threading.Lock()
        self._latest: Any = None
        self.count = 0
        self._sub = OwnSubscription(ros, topic, type_name or None, self._on_message, throttle_ms)

    def _on_message(self, msg: Any) -> None:  # I/O thread: store only
        header = msg.get("header") if isinstance(msg, dict) else None
        seq = header.get("seq") if isinstance(header, dict) else None
        self.meter.add(time.monotonic(), seq if isinstance(seq, int) and not isinstance(seq, bool) else None)
        with self._lock:
            self._latest = msg
            self.count += 1

    def latest(self) -> Any:
        with self._lock:
            return self._latest

    def stop(self) -> None:
        """Unsubscribe this probe only (the link's own stream of the same topic goes on)."""
        self._sub.stop()
