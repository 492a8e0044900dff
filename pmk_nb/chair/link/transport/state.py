"""Link state and the watchdog thread that turns "no news" into a state change.

rosbridge never tells a client that a socket went half-open or that the chair stopped
publishing, so the link polls its own facts (socket open? last message age?) every tick and
reports changes. Callbacks run on the watchdog thread, never on the I/O thread, so a slow UI
callback cannot delay message handling.
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable
from enum import Enum

LOG = logging.getLogger(__name__)
TICK = 0.1  # s between state evaluations: state-change callbacks lag by at most this much


class LinkState(str, Enum):
    DISCONNECTED = "disconnected"
    CONNECTING = "connecting"  # also while reconnecting with backoff after a drop
    CONNECTED = "connected"
    STALE = "stale"  # socket open, but no message on the streams for stale_after seconds


StateCallback = Callable[[LinkState], None]


class StateWatch:
    """Evaluates ``compute()`` every tick on its own thread and calls the callbacks on changes."""

    def __init__(self, compute: Callable[[], LinkState], thread_name: str) -> None:
        self._compute = compute
        self._thread_name = thread_name
        self._callbacks: list[StateCallback] = []
        self._lock = threading.Lock()
        self._thread: threading.Thread | None = None
        self._stop = threading.Event()
        self._last = LinkState.DISCONNECTED

    def add(self, callback: StateCallback) -> Callable[[], None]:
        with self._lock:
            self._callbacks = [*self._callbacks, callback]  # copy-on-write: the thread reads without a lock

        def remove() -> None:
            with self._lock:
                self._callbacks = [c for c in self._callbacks if c is not callback]

        return remove

    def start(self) -> None:
        if self._thread is not None and self._thread.is_alive():
            return
        self._stop = stop = threading.Event()
        self._thread = threading.Thread(target=self._run, args=(stop,), name=self._thread_name, daemon=True)
        self._thread.start()

    def stop(self) -> None:
        """Stop after one last evaluation (so "disconnected" is reported), and join."""
        self._stop.set()
        thread, self._thread = self._thread, None
        if thread is not None and thread is not threading.current_thread():
            thread.join(2.0)

    def _run(self, stop: threading.Event) -> None:
        while True:
            stopping = stop.wait(TICK)
            state = self._compute()
            if state != self._last:
                self._last = state
                for cb in self._callbacks:
                    try:
                        cb(state)
                    except Exception:  # a UI bug must not stop the watchdog
                        LOG.exception("state-change callback failed")
            if stopping:
                return
