"""roslibpy's Twisted connection factory for a chair link, when the process already uses Twisted.

Autobahn's txaio layer binds one framework per process. When user code (a plain ``roslibpy.Ros``,
whose default transport is Twisted, or any Autobahn/Twisted library) got there first, the link cannot
use asyncio at all; instead of failing it runs on roslibpy's Twisted transport too, on the one
process-wide reactor thread roslibpy starts (and never stops: a reactor cannot be restarted). A
link's ``close()`` then closes its connection only; the reactor thread stays for everybody.

roslibpy internals touched: none beyond its classes (``AutobahnRosBridgeClientFactory``,
``TwistedEventLoopManager``, the factory's ``connector``); ``stopTrying`` and ``setProtocolOptions``
are public Twisted / Autobahn API. ``tests/real/test_real_coexist.py`` runs this path in both orders.
"""

from __future__ import annotations

import threading
from typing import Any

from roslibpy.comm.comm_autobahn import AutobahnRosBridgeClientFactory, TwistedEventLoopManager
from twisted.internet import reactor

from pmk_nb.chair.link.transport.backoff import set_backoff, set_pings


class TwistedLinkFactory(AutobahnRosBridgeClientFactory):  # type: ignore[misc]  # roslibpy has no type hints: subclassing it is the seam
    """roslibpy's Twisted factory with the link's reconnect backoff and websocket pings."""

    def __init__(
        self,
        url: str,
        manager: TwistedEventLoopManager,
        *,
        initial_delay: float,
        max_delay: float,
        ping_interval: float,
        ping_timeout: float,
    ) -> None:
        super().__init__(url)
        self._manager = manager
        set_backoff(self, initial_delay, max_delay)
        self.delay = initial_delay  # Twisted's ReconnectingClientFactory already set it from its default
        set_pings(self, ping_interval, ping_timeout)

    def stop_reconnecting(self) -> None:
        """No further reconnect attempts (Twisted's public ``stopTrying``), on the reactor thread."""
        reactor.callFromThread(self.stopTrying)

    def loop_alive(self) -> bool:
        return bool(reactor.running)

    def abort(self, ros: Any, deadline_s: float) -> None:
        """Drop a socket still open or a connect attempt under way; the reactor keeps running."""
        done = threading.Event()

        def _abort() -> None:
            try:
                transport = getattr(ros.protocol, "transport", None)
                if transport is not None and getattr(transport, "connected", False):
                    transport.abortConnection()
                connector = self.connector
                if connector is not None and connector.state == "connecting":
                    connector.stopConnecting()
            finally:
                done.set()

        reactor.callFromThread(_abort)
        done.wait(max(0.05, deadline_s))


def start_loop(thread_name: str, timeout: float = 5.0) -> tuple[TwistedEventLoopManager, threading.Thread]:
    """roslibpy's reactor thread (started if needed; shared by every Twisted client in the process).

    ``thread_name`` is not applied: the thread belongs to the whole process, not to one link.
    """
    manager = TwistedEventLoopManager()
    manager.run()  # starts reactor.run in a daemon thread unless the reactor already runs
    box: list[threading.Thread] = []
    found = threading.Event()

    def _which() -> None:
        box.append(threading.current_thread())
        found.set()

    reactor.callFromThread(_which)
    if not found.wait(timeout):  # pragma: no cover - a running reactor answers at once
        raise RuntimeError(f"the Twisted reactor did not run ({thread_name})")
    return manager, box[0]
