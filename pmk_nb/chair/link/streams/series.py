"""Samples of any numeric fields of one topic over time (issue 40, Plots), on one throttled subscription.

The I/O thread reads each plotted field of a message (:func:`~pmk_nb.chair.link.streams.fields.field_value`,
a few dictionary look-ups) into that field's bounded ring: storing a whole message per sample would
keep megabytes of scans for a chart of one number. The time axis is the arrival time (monotonic).
"""

from __future__ import annotations

import threading
import time
from typing import TYPE_CHECKING, Any

from pmk_nb.chair.link.streams.fields import field_value
from pmk_nb.chair.link.streams.inspect import OwnSubscription  # a subscription that ends alone
from pmk_nb.viewport import SeriesRing

if TYPE_CHECKING:
    import roslibpy

__all__ = ["SERIES_THROTTLE_MS", "TopicSeries"]

#: at most 20 samples a second per topic: a chart a few hundred pixels wide shows no more
SERIES_THROTTLE_MS = 50
#: 15 minutes at 20 Hz per field
CAPACITY = 18_000


class TopicSeries:
    """One topic's plotted fields: ``rings[field]`` holds its samples until :meth:`stop`."""

    def __init__(self, ros: roslibpy.Ros, topic: str, type_name: str, throttle_ms: int = SERIES_THROTTLE_MS) -> None:
        self.topic, self.type_name = topic, type_name
        self._lock = threading.Lock()
        self.rings: dict[str, SeriesRing] = {}
        self.count = 0
        self._sub = OwnSubscription(ros, topic, type_name or None, self._on_message, throttle_ms)

    def add_field(self, path: str) -> SeriesRing:
        with self._lock:
            return self.rings.setdefault(path, SeriesRing(CAPACITY))

    def remove_field(self, path: str) -> None:
        with self._lock:
            self.rings.pop(path, None)

    @property
    def fields(self) -> list[str]:
        with self._lock:
            return list(self.rings)

    def _on_message(self, msg: Any) -> None:  # I/O thread: a few look-ups per field, then store
        now = time.monotonic()
        with self._lock:
            rings = list(self.rings.items())
            self.count += 1
        for path, ring in rings:
            value = field_value(msg, path)
            if value is not None:
                ring.add(now, value)

    def stop(self) -> None:
        self._sub.stop()
