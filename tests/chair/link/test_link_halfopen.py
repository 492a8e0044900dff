"""Half-open sockets: the chair drops off the network without closing the TCP connection.

rosbridge never reports this, so the link must notice (stale data, then websocket pings that get
no answer) and reconnect by itself once the chair is reachable again. A TCP proxy between link and
simulator plays the network: "frozen" it forwards nothing and closes nothing.
"""

from __future__ import annotations

import select
import socket
import threading
from collections.abc import Iterator

import pytest

from pmk_nb.chair.link.client import ChairLink, LinkState
from tests.fixtures_sim import wait_until


class FreezableProxy:
    """Forwards 127.0.0.1:port to an upstream port; ``frozen`` black-holes every connection."""

    def __init__(self, upstream: int) -> None:
        self.upstream = upstream
        self.frozen = threading.Event()
        self._closed = threading.Event()
        self._server = socket.socket()
        self._server.bind(("127.0.0.1", 0))
        self._server.listen(16)
        self._server.settimeout(0.1)
        self.port = self._server.getsockname()[1]
        self._threads = [threading.Thread(target=self._accept, daemon=True)]
        self._threads[0].start()

    def _accept(self) -> None:
        while not self._closed.is_set():
            try:
                client, _ = self._server.accept()
            except (TimeoutError, OSError):
                continue
            upstream = socket.create_connection(("127.0.0.1", self.upstream))
            thread = threading.Thread(target=self._pump, args=(client, upstream), daemon=True)
            thread.start()
            self._threads.append(thread)

    def _pump(self, a: socket.socket, b: socket.socket) -> None:
        peers = {a: b, b: a}
        try:
            while not self._closed.is_set():
                if self.frozen.is_set():
                    self._closed.wait(0.02)  # nothing moves, nothing closes
                    continue
                readable, _, _ = select.select(list(peers), [], [], 0.05)
                for sock in readable:
                    data = sock.recv(65536)
                    if not data:
                        return
                    peers[sock].sendall(data)
        except OSError:
            return
        finally:
            a.close()
            b.close()

    def close(self) -> None:
        self._closed.set()
        self._server.close()
        for thread in self._threads:
            thread.join(2.0)


@pytest.fixture
def proxy(sim_chair) -> Iterator[FreezableProxy]:
    p = FreezableProxy(sim_chair.port)
    yield p
    p.close()


@pytest.mark.slow
def test_half_open_socket_goes_stale_then_reconnects(proxy: FreezableProxy) -> None:
    link = ChairLink(
        "127.0.0.1",
        proxy.port,
        stale_after=0.3,
        ping_interval=0.5,
        ping_timeout=1.0,
        reconnect_initial=0.2,
        reconnect_max=0.5,
    )
    seen: list[LinkState] = []
    link.on_state_change(seen.append)
    try:
        link.connect()
        link.start_streams()
        assert wait_until(lambda: link.state is LinkState.CONNECTED and link.latest_odom() is not None, 5.0)
        proxy.frozen.set()
        assert wait_until(lambda: link.state is LinkState.STALE, 2.0)
        # the unanswered websocket ping makes the link drop the dead socket and retry
        assert wait_until(lambda: link.state is LinkState.CONNECTING, 5.0)
        proxy.frozen.clear()
        assert wait_until(lambda: link.state is LinkState.CONNECTED, 10.0)
        count = link.message_counts["odom"]
        assert wait_until(lambda: link.message_counts["odom"] > count + 5, 5.0)
        assert wait_until(lambda: seen[-1:] == [LinkState.CONNECTED], 1.0)
        assert seen.index(LinkState.STALE) < seen.index(LinkState.CONNECTING)
    finally:
        link.close()
