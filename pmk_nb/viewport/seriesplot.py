"""Several series of any numeric field over a time window (issue 40, Plots): a bounded ring of (t, value)
samples per series and the maths that turns the visible part of each into pixel polylines on one
shared y-axis (the plot widget only draws what :func:`series_lines` returns).
"""

from __future__ import annotations

import math
import threading
from dataclasses import dataclass

import numpy as np

from pmk_nb.viewport.history import nice_limit

__all__ = ["SeriesLines", "SeriesRing", "series_lines"]


class SeriesRing:
    """The last ``capacity`` (t, value) samples of one series; thread-safe (the link's I/O thread adds,
    the page's timer reads). Non-finite samples and samples not newer than the last are skipped."""

    def __init__(self, capacity: int = 6000) -> None:
        if capacity < 2:
            raise ValueError(f"capacity must be at least 2 samples, got {capacity}")
        self.capacity = int(capacity)
        self._data = np.zeros((self.capacity, 2), dtype=np.float64)
        self._next = self._count = 0
        self._lock = threading.Lock()

    def __len__(self) -> int:
        return self._count

    def add(self, t: float, value: float) -> bool:
        if not (math.isfinite(t) and math.isfinite(value)):
            return False
        with self._lock:
            if self._count and t <= self._data[(self._next - 1) % self.capacity, 0]:
                return False
            self._data[self._next] = (t, value)
            self._next = (self._next + 1) % self.capacity
            self._count = min(self._count + 1, self.capacity)
        return True

    def window(self, since: float) -> np.ndarray:
        """The samples with ``t >= since``, oldest first, as a (n, 2) copy."""
        with self._lock:
            order = (self._next - self._count + np.arange(self._count)) % self.capacity
            rows = self._data[order]
        return rows[rows[:, 0] >= since]


@dataclass(frozen=True)
class SeriesLines:
    """Pixel polylines (n, 2) per series, and the shared y-axis from ``y_min`` (bottom) to ``y_max`` (top)."""

    lines: list[np.ndarray]
    y_min: float
    y_max: float


def _axis(lo: float, hi: float) -> tuple[float, float]:
    """Round limits around [lo, hi]: from 0 when all values share a sign, symmetric steps otherwise."""
    if not (math.isfinite(lo) and math.isfinite(hi)):
        return -1.0, 1.0
    if lo >= 0:
        return 0.0, nice_limit(hi, 1e-9) if hi > 0 else 1.0
    if hi <= 0:
        return -nice_limit(-lo, 1e-9), 0.0
    return -nice_limit(-lo, 1e-9), nice_limit(hi, 1e-9)


def series_lines(windows: list[np.ndarray], now: float, span_s: float, width: int, height: int) -> SeriesLines:
    """Each series' samples (t, value) of the last ``span_s`` seconds -> pixels in a ``width`` x ``height``
    box: time left (``now - span_s``) to right (``now``), values on one y-axis that holds them all."""
    rows = [np.asarray(w, dtype=np.float64).reshape(-1, 2) for w in windows]
    values = np.concatenate([r[:, 1] for r in rows]) if rows else np.empty(0)
    lo, hi = _axis(float(values.min()), float(values.max())) if values.size else (-1.0, 1.0)
    span = max(float(span_s), 1e-9)
    scale = (height - 1) / (hi - lo)
    lines = [
        np.stack([(r[:, 0] - (now - span)) / span * (width - 1), (height - 1) - (r[:, 1] - lo) * scale], axis=1)
        for r in rows
    ]
    return SeriesLines(lines, lo, hi)
