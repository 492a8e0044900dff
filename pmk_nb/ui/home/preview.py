"""The Home preview's chair link: connect off the kernel's thread, stream, stop, and report state.

The widgets stay in :class:`pmk_nb.ui.home.screen.HomeScreen`; this holds the link the preview uses, why
connecting failed, and when the preview started, and takes the typed :class:`PreviewSnapshot`
the info panel is written from.
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable
from typing import TYPE_CHECKING

from pmk_nb.clock import MONOTONIC, Clock
from pmk_nb.errors import PmkError
from pmk_nb.ui.common.page_lifecycle import page_seen
from pmk_nb.ui.home.info import CONNECT_TIMEOUT, STOPPED, PreviewSnapshot, unreachable_text

if TYPE_CHECKING:
    from pmk_nb.chair.link import ChairLink, LinkState

log = logging.getLogger(__name__)
READY_POLL_S = 0.1


class PreviewController:
    """Connects, streams and stops the preview's link; thread-safe.

    Args:
        on_state: called (on the link's watchdog thread) when the link's state changes.
        on_unreachable: called (on the connect thread) with the user message when connecting
            failed for the link still in use.
        ready: the chair is connected only once this says True: on a Voilà page, its first
            heartbeat (a kernel whose page closed while loading never opens a chair connection).
        clock: the start time and the wait between looks at ``ready`` (a ``VirtualClock`` in tests).
    """

    def __init__(
        self,
        on_state: Callable[[], None],
        on_unreachable: Callable[[str], None],
        ready: Callable[[], bool] = page_seen,
        clock: Clock = MONOTONIC,
    ) -> None:
        self._on_state = on_state
        self._clock = clock
        self._on_unreachable = on_unreachable
        self._ready = ready
        self._lock = threading.RLock()
        self._link: ChairLink | None = None
        self._unsubscribe: Callable[[], None] | None = None
        self._connect_error: str | None = None
        self._started = 0.0

    @property
    def link(self) -> ChairLink | None:
        """The link the preview uses, None when it is stopped."""
        with self._lock:
            return self._link

    def start(self, link: ChairLink) -> threading.Thread:
        """Use ``link`` and connect it in a thread (connecting can take seconds: timeout, DNS)."""
        with self._lock:
            self._link = link
            self._connect_error = None
            self._started = self._clock.now()
            self._unsubscribe = link.on_state_change(self._state_changed)
        thread = threading.Thread(target=self._connect, args=(link,), name="pmk-home-connect", daemon=True)
        thread.start()
        return thread

    def stop(self) -> None:
        """Stop the link's streams (the link itself stays open for other screens)."""
        with self._lock:
            link, self._link = self._link, None
            unsubscribe, self._unsubscribe = self._unsubscribe, None
        if unsubscribe is not None:
            unsubscribe()
        if link is not None:
            try:
                link.stop_streams()
            except Exception as err:  # the chair may be gone already: nothing to stop
                log.info("stopping streams failed: %s", err)

    def snapshot(self) -> PreviewSnapshot:
        """The link's state and latest messages now (:data:`STOPPED` without a link)."""
        with self._lock:
            link, error, started = self._link, self._connect_error, self._started
        if link is None:
            return STOPPED
        state: LinkState = link.state
        odom = link.latest_odom()
        pose = link.latest_pose() or odom
        return PreviewSnapshot(state, odom, pose, error, started, link.latest_scan())

    def _state_changed(self, _state: LinkState) -> None:
        self._on_state()

    def _connect(self, link: ChairLink) -> None:
        while not self._ready():
            with self._lock:
                if self._link is not link:  # stopped (or the app closed) before the page came
                    return
            self._clock.sleep(READY_POLL_S)
        try:
            link.connect(timeout=CONNECT_TIMEOUT)
            link.start_streams()
        except Exception as err:  # whatever it is, the page must say the chair is unreachable
            if not isinstance(err, PmkError):
                log.exception("connecting to the chair at %s:%s failed", link.host, link.port)
            message = unreachable_text(err, link.host, link.port)
            with self._lock:
                if self._link is not link:  # stopped meanwhile
                    return
                self._connect_error = message
            self._on_unreachable(message)
