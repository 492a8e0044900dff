"""MapsFolder.download against a real HTTP server on 127.0.0.1 (no mocks): every failure leaves the
folder exactly as it was, and the message names the cause."""

from __future__ import annotations

import socket
import threading
import time
from collections.abc import Iterator
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path

import pytest

from pmk_nb.errors import DownloadError, LibraryError
from pmk_nb.library.download import _describe_reason
from pmk_nb.library.folder import MapsFolder
from pmk_nb.progress import Progress
from tests.indoorgml_samples import HTML_PAGE, two_rooms

GOOD = two_rooms(("F1", "F2"))
SMALL_LIMIT = 64 * 1024


class _Handler(BaseHTTPRequestHandler):
    protocol_version = "HTTP/1.1"
    stop: threading.Event  # set on the class by the fixture
    requested: list[str]  # every request path, in order (set by the fixture)

    def log_message(self, format: str, *args: object) -> None:  # keep pytest output clean
        pass

    def _send(self, status: int, body: bytes, ctype: str = "application/xml", length: int | None = None) -> None:
        self.send_response(status)
        self.send_header("Content-Type", ctype)
        self.send_header("Content-Length", str(len(body) if length is None else length))
        self.send_header("Connection", "close")
        self.end_headers()
        self.wfile.write(body)
        self.wfile.flush()
        self.close_connection = True

    def do_GET(self) -> None:
        self.requested.append(self.path)
        path = self.path.split("?", 1)[0]
        if path == "/good.gml":
            self._send(200, GOOD)
        elif path == "/page.html":
            self._send(200, HTML_PAGE, "text/html")
        elif path == "/missing.gml":
            self._send(404, b"no such map", "text/plain")
        elif path == "/slow.gml":
            self.stop.wait(5.0)  # longer than the client's timeout; released at teardown
            self._send(200, GOOD)
        elif path == "/big.gml":  # declared too big: refused before reading
            self._send(200, GOOD + b" " * (SMALL_LIMIT * 2))
        elif path == "/big-chunked.gml":  # no Content-Length: the cap applies while reading
            self.send_response(200)
            self.send_header("Content-Type", "application/xml")
            self.send_header("Transfer-Encoding", "chunked")
            self.end_headers()
            chunk = b"<!--" + b"x" * 8000 + b"-->"
            for _ in range(3 * SMALL_LIMIT // len(chunk)):
                self.wfile.write(b"%x\r\n%s\r\n" % (len(chunk), chunk))
            self.wfile.write(b"0\r\n\r\n")
            self.close_connection = True
        elif path == "/lying.gml":  # promises more than it sends, then closes
            self._send(200, GOOD[:500], length=len(GOOD))
        elif path == "/understated.gml":  # declares less than it sends: the client stops early
            self._send(200, GOOD, length=300)
        elif path == "/truncated.gml":  # honest length, but the XML stops half-way
            self._send(200, GOOD[: len(GOOD) // 2])
        elif path == "/trickle.gml":  # a byte every 50 ms: never stalls, never finishes in time
            self.send_response(200)
            self.send_header("Content-Type", "application/xml")
            self.send_header("Content-Length", str(len(GOOD)))
            self.end_headers()
            for byte in GOOD[:100]:  # bounded: at most 5 s even if the client never gives up
                if self.stop.wait(0.05):
                    break
                self.wfile.write(bytes([byte]))
                self.wfile.flush()
            self.close_connection = True
        elif path == "/to-ftp":
            self.send_response(302)
            self.send_header("Location", "ftp://127.0.0.1/map.gml")
            self.send_header("Content-Length", "0")
            self.end_headers()
        elif path == "/to-good":
            self.send_response(302)
            self.send_header("Location", "/good.gml")
            self.send_header("Content-Length", "0")
            self.end_headers()
        else:
            self._send(500, b"unexpected", "text/plain")


class Server(str):
    """The base URL; ``requested`` lists the paths the server has seen."""

    requested: list[str]

    def __new__(cls, url: str, requested: list[str]) -> Server:
        obj = super().__new__(cls, url)
        obj.requested = requested
        return obj


class _QuietServer(ThreadingHTTPServer):
    daemon_threads = True

    def handle_error(self, request: object, client_address: object) -> None:
        pass  # clients that give up early (size cap, timeout) cause broken pipes here, on purpose


@pytest.fixture(scope="module")
def server() -> Iterator[Server]:
    stop = threading.Event()
    handler = type("Handler", (_Handler,), {"stop": stop, "requested": []})
    httpd = _QuietServer(("127.0.0.1", 0), handler)
    thread = threading.Thread(target=httpd.serve_forever, daemon=True)
    thread.start()
    try:
        yield Server(f"http://127.0.0.1:{httpd.server_address[1]}", handler.requested)
    finally:
        stop.set()
        httpd.shutdown()
        httpd.server_close()
        thread.join(5)


@pytest.fixture
def folder(tmp_path: Path) -> MapsFolder:
    folder = MapsFolder(tmp_path / "maps", allow_local=True)  # the server is on 127.0.0.1 (a lab's --allow-local)
    folder.root.mkdir()
    (folder.root / "keep.gml").write_bytes(two_rooms())
    (folder.root / "keep.yaml").write_text("image: keep.pgm\n")
    return folder


def snapshot(root: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in root.iterdir()}


def closed_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def test_download_good_map_with_progress(server: Server, folder: MapsFolder) -> None:
    seen: list[Progress] = []
    entry = folder.download(f"{server}/good.gml?probe=good", "clinic", progress=seen.append)
    assert "/good.gml?probe=good" in server.requested
    assert entry.source == folder.root / "clinic.gml"
    assert entry.source.read_bytes() == GOOD
    assert (seen[0].step, seen[0].fraction, seen[-1].fraction) == ("download", 0.0, 1.0)
    assert seen[-1].message == f"{len(GOOD)} bytes of {len(GOOD)} bytes"
    assert sorted(snapshot(folder.root)) == ["clinic.gml", "keep.gml", "keep.yaml"]


def test_download_follows_http_redirect(server: str, folder: MapsFolder) -> None:
    assert folder.download(f"{server}/to-good", "moved").source.read_bytes() == GOOD


def test_overwrite_refused_before_downloading_and_accepted_with_flag(server: Server, folder: MapsFolder) -> None:
    before = snapshot(folder.root)
    with pytest.raises(LibraryError, match="map 'keep' already exists; pass overwrite=True"):
        folder.download(f"{server}/good.gml?probe=refused", "keep")
    assert "/good.gml?probe=refused" not in server.requested  # refused before any request
    assert snapshot(folder.root) == before
    entry = folder.download(f"{server}/good.gml", "keep", overwrite=True)
    assert entry.source.read_bytes() == GOOD
    assert (folder.root / "keep.yaml").read_text() == "image: keep.pgm\n"


@pytest.mark.slow
@pytest.mark.parametrize(
    ("path", "kwargs", "message"),
    [
        ("/page.html", {}, "not IndoorGML.*web page"),
        ("/missing.gml", {}, "HTTP 404 Not Found; check the URL"),
        ("/slow.gml", {"timeout": 0.3}, "timed out"),
        ("/big.gml", {"max_bytes": SMALL_LIMIT}, "refused: the file is .* more than the limit of 65536 bytes"),
        ("/big-chunked.gml", {"max_bytes": SMALL_LIMIT}, "aborted: more than the limit"),
        ("/lying.gml", {}, f"incomplete: the connection closed after 500 of {len(GOOD)} bytes"),
        ("/understated.gml", {}, "not a well-formed XML"),
        ("/truncated.gml", {}, "not a well-formed XML"),
        ("/to-ftp", {}, "redirects to 'ftp://"),
    ],
)
def test_download_failures_leave_folder_untouched(
    server: str, folder: MapsFolder, path: str, kwargs: dict[str, float], message: str
) -> None:
    before = snapshot(folder.root)
    for name, overwrite in (("new", False), ("keep", True)):
        with pytest.raises(LibraryError, match=message):
            folder.download(f"{server}{path}", name, overwrite=overwrite, **kwargs)  # type: ignore[arg-type]
        assert snapshot(folder.root) == before


@pytest.mark.slow
@pytest.mark.realtime  # a real trickling server against the download's real deadline
def test_overall_deadline_cuts_off_a_trickling_server(server: str, folder: MapsFolder) -> None:
    before = snapshot(folder.root)
    url = f"{server}/trickle.gml"
    started = time.monotonic()
    with pytest.raises(DownloadError, match="deadline") as info:
        folder.download(url, "slowpoke", timeout=2.0, deadline=0.5)
    elapsed = time.monotonic() - started
    assert info.value.url == url and info.value.hint
    assert 0.5 <= elapsed < 2.0  # the per-read timeout alone would never fire: bytes keep coming
    assert snapshot(folder.root) == before


def test_connection_refused(folder: MapsFolder) -> None:
    before = snapshot(folder.root)
    port = closed_port()
    with pytest.raises(LibraryError, match=f"connection to 127.0.0.1:{port} refused"):
        folder.download(f"http://127.0.0.1:{port}/map.gml", "new", timeout=2)
    assert snapshot(folder.root) == before


@pytest.mark.parametrize(
    ("url", "message"),
    [
        ("file:///etc/passwd", "only http:// and https://"),
        ("ftp://example.org/map.gml", "only http:// and https://"),
        ("example.org/map.gml", "no scheme"),
        ("http:///map.gml", "no host name"),
        ("http://127.0.0.1:99999/x", "not a valid URL"),
    ],
)
def test_bad_urls_are_refused_without_network(folder: MapsFolder, url: str, message: str) -> None:
    before = snapshot(folder.root)
    with pytest.raises(LibraryError, match=message):
        folder.download(url, "new")
    assert snapshot(folder.root) == before


def test_bad_name_refused_before_download(folder: MapsFolder) -> None:
    with pytest.raises(LibraryError, match="path separator"):
        folder.download("http://127.0.0.1:1/x.gml", "../x")


def test_dns_failure_message_names_the_host() -> None:
    # resolving a real name would leave the loopback; the message mapping is checked directly
    reason = socket.gaierror(socket.EAI_NONAME, "Name or service not known")
    assert "cannot resolve host 'maps.example' (DNS failure)" in _describe_reason(reason, "maps.example:8080", 30)
