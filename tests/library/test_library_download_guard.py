"""Issue 30 (SSRF): downloads reach only public addresses unless a lab allows local ones.

Only loopback traffic is ever sent: names are resolved by a fake ``getaddrinfo``, and the one public
address used is routed to a loopback server by the connect seam (``netguard.connect``); every
non-public address must be refused BEFORE any connection, which the seam records.
"""

from __future__ import annotations

import socket
import threading
from collections.abc import Iterator
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path
from typing import Any, ClassVar

import pytest

from pmk_nb.errors import AddressRefused, DownloadError
from pmk_nb.library import netguard
from pmk_nb.library.folder import MapsFolder
from tests.indoorgml_samples import two_rooms

PUBLIC = "93.184.215.14"  # a global address; its traffic is routed to the loopback server below


class _Handler(BaseHTTPRequestHandler):
    redirects: ClassVar[dict[str, str]] = {}
    seen: ClassVar[list[str]] = []

    def log_message(self, format: str, *args: object) -> None:
        pass

    def do_GET(self) -> None:
        self.seen.append(self.path)
        target = self.redirects.get(self.path)
        body = b"" if target else two_rooms()
        self.send_response(302 if target else 200)
        if target:
            self.send_header("Location", target)
        self.send_header("Content-Length", str(len(body)))
        self.send_header("Connection", "close")
        self.end_headers()
        self.wfile.write(body)


@pytest.fixture
def port() -> Iterator[int]:
    _Handler.seen = []
    httpd = ThreadingHTTPServer(("127.0.0.1", 0), _Handler)
    thread = threading.Thread(target=httpd.serve_forever, daemon=True)
    thread.start()
    try:
        yield int(httpd.server_address[1])
    finally:
        httpd.shutdown()
        httpd.server_close()
        thread.join(5)


@pytest.fixture
def net(monkeypatch: pytest.MonkeyPatch, port: int) -> list[Any]:
    """Fake DNS for *.example names; connections to PUBLIC go to the loopback server; returns the connects."""
    names = {"maps.example": [PUBLIC], "lan.example": ["192.168.1.20"], "mixed.example": [PUBLIC, "10.0.0.5"]}
    real_getaddrinfo = socket.getaddrinfo

    def getaddrinfo(host: str, port_: int, *args: Any, **kwargs: Any) -> list[Any]:
        if host not in names:
            return real_getaddrinfo(host, port_, *args, **kwargs)
        return [(socket.AF_INET, socket.SOCK_STREAM, 6, "", (a, port_)) for a in names[host]]

    connects: list[Any] = []

    def connect(sock: socket.socket, sockaddr: Any) -> None:
        connects.append(sockaddr[0])
        assert sockaddr[0] in (PUBLIC, "127.0.0.1", "::1"), f"traffic to {sockaddr} must never be sent"
        sock.connect(("127.0.0.1", port) if sockaddr[0] == PUBLIC else sockaddr)

    monkeypatch.setattr(socket, "getaddrinfo", getaddrinfo)
    monkeypatch.setattr(netguard, "connect", connect)
    return connects


@pytest.mark.parametrize(
    ("address", "reason"),
    [
        ("127.0.0.1", "loopback"),
        ("::1", "loopback"),
        ("10.1.2.3", "private"),
        ("192.168.1.1", "private"),
        ("172.16.0.1", "private"),
        ("169.254.169.254", "link-local"),
        ("fe80::1%eth0", "link-local"),
        ("fc00::1", "private"),
        ("::ffff:127.0.0.1", "IPv4-mapped loopback"),
        ("::ffff:10.0.0.1", "IPv4-mapped private"),
        ("2002:c0a8:0101::1", "6to4 private"),
        ("64:ff9b::7f00:1", "NAT64 loopback"),
        ("0.0.0.0", "unspecified"),
        ("::", "unspecified"),
        ("224.0.0.1", "multicast"),
        ("ff02::1", "multicast"),
        ("100.64.1.1", "carrier-grade NAT"),
        ("240.0.0.1", "reserved"),
    ],
)
def test_non_public_addresses_are_named(address: str, reason: str) -> None:
    assert reason in (netguard.refusal(address) or "")


