"""Frame metrics of the live view and a ``hold_canvas`` that measures the bytes a frame sends.

Kept apart from the drawing code: tests and ``bench/bench_live.py`` read these numbers, the view
only records them.
"""

from __future__ import annotations

import contextlib
import json
from collections import deque
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from ipycanvas import hold_canvas

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
        }


@contextlib.contextmanager
def measured_hold(widget: Any) -> Iterator[list[int]]:
    """``hold_canvas()`` that also counts the bytes the flush hands to the comm (JSON + buffers).

    ipycanvas batches a frame into one custom message on its canvas manager; wrapping that
    manager's ``send`` for the duration of the hold measures the real payload (the message still
    goes out unchanged).  The count is 0 when nothing was drawn.
    """
    counter = [0]
    manager = getattr(widget, "_canvas_manager", None)
    if manager is None:  # unknown ipycanvas internals: draw anyway, report nothing
        with hold_canvas():
            yield counter
        return
    if hasattr(manager, "_current_canvas"):
        # ipycanvas sends "switch to layer N" only when the target layer changes, remembering the
        # last one in Python.  A page that joined later (Voilà drops messages sent before the page
        # connected; a reload; a second view) never saw that switch, and a frame drawing only the
        # dynamic layer would go nowhere.  Forgetting it makes every frame name its layer again.
        manager._current_canvas = None
    had_own = "send" in manager.__dict__
    original = manager.send

    def counting_send(content: Any, buffers: list[Any] | None = None) -> None:
        counter[0] += len(json.dumps(content, default=str))
        counter[0] += sum(memoryview(b).nbytes for b in buffers or [])
        original(content, buffers)

    manager.send = counting_send
    try:
        with hold_canvas():
            yield counter
    finally:
        if had_own:
            manager.send = original
        else:
            with contextlib.suppress(AttributeError):
                del manager.send
