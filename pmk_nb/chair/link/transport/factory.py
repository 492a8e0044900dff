"""roslibpy's asyncio connection factory, bound to one link's private event loop.

Importing this module imports ``roslibpy.comm.comm_asyncio``, which binds Autobahn's txaio layer to
asyncio for the whole process; :mod:`pmk_nb.chair.link.transport.framework` therefore imports it only when a
link opens its first connection.

roslibpy internals are touched only through :mod:`pmk_nb.seams.roslibpy_seam` (``FactorySeam``: a
private loop manager, the reconnect switch, the connect attempt; pinned and checked by
``tests/seams/test_roslibpy_seam.py``). A wss link makes its own connect attempt: roslibpy's with the link's
TLS context (:mod:`pmk_nb.chair.link.transport.tls`), and a certificate refused ends the reconnects. Its
protocol class checks the certificate in ``connection_made``, after the TLS handshake and before
Autobahn sends the websocket's first byte.
"""

from __future__ import annotations

import asyncio
import ssl
import threading
from typing import Any

from roslibpy.comm.comm_asyncio import (
    AsyncioEventLoopManager,
    AsyncioRosBridgeClientFactory,
    AsyncioRosBridgeProtocol,
)

from pmk_nb.chair.link.transport.backoff import set_backoff, set_pings
from pmk_nb.chair.link.transport.tls import ChairTls, check_peer, handshake_failure
from pmk_nb.errors import ChairCertificateError
from pmk_nb.seams import FactorySeam


class CheckedProtocol(AsyncioRosBridgeProtocol):  # type: ignore[misc]  # roslibpy has no type hints: subclassing it is the seam
    """roslibpy's protocol; on a wss link the chair's certificate is checked before the websocket starts."""

    refused = False

    def connection_made(self, transport: Any) -> None:
        try:
            self.factory.check_certificate(transport)
        except ChairCertificateError as err:
            self.refused = True
            transport.abort()
            self.factory.refuse(err)
            return
        super().connection_made(transport)

    def connection_lost(self, exc: Exception | None) -> None:
        if not self.refused:  # Autobahn never started on a refused socket
            super().connection_lost(exc)


class LinkFactory(FactorySeam, AsyncioRosBridgeClientFactory):  # type: ignore[misc]  # roslibpy has no type hints: subclassing it is the seam
    """roslibpy's asyncio factory on a private loop, with link-specific reconnect backoff (and TLS trust)."""

    protocol = CheckedProtocol

    def __init__(
        self,
        url: str,
        manager: AsyncioEventLoopManager,
        *,
        initial_delay: float,
        max_delay: float,
        ping_interval: float,
        ping_timeout: float,
        tls: ChairTls | None = None,
        chair: tuple[str, int] = ("", 0),
    ) -> None:
        self.link_manager = manager
        self.tls, self.chair = tls, chair
        self.refusal: ChairCertificateError | None = None
        # set before the constructor, which derives the first reconnect delay from them
        set_backoff(self, initial_delay, max_delay)
        super().__init__(url, loop=manager.loop)
        set_pings(self, ping_interval, ping_timeout)

    def check_certificate(self, transport: Any) -> None:
        """On the loop, right after the TLS handshake: raises a ChairCertificateError when not trusted."""
        if self.tls is None:
            return
        tls_object = transport.get_extra_info("ssl_object")
        der = tls_object.getpeercert(binary_form=True) if tls_object is not None else None
        check_peer(self.tls, *self.chair, der)

    def refuse(self, err: ChairCertificateError) -> None:
        """A certificate not trusted: keep why, stop reconnecting, tell the link (event "refused")."""
        self.refusal = err
        self.stop_reconnecting()
        self.emit("refused", err)

    async def connect_attempt(self) -> bool:
        """A wss link: roslibpy's connect attempt with the link's TLS context (see the module
        docstring); a plain link: False, roslibpy's own attempt."""
        if self.tls is None:
            return False
        loop = self.manager.loop
        if loop is None or loop.is_closed():
            return True
        try:
            await loop.create_connection(self, self.host, self.port, ssl=self.tls.context())
        except asyncio.CancelledError:
            raise
        except ssl.SSLError as err:
            refused = handshake_failure(self.tls, *self.chair, err)
            if refused is not None:
                self.refuse(refused)
            else:
                self.schedule_reconnect()
        except Exception:  # as roslibpy: any other connect error means a retry
            self.schedule_reconnect()
        return True

    def loop_alive(self) -> bool:
        loop = self.link_manager.loop
        return loop is not None and not loop.is_closed()

    def abort(self, ros: Any, deadline_s: float) -> None:
        """Drop a socket still open, cancel pending connects, then stop and join the private loop."""
        loop = self.link_manager.loop
        if loop is not None and not loop.is_closed():
            done = threading.Event()

            def _call() -> None:
                try:
                    _abort_and_cancel(ros)
                finally:
                    # One more loop turn so cancelled tasks can unwind before the loop stops.
                    loop.call_later(0.02, done.set)

            loop.call_soon_threadsafe(_call)
            done.wait(max(0.05, deadline_s))
        self.link_manager.terminate()


def _abort_and_cancel(ros: Any) -> None:
    """On the loop: drop a socket still open and cancel pending connect attempts."""
    transport = getattr(ros.protocol, "transport", None)
    if transport is not None and not transport.is_closing():
        transport.abort()
    for task in asyncio.all_tasks():
        task.cancel()


def start_private_loop(thread_name: str, timeout: float = 5.0) -> tuple[AsyncioEventLoopManager, threading.Thread]:
    """A running roslibpy loop manager of our own, its thread renamed to ``thread_name``."""
    manager = AsyncioEventLoopManager()
    manager.run()
    loop = manager.loop
    if loop is None:  # pragma: no cover - run() waits for the loop
        raise RuntimeError("roslibpy event loop did not start")
    box: list[threading.Thread] = []
    named = threading.Event()

    def _name_thread() -> None:
        thread = threading.current_thread()
        thread.name = thread_name
        box.append(thread)
        named.set()

    loop.call_soon_threadsafe(_name_thread)
    if not named.wait(timeout):  # pragma: no cover - a fresh loop runs callbacks at once
        manager.terminate()
        raise RuntimeError("roslibpy event loop did not run")
    return manager, box[0]
