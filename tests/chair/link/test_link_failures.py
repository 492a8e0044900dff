"""Why a chair cannot be reached: each failure gets its own reason, within the timeout."""

from __future__ import annotations

import http.server
import socket
import threading
import time
from collections.abc import Iterator

import pytest
from websockets.sync.server import ServerConnection, serve

from pmk_nb.chair.link.client import ChairLink
from pmk_nb.errors import ChairLinkError


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def _link_threads() -> list[str]:
    return [t.name for t in threading.enumerate() if t.name.startswith("pmk-link-") and t.is_alive()]


@pytest.fixture
def silent_tcp() -> Iterator[int]:
    """Accepts TCP connections and never says a word (a hung server, a black-holing proxy)."""
    srv = socket.socket()
    srv.bind(("127.0.0.1", 0))
    srv.listen(8)
    yield srv.getsockname()[1]
    srv.close()


@pytest.fixture
def http_port() -> Iterator[int]:
    class Quiet(http.server.BaseHTTPRequestHandler):
        def do_GET(self) -> None:
            body = b"<html>not rosbridge</html>"
            self.send_response(200)
            self.send_header("Content-Length", str(len(body)))
            self.end_headers()
            self.wfile.write(body)

        def log_message(self, *args: object) -> None:
            pass

    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), Quiet)
    server.protocol_version = "HTTP/1.1"
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    yield server.server_address[1]
    server.shutdown()
    server.server_close()


def _ws_server(handler):  # type: ignore[no-untyped-def]
    server = serve(handler, "127.0.0.1", 0)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    return server


@pytest.fixture
def echo_ws() -> Iterator[int]:
    """A websocket server that is not rosbridge: it echoes whatever it gets."""

    def echo(ws: ServerConnection) -> None:
        for msg in ws:
            ws.send(msg)

    server = _ws_server(echo)
    yield server.socket.getsockname()[1]
    server.shutdown()


@pytest.fixture
def silent_ws() -> Iterator[int]:
    """A websocket server that accepts the handshake and never answers."""

    def silent(ws: ServerConnection) -> None:
        for _msg in ws:
            pass

    server = _ws_server(silent)
    yield server.socket.getsockname()[1]
    server.shutdown()


def _check(host: str, port: int, timeout: float, starts: str) -> None:
    before = set(_link_threads())
    link = ChairLink(host, port)
    t0 = time.monotonic()
    report = link.test_connection(timeout=timeout)
    took = time.monotonic() - t0
    assert not report.ok
    assert report.reason.startswith(starts), report.reason
    assert report.map_info is None
    assert took < timeout + 1.0  # never hangs beyond the timeout
    assert report.elapsed == pytest.approx(took, abs=0.2)
    with pytest.raises(ChairLinkError, match=starts):
        link.connect(timeout=timeout)
    assert link.state.value == "disconnected"
    link.close()
    assert set(_link_threads()) <= before  # a failed connect leaves no thread behind


@pytest.mark.realtime  # a real socket: the connect's real timeout is the subject
def test_connection_refused() -> None:
    _check("127.0.0.1", _free_port(), 3.0, "connection refused")


@pytest.mark.realtime  # a real socket: the connect's real timeout is the subject
def test_host_unknown() -> None:
    _check("no-such-host.invalid", 9090, 3.0, "host unknown")


@pytest.mark.slow
@pytest.mark.realtime  # a real socket: the connect's real timeout is the subject
def test_timed_out_when_the_server_never_answers_the_handshake(silent_tcp: int) -> None:
    _check("127.0.0.1", silent_tcp, 1.5, "timed out")


@pytest.mark.slow
@pytest.mark.realtime  # a real socket: the connect's real timeout is the subject
def test_plain_http_server_is_not_rosbridge(http_port: int) -> None:
    _check("127.0.0.1", http_port, 3.0, "not a rosbridge server")


@pytest.mark.realtime  # a real socket: the connect's real timeout is the subject
def test_websocket_echo_server_is_not_rosbridge(echo_ws: int) -> None:
    _check("127.0.0.1", echo_ws, 3.0, "not a rosbridge server")


@pytest.mark.slow
@pytest.mark.realtime  # a real socket: the connect's real timeout is the subject
def test_silent_websocket_server_times_out(silent_ws: int) -> None:
    """Silence cannot be told from a busy rosbridge (issue 9, fault 6): "timed out", both causes named."""
    _check("127.0.0.1", silent_ws, 1.5, "timed out")


def test_service_calls_need_a_connection() -> None:
    link = ChairLink("127.0.0.1", _free_port())
    with pytest.raises(ChairLinkError, match="Not connected"):
        link.services()
    assert link.publish_cmd_vel(0.5, 0.0) is False  # nothing queued for later
    assert link.send_goal(1.0, 2.0, 0.0) is False
    assert link.latest_odom() is None and link.latest_scan() is None and link.latest_pose() is None


def test_bad_configuration_is_rejected() -> None:
    with pytest.raises(ValueError, match="pose_topic"):
        ChairLink("127.0.0.1", 9090, pose_source="pose_topic")
    with pytest.raises(ValueError, match="pose_source"):
        ChairLink("127.0.0.1", 9090, pose_source="gps")  # type: ignore[arg-type]