@pytest.mark.parametrize(
    "address", [PUBLIC, "8.8.8.8", "2606:4700:4700::1111", "::ffff:8.8.8.8", "2002:0808:0808::1", "64:ff9b::808:808"]
)
def test_public_addresses_pass(address: str) -> None:
    assert netguard.refusal(address) is None


def _folder(tmp_path: Path, **kwargs: Any) -> MapsFolder:
    return MapsFolder(tmp_path / "maps", **kwargs)


def test_loopback_is_refused_by_default_and_allowed_for_labs(tmp_path: Path, port: int) -> None:
    url = f"http://127.0.0.1:{port}/plan.gml"
    with pytest.raises(AddressRefused) as info:
        _folder(tmp_path).download(url, "inside")
    err = info.value
    assert (err.host, err.address, err.reason, err.url) == ("127.0.0.1", "127.0.0.1", "loopback address", url)
    assert "--allow-local" in str(err) and _Handler.seen == []  # refused before any request
    assert not (tmp_path / "maps" / "inside.gml").exists()
    assert _folder(tmp_path, allow_local=True).download(url, "inside").source.read_bytes() == two_rooms()


def test_ipv6_loopback_is_refused_without_a_connection(tmp_path: Path, net: list[Any]) -> None:
    with pytest.raises(AddressRefused) as info:
        _folder(tmp_path).download("http://[::1]:9/plan.gml", "inside")
    assert (info.value.address, info.value.reason) == ("::1", "loopback address") and net == []


@pytest.mark.parametrize(("host", "address"), [("lan.example", "192.168.1.20"), ("mixed.example", "10.0.0.5")])
def test_a_name_resolving_to_a_lan_address_is_refused(tmp_path: Path, net: list[Any], host: str, address: str) -> None:
    """Every resolved address is checked: one LAN address among public ones is enough to refuse."""
    with pytest.raises(AddressRefused) as info:
        _folder(tmp_path).download(f"http://{host}:8080/plan.gml", "lan")
    assert (info.value.host, info.value.address, info.value.reason) == (host, address, "private (LAN) address")
    assert net == []  # nothing was connected to


def test_a_public_name_is_fetched_from_the_checked_address(tmp_path: Path, net: list[Any], port: int) -> None:
    entry = _folder(tmp_path).download(f"http://maps.example:{port}/plan.gml", "public")
    assert entry.source.read_bytes() == two_rooms() and net == [PUBLIC]


@pytest.mark.parametrize(
    ("target", "address"),
    [("http://lan.example:{port}/plan.gml", "192.168.1.20"), ("http://127.0.0.1:{port}/plan.gml", "127.0.0.1")],
)
def test_a_redirect_to_a_local_address_is_refused_before_connecting(
    tmp_path: Path, net: list[Any], port: int, target: str, address: str
) -> None:
    _Handler.redirects = {"/moved": target.format(port=port)}
    with pytest.raises(AddressRefused) as info:
        _folder(tmp_path).download(f"http://maps.example:{port}/moved", "moved")
    assert info.value.address == address and info.value.url == target.format(port=port)
    assert net == [PUBLIC] and _Handler.seen == ["/moved"]  # the redirect's target was never reached
    assert isinstance(info.value, DownloadError)


def test_pmk_dashboard_allow_local_reaches_the_kernels_maps_folder(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    """``pmk dashboard --allow-local`` -> the kernel's environment -> MapsFolder (the Maps screen's)."""
    from pmk_nb.cli import dashboard, main

    seen: list[dict[str, str]] = []
    monkeypatch.setattr(dashboard, "preflight", lambda args, env, kiosk=False: None)
    monkeypatch.setattr(dashboard, "serve_dashboard", lambda args, env, tmp, token, tls=None: seen.append(env) or 0)
    for argv, expected in ((["--allow-local"], True), ([], False)):
        assert main(["dashboard", "--port", "8866", *argv]) == 0
        monkeypatch.setenv(netguard.ALLOW_LOCAL_ENV, seen[-1][netguard.ALLOW_LOCAL_ENV])
        assert _folder(tmp_path).allow_local is expected
