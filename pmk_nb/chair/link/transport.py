"""A roslibpy ``Ros`` on its own asyncio loop thread, so one link can be closed and reopened.

roslibpy 2.1's asyncio transport shares one process-wide loop between all ``Ros`` objects, and
``terminate()`` stops it for everyone (the Twisted transport cannot even restart its reactor). A
chair link must release its thread on ``close()`` and connect again later in the same kernel, and
two chairs must not share one I/O thread. So each link builds its factory on a private
:class:`AsyncioEventLoopManager`; the rest of roslibpy (topics, services, reconnect) is unchanged.

The factory below re-does the few lines of ``AsyncioRosBridgeClientFactory.__init__`` that bind
the shared loop; ``tests/test_link.py`` exercises this against the simulator so a roslibpy change
that breaks it fails loudly.
"""

from __future__ import annotations

import asyncio
import threading
import time
from typing import Any

import roslibpy
from roslibpy.comm.comm_asyncio import AsyncioEventLoopManager, AsyncioRosBridgeClientFactory


class _LinkFactory(AsyncioRosBridgeClientFactory):
    """roslibpy's asyncio factory bound to a private loop, with link-specific reconnect backoff."""

    def __init__(
        self,
        url: str,
        manager: AsyncioEventLoopManager,
        *,
        initial_delay: float,
        max_delay: float,
        ping_interval: float,
        ping_timeout: float,
    ) -> None:
        # Skip AsyncioRosBridgeClientFactory.__init__ (it starts the shared loop) but run the
        # rest of the MRO (EventEmitterMixin, autobahn's WebSocketClientFactory) on our loop.
        super(AsyncioRosBridgeClientFactory, self).__init__(url, loop=manager.loop)
        self._manager = manager
        self._proto = None
        self._proto_lock = threading.Lock()
        self._stop = False
        self._retry_count = 0
        # Instance attributes shadow the class-wide roslibpy defaults (1 s x 2.7 up to an hour),
        # which would leave a chair that rebooted disconnected for minutes.
        self.initialDelay = initial_delay
        self.maxDelay = max_delay
        self.factor = 2.0
        self.jitter = 0.1
        self._reconnect_delay = initial_delay
        # Websocket pings notice half-open sockets (chair left the Wi-Fi) that TCP would keep
        # "open" for many minutes; rosbridge itself never tells. Each ping must get its pong:
        # autobahn's "any traffic counts" mode logs a warning for every late pong while streaming.
        self.setProtocolOptions(
            closeHandshakeTimeout=1,
            openHandshakeTimeout=max(2.0, ping_timeout),
            autoPingInterval=ping_interval,
            autoPingTimeout=ping_timeout,
            autoPingRestartOnAnyTraffic=False,
        )
        self._configure_compression()


class LinkRos(roslibpy.Ros):
    """``roslibpy.Ros`` that owns its event-loop thread.

    Use :meth:`shutdown` (not ``terminate``) to close the socket and stop the thread.
    """

    def __init__(
        self,
        host: str,
        port: int,
        *,
        thread_name: str,
        initial_delay: float = 0.5,
        max_delay: float = 10.0,
        ping_interval: float = 5.0,
        ping_timeout: float = 5.0,
    ) -> None:
        # Deliberately not calling roslibpy.Ros.__init__: it would pick the shared factory.
        self._id_counter = 0
        self.manager = AsyncioEventLoopManager()
        self.manager.run()
        if self.manager.loop is None:  # pragma: no cover - run() waits for the loop
            raise RuntimeError("roslibpy event loop did not start")
        self.manager._thread.name = thread_name  # type: ignore[union-attr]
        url = _LinkFactory.create_url(host, port, False)
        self.factory = _LinkFactory(
            url,
            self.manager,
            initial_delay=initial_delay,
            max_delay=max_delay,
            ping_interval=ping_interval,
            ping_timeout=ping_timeout,
        )
        self.is_connecting = False

    @property
    def loop_thread(self) -> threading.Thread | None:
        return self.manager._thread

    def shutdown(self, timeout: float = 2.0) -> None:
        """Stop reconnecting, close the websocket, stop and join the loop thread (bounded by ``timeout``)."""
        deadline = time.monotonic() + timeout
        factory: Any = self.factory
        factory._stop = True  # no reconnect after the close below
        loop = self.manager.loop
        if loop is None or loop.is_closed():
            return
        proto = factory._proto
        if proto is not None:
            closed = threading.Event()
            factory.once("close", lambda *_: closed.set())

            def _close() -> None:
                proto._manual_disconnect = True
                proto.sendClose()

            loop.call_soon_threadsafe(_close)
            # A half-open peer never answers the close handshake: do not wait for it long.
            closed.wait(max(0.0, min(deadline - time.monotonic(), timeout / 2)))
        self._run_on_loop(_abort_and_cancel, deadline)
        self.manager.terminate()

    def _run_on_loop(self, fn: Any, deadline: float) -> None:
        loop = self.manager.loop
        if loop is None or loop.is_closed():
            return
        done = threading.Event()

        def _call() -> None:
            try:
                fn(self)
            finally:
                # One more loop turn so cancelled tasks can unwind before the loop stops.
                loop.call_later(0.02, done.set)

        loop.call_soon_threadsafe(_call)
        done.wait(max(0.05, deadline - time.monotonic()))


def _abort_and_cancel(ros: LinkRos) -> None:
    """On the loop: drop a socket still open and cancel pending connect attempts."""
    proto: Any = ros.factory._proto
    transport = getattr(proto, "transport", None)
    if transport is not None and not transport.is_closing():
        transport.abort()
    for task in asyncio.all_tasks():
        task.cancel()
