"""Automatic subscription throttling: only when the chair sends faster than a screen draws.

rosbridge's ``throttle_rate`` is not free. rosbridge-server-rs holds a throttled message until the
next tick, so a 50 ms throttle on a 40 Hz laser adds ~26 ms median and drops some scans; a 20 ms
throttle on 50 Hz odometry adds ~10 ms (issue 9, ``bench/bench_link.py``). A message that arrives
between two frames is drawn at the next frame anyway, so throttling a stream the screen keeps up
with saves nothing the user sees and only adds delay. Throttling pays only when the chair sends
faster than any screen draws (a 100 Hz odometry, a 200 Hz IMU-fed pose): then most messages would
be thrown away after crossing the Wi-Fi and being parsed.

So a stream set to :data:`AUTO` starts unthrottled; :class:`AutoThrottle` counts its messages per
window and asks once for ``throttle_rate`` = one screen frame when the rate stays above
:data:`SCREEN_HZ` (with a margin) for two windows. It never asks to release it: the rate seen through a throttle
depends on the server's throttle semantics (the Python server drops, the Rust one holds), so it
says nothing reliable about the chair's own rate; a new subscription (reconfigure) measures afresh.
"""

from __future__ import annotations

import math

#: ``throttle_ms`` value meaning "automatic" (the default for odometry, scans and poses).
AUTO = -1
#: The most frames a screen draws per second (common display refresh): above it, messages are wasted.
SCREEN_HZ = 60.0
#: The throttle used when a stream is faster than the screen: one frame.
FRAME_MS = math.ceil(1000.0 / SCREEN_HZ)
#: Measuring window (seconds) and margin: throttle above SCREEN_HZ * ENGAGE in WINDOWS windows in a
#: row (timer jitter and a burst of late messages, e.g. after a Wi-Fi stall, aside).
WINDOW_S = 1.0
ENGAGE = 1.15
WINDOWS = 2


class AutoThrottle:
    """Rate watch for one stream; :meth:`note` returns the ``throttle_rate`` to use when one is due.

    Pure and single-threaded (called on the link's I/O thread, once per message): a counter and a
    window start, no lock, no allocation.
    """

    def __init__(self, screen_hz: float = SCREEN_HZ, window_s: float = WINDOW_S) -> None:
        self.screen_hz = screen_hz
        self.window_s = window_s
        self.frame_ms = math.ceil(1000.0 / screen_hz)
        self.current_ms = 0
        self.rate_hz: float | None = None  # messages/s received in the last full window
        self._start: float | None = None
        self._count = 0
        self._over = 0  # windows in a row above the screen's rate

    def note(self, now: float) -> int | None:
        """Count one message received at ``now`` (monotonic s); a new throttle (ms) or None."""
        if self._start is None:
            self._start = now
            return None
        self._count += 1
        elapsed = now - self._start
        if elapsed < self.window_s:
            return None
        self.rate_hz = self._count / elapsed
        self._start, self._count = now, 0
        self._over = self._over + 1 if self.rate_hz > self.screen_hz * ENGAGE else 0
        if self.current_ms or self._over < WINDOWS:
            return None
        self.current_ms = self.frame_ms
        return self.current_ms
