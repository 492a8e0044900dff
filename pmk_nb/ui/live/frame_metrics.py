"""Frame metrics of the live view, and a ``hold_canvas`` that measures the bytes a frame sends.

Kept apart from the drawing code: tests and ``bench/bench_live.py`` read these numbers, the view
only records them.  Measuring never changes what is sent: the byte counter is one wrapper of the
canvas manager's ``send``, installed once, that passes every message on unchanged.
"""

from __future__ import annotations

import contextlib
import json
import threading
import time
from collections import deque
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from ipycanvas import hold_canvas

from pmk_nb.chair import Odometry, Pose2D, Scan
from pmk_nb.seams import canvas_manager

HISTORY = 4000  # frames kept for the metrics


@dataclass
class FrameMetrics:
    """Counters for tests and the benchmark; times in milliseconds, sizes in bytes."""

    frames: int = 0
    map_draws: int = 0
    skipped: int = 0
    errors: int = 0
    last_pose: tuple[float, float, float] | None = None
    last_hits: int = 0
    last_max_rays: int = 0
    frame_ms: deque[float] = field(default_factory=lambda: deque(maxlen=HISTORY))
    odom_delay_ms: deque[float] = field(default_factory=lambda: deque(maxlen=HISTORY))
    scan_delay_ms: deque[float] = field(default_factory=lambda: deque(maxlen=HISTORY))
    frame_bytes: deque[int] = field(default_factory=lambda: deque(maxlen=HISTORY))
    frame_sent: deque[float] = field(default_factory=lambda: deque(maxlen=HISTORY))
    #: the odometry and scan of the last recorded frame: a message's delay is counted once
    _last_messages: tuple[Odometry | None, Scan | None] = (None, None)

    def record(
        self,
        started: float,
        sent_at: float,
        nbytes: int,
        drew_map: bool,
        pose: Pose2D | Odometry | None,
        odom: Odometry | None,
        scan: Scan | None,
    ) -> None:
        """Count one drawn frame: ``started`` is its ``perf_counter()``, ``sent_at`` its ``monotonic()``."""
        self.frames += 1
        self.map_draws += int(drew_map)
        self.frame_ms.append((time.perf_counter() - started) * 1000.0)
        self.frame_bytes.append(nbytes)
        self.frame_sent.append(sent_at)
        last_odom, last_scan = self._last_messages
        if odom is not None and odom is not last_odom:
            self.odom_delay_ms.append((sent_at - float(odom.received)) * 1000.0)
        if scan is not None and scan is not last_scan:
            self.scan_delay_ms.append((sent_at - float(scan.received)) * 1000.0)
        self._last_messages = (odom, scan)
        self.last_pose = (float(pose.x), float(pose.y), float(pose.theta)) if pose is not None else None

    def summary(self) -> dict[str, float | int | None]:
        """Percentiles of what was recorded (None when nothing was)."""

        def pct(values: deque[float] | deque[int], q: float) -> float | None:
            return float(np.percentile(np.asarray(values, dtype=float), q)) if values else None

        sent = list(self.frame_sent)
        fps = (len(sent) - 1) / (sent[-1] - sent[0]) if len(sent) > 1 and sent[-1] > sent[0] else None
        return {
            "frames": self.frames,
            "map_draws": self.map_draws,
            "skipped": self.skipped,
            "errors": self.errors,
            "fps": fps,
            "frame_ms_p50": pct(self.frame_ms, 50),
            "frame_ms_p95": pct(self.frame_ms, 95),
            "odom_delay_ms_p50": pct(self.odom_delay_ms, 50),
            "odom_delay_ms_p95": pct(self.odom_delay_ms, 95),
            "scan_delay_ms_p50": pct(self.scan_delay_ms, 50),
            "scan_delay_ms_p95": pct(self.scan_delay_ms, 95),
            "bytes_p50": pct(self.frame_bytes, 50),
            "bytes_p95": pct(self.frame_bytes, 95),
            "bytes_max": float(max(self.frame_bytes)) if self.frame_bytes else None,
        }


class SendMeter:
    """Counts what a canvas manager hands to its comm (JSON content + binary buffers).

    ipycanvas batches a held frame into one custom message on its (kernel-wide, shared) canvas
    manager; one wrapper of that manager's ``send``, installed by :meth:`on`, adds each message's
    size to the counter of the measurement open on the sending thread, if any.  Other threads and
    unmeasured drawing pass through uncounted.
    """

    _ATTR = "_pmk_send_meter"

    def __init__(self, manager: Any) -> None:
        self._open = threading.local()
        original = manager.send

        def counting_send(content: Any, buffers: list[Any] | None = None) -> None:
            counter: list[int] | None = getattr(self._open, "counter", None)
            if counter is not None:
                # ipycanvas sends a frame as one binary buffer (its commands, JSON-encoded once by
                # ipycanvas) plus a small header dict ({"shape", "dtype"}): the buffers are counted by
                # length, never encoded again; only the ~40-byte header is (about 10 us a frame)
                counter[0] += sum(memoryview(b).nbytes for b in buffers or [])
                counter[0] += len(json.dumps(content, default=str))
            original(content, buffers)

        manager.send = counting_send

    @classmethod
    def on(cls, manager: Any) -> SendMeter:
        """The manager's meter, installed on first use."""
        meter = manager.__dict__.get(cls._ATTR)
        if meter is None:
            meter = cls(manager)
            manager.__dict__[cls._ATTR] = meter
        return meter

    @contextlib.contextmanager
    def measure(self) -> Iterator[list[int]]:
        """Yields ``[bytes]``, counting this thread's sends until the block ends."""
        counter = [0]
        outer = getattr(self._open, "counter", None)
        self._open.counter = counter
        try:
            yield counter
        finally:
            self._open.counter = outer


def install_byte_meter(widget: Any) -> None:
    """Install the byte counter on ``widget``'s canvas manager now (once; later calls do nothing).

    Done when a canvas is made, before anyone else wraps the manager's ``send`` (a test capturing
    messages, say), so every later wrapper chains to it and restoring theirs keeps it in place.
    """
    manager = canvas_manager(widget)
    if manager is not None:
        SendMeter.on(manager)


@contextlib.contextmanager
def measured_hold(widget: Any) -> Iterator[list[int]]:
    """``hold_canvas()`` that also counts the bytes its flush sends; yields ``[bytes]`` (0 if nothing drawn)."""
    manager = canvas_manager(widget)
    if manager is None:  # unknown ipycanvas internals: draw anyway, report nothing
        with hold_canvas():
            yield [0]
        return
    with SendMeter.on(manager).measure() as counter, hold_canvas():
        yield counter
