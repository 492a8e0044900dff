"""Speed and turn rate over the last minutes: a bounded ring buffer of odometry samples and the
maths that turns a window of it into plot lines (issue 29: "odometry and speed over time").

Home samples the link's latest odometry from its info timer (a few per second, never per message),
so the buffer grows by at most :attr:`OdomHistory.capacity` samples whatever the chair's odometry
rate; the oldest fall out. The plot widget (:mod:`pmk_nb.ui.plots.panel`) only draws what
:func:`plot_lines` returns.
"""

from __future__ import annotations

import math
import threading
from dataclasses import dataclass

import numpy as np

__all__ = ["OdomHistory", "PlotLines", "nice_limit", "plot_lines"]


class OdomHistory:
    """The last ``capacity`` (t, v, w) samples: time (s, monotonic), speed (m/s), turn rate (rad/s).

    Thread-safe; :meth:`add` skips a sample not newer than the last (the same odometry message seen
    twice by the timer) and any non-finite value.
    """

    def __init__(self, capacity: int = 1200) -> None:
        if capacity < 2:
            raise ValueError(f"capacity must be at least 2 samples, got {capacity}")
        self.capacity = int(capacity)
        self._data = np.zeros((self.capacity, 3), dtype=np.float64)
        self._next = 0
        self._count = 0
        self._lock = threading.Lock()

    def __len__(self) -> int:
        return self._count

    def add(self, t: float, v: float, w: float) -> bool:
        """Keep one sample; False when it is not newer than the last one or not finite."""
        if not (math.isfinite(t) and math.isfinite(v) and math.isfinite(w)):
            return False
        with self._lock:
            if self._count and t <= self._data[(self._next - 1) % self.capacity, 0]:
                return False
            self._data[self._next] = (t, v, w)
            self._next = (self._next + 1) % self.capacity
            self._count = min(self._count + 1, self.capacity)
        return True

    def clear(self) -> None:
        with self._lock:
            self._next = self._count = 0

    def window(self, since: float) -> np.ndarray:
        """The samples with ``t >= since``, oldest first, as a (n, 3) copy."""
        with self._lock:
            start = (self._next - self._count) % self.capacity
            order = (start + np.arange(self._count)) % self.capacity
            rows = self._data[order]
        return rows[rows[:, 0] >= since]


@dataclass(frozen=True)
class PlotLines:
    """Pixel polylines of one plot: ``speed`` and ``turn`` (n, 2) each, and the y-axis limits
    (``speed_max`` m/s, ``turn_max`` °/s; each axis runs from -max to +max)."""

    speed: np.ndarray
    turn: np.ndarray
    speed_max: float
    turn_max: float


def nice_limit(peak: float, floor: float) -> float:
    """An axis limit at or above ``peak`` and ``floor``: 1, 2 or 5 times a power of ten."""
    value = max(abs(peak), floor)
    exp = math.floor(math.log10(value))
    for step in (1.0, 2.0, 5.0, 10.0):
        if step * 10.0**exp >= value - 1e-12:
            return step * 10.0**exp
    return 10.0 ** (exp + 1)  # not reached: 10 * 10**exp always covers value


def plot_lines(samples: np.ndarray, now: float, span_s: float, width: int, height: int) -> PlotLines:
    """Samples (t, v, w) of the last ``span_s`` seconds -> pixels in a ``width`` x ``height`` box.

    Time runs left (``now - span_s``) to right (``now``); each value is scaled around the box's
    middle line by its own symmetric limit (turn rate in degrees per second).
    """
    rows = np.asarray(samples, dtype=np.float64).reshape(-1, 3)
    v, w_deg = rows[:, 1], np.degrees(rows[:, 2])
    speed_max = nice_limit(float(np.max(np.abs(v))) if v.size else 0.0, 0.2)
    turn_max = nice_limit(float(np.max(np.abs(w_deg))) if w_deg.size else 0.0, 10.0)
    x = (rows[:, 0] - (now - span_s)) / span_s * (width - 1)
    mid = (height - 1) / 2.0

    def line(values: np.ndarray, limit: float) -> np.ndarray:
        return np.stack([x, mid - values / limit * mid], axis=1)

    return PlotLines(line(v, speed_max), line(w_deg, turn_max), speed_max, turn_max)
