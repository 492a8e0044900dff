"""The dashboard server's guards (issue 30, findings 2 and 4): unit tests of pmk_nb.serve.voila_guard and
the served config, then a real Voilà started as ``pmk dashboard`` starts it, attacked over HTTP.

Host and Origin: a page request for ``Host: evil.example`` was served, and a kernel websocket from a
rebinding page (Host and Origin ``evil.example``) or with the token and a foreign Origin was
accepted.  Kernel sockets: a second websocket to a page's kernel was accepted, in the legacy protocol
too.  A kiosk served on loopback needed no token.
"""

from __future__ import annotations

import argparse
import logging
import os
import re
import socket
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import httpx
import psutil
import pytest
from websockets.exceptions import InvalidStatus
from websockets.sync.client import connect

from pmk_nb.serve.procs import free_port, stop_process, wait_for_port
from pmk_nb.serve.serving import server_names
from pmk_nb.serve.voila import preflight, server_config, voila_command, write_dashboard_notebook
from pmk_nb.serve.voila_guard import (
    POLICY_VIOLATION,
    V1_PROTOCOL,
    OutputBudget,
    PageChannelConnection,
    host_allowed,
    is_own_address,
    request_host,
)
from tests.page_probes import rss_mb, wait_until
from tests.raw_websocket import RawWebSocket

# --- units -----------------------------------------------------------------------------------------


def test_request_host_drops_port_brackets_and_case() -> None:
    assert request_host("Evil.Example:8866") == "evil.example"
    assert request_host("[::1]:8866") == "::1"
    assert request_host("127.0.0.1") == "127.0.0.1"
    assert request_host("") == ""


def test_loopback_serves_loopback_names_only() -> None:
    for host in ("localhost", "127.0.0.1", "127.0.0.2", "::1"):
        assert host_allowed(host, "127.0.0.1", []), host
    for host in ("evil.example", "", "localhost.evil.example", "8.8.8.8", "0.0.0.0"):
        assert not host_allowed(host, "127.0.0.1", []), host


def test_lan_serving_also_allows_the_machines_names_and_addresses() -> None:
    assert host_allowed("tablet-host", "0.0.0.0", ["tablet-host"])
    assert host_allowed("192.0.2.7", "192.0.2.7", [])  # the address it was told to listen on
    assert not host_allowed("evil.example", "0.0.0.0", ["tablet-host"])
    assert not host_allowed("192.0.2.7", "0.0.0.0", [])  # TEST-NET: not an address of this machine
    assert is_own_address("127.0.0.1") and not is_own_address("192.0.2.7") and not is_own_address("name")
    assert socket.gethostname().lower() in server_names("0.0.0.0") and server_names("127.0.0.1") == []


def test_output_budget_stops_queueing_past_its_limit() -> None:
    budget = OutputBudget(limit=1000)
    budget.queued(600)
    assert not budget.over()
    budget.queued(600)
    assert budget.over()
    budget.sent(600)
    assert not budget.over() and budget.unsent == 600
    budget.sent(10_000)
    assert budget.unsent == 0


def test_the_served_config_plugs_in_both_guards() -> None:
    config = server_config("t" * 20, "127.0.0.1")
    voila = config["Voila"]
    assert isinstance(voila, dict)
    assert voila["identity_provider_class"].endswith("HostCheckingIdentityProvider")
    assert voila["kernel_websocket_connection_class"].endswith("PageChannelConnection")
    assert voila["tornado_settings"]["allow_remote_access"] is False
    lan = server_config("t" * 20, "0.0.0.0")
    assert "allow_remote_access" not in lan["Voila"]["tornado_settings"]  # type: ignore[index]


def test_a_kiosk_gets_a_token_on_loopback_too() -> None:
    args = argparse.Namespace(token=None, ip="127.0.0.1", port=free_port())
    assert preflight(args, {}) is None
    token = preflight(args, {}, kiosk=True)
    assert token and len(token) >= 16


class _Handler:
    """A websocket handler as the guard sees it: its protocol (None once the server closed it), close()."""

    def __init__(self, *, open_: bool = True, closing: bool = False) -> None:
        self.ws_connection = SimpleNamespace(is_closing=lambda: closing) if open_ else None
        self.selected_subprotocol = V1_PROTOCOL
        self.closed: list[tuple[int, str]] = []

    def close(self, code: int, reason: str) -> None:
        self.closed.append((code, reason))


class _Connection(PageChannelConnection):
    """The guard over a stand-in handler, without a kernel behind it."""

    websocket_handler: Any = None  # plain attribute: the stand-in is no tornado handler
    kernel_id = "k"
    multi_kernel_manager = SimpleNamespace(log=logging.getLogger("test"))


def _connection(handler: _Handler, *, admitted: bool = True) -> PageChannelConnection:
    conn = _Connection()
    conn.websocket_handler = handler
    conn._admitted = admitted
    return conn


def test_a_closed_closing_or_unadmitted_socket_drops_frames_and_a_malformed_frame_closes_it() -> None:
    malformed = (1 << 24).to_bytes(8, "little") + b"\0" * 60
    for handler, admitted in ((_Handler(open_=False), True), (_Handler(closing=True), True), (_Handler(), False)):
        conn = _connection(handler, admitted=admitted)
        conn.handle_incoming_message(malformed)  # type: ignore[arg-type]
        assert handler.closed == []  # dropped unread: not even judged malformed
    handler = _Handler()
    conn = _connection(handler)
    conn.handle_incoming_message(malformed)  # type: ignore[arg-type]
    assert handler.closed == [(POLICY_VIOLATION, "malformed frame")]


# --- a real Voilà ------------------------------------------------------------------------------------


def _serve(tmp_path: Path, token: str | None = None) -> Iterator[tuple[int, subprocess.Popen[bytes]]]:
    env = {**os.environ, "PMK_MAPS_DIR": str(tmp_path / "maps"), "PMK_CONFIG_DIR": str(tmp_path / "config")}
    port = free_port()
    notebook = write_dashboard_notebook(tmp_path / "served", token=token)
    log = (tmp_path / "voila.log").open("wb")
    voila = subprocess.Popen(
        voila_command(notebook, port=port), env=env, cwd=notebook.parent, stdout=log, stderr=subprocess.STDOUT
    )
    try:
        wait_for_port("127.0.0.1", port, voila, "Voilà", 120.0)
        yield port, voila
    finally:
        stop_process(voila)
        log.close()


def _log(tmp_path: Path) -> str:
    """What the served Voilà has logged so far."""
    return (tmp_path / "voila.log").read_text(errors="replace")


@pytest.fixture
def served(tmp_path: Path) -> Iterator[tuple[int, subprocess.Popen[bytes]]]:
    yield from _serve(tmp_path)


def _kernel_id(page: httpx.Response) -> str:
    found = re.search(r'"kernelId":\s*"([0-9a-f-]{36})"', page.text)
    assert page.status_code == 200 and found, f"no page: {page.status_code}"
    return found.group(1)


def _ws_status(url: str, *, host: str | None = None, origin: str | None = None, v1: bool = True) -> int:
    """101 when the websocket opened (then closed again), else the HTTP status it was refused with."""
    headers = {"Host": host} if host else None
    try:
        with connect(
            url,
            origin=origin,
            additional_headers=headers,
            subprotocols=[V1_PROTOCOL] if v1 else None,  # type: ignore[arg-type]
            open_timeout=60,
        ):
            return 101
    except InvalidStatus as err:
        return err.response.status_code


@pytest.mark.slow
@pytest.mark.timeout(300)
def test_a_foreign_host_or_origin_is_refused_and_a_kernel_takes_one_socket(
    served: tuple[int, subprocess.Popen[bytes]],
) -> None:
    port, _voila = served
    base = f"http://127.0.0.1:{port}/"
    refused = httpx.get(base, headers={"Host": f"evil.example:{port}"}, timeout=120)
    assert refused.status_code in (400, 403), f"Host: evil.example was served ({refused.status_code})"
    kernel = _kernel_id(httpx.get(base, timeout=120))
    channels = f"ws://127.0.0.1:{port}/api/kernels/{kernel}/channels?session_id="
    rebound = _ws_status(channels + "a", host=f"evil.example:{port}", origin=f"http://evil.example:{port}")
    assert rebound in (400, 403), f"a rebinding page's websocket: {rebound}"
    assert _ws_status(channels + "a", origin=f"http://evil.example:{port}") in (400, 403)
    assert _ws_status(channels + "a", v1=False) in (400, 409), "the legacy protocol was served"
    with connect(channels + "page", origin=f"http://127.0.0.1:{port}", subprotocols=[V1_PROTOCOL], open_timeout=60):
        second = _ws_status(channels + "other", origin=f"http://127.0.0.1:{port}")
        assert second == 409, f"a second socket to the page's kernel: {second}"
    for name in ("localhost", "[::1]"):  # the loopback names are served (no kernel needed: the login page)
        assert httpx.get(base + "login", headers={"Host": f"{name}:{port}"}, timeout=60).status_code in (200, 302), name


@pytest.mark.slow
@pytest.mark.timeout(300)
def test_a_token_does_not_excuse_a_foreign_origin(tmp_path: Path) -> None:
    token = "k" * 24
    for port, _voila in _serve(tmp_path, token=token):
        base = f"http://127.0.0.1:{port}/"
        assert httpx.get(base, timeout=60).status_code in (302, 403), "served without the token"
        kernel = _kernel_id(httpx.get(base + f"?token={token}", timeout=120))
        channels = f"ws://127.0.0.1:{port}/api/kernels/{kernel}/channels?token={token}&session_id=s"
        assert _ws_status(channels, origin=f"http://evil.example:{port}") in (400, 403)
        assert _ws_status(channels, origin=f"http://127.0.0.1:{port}") == 101
        assert httpx.get(base + f"voila/static/none.js?token={token}", timeout=60).status_code in (403, 404)
        assert wait_until(lambda: "none.js?token=***" in _log(tmp_path), 60) is not None
        assert token not in _log(tmp_path), "the token was logged"


@pytest.mark.slow
@pytest.mark.timeout(300)
def test_pmk_dashboard_kiosk_on_loopback_requires_the_printed_token(tmp_path: Path) -> None:
    env = {**os.environ, "PMK_MAPS_DIR": str(tmp_path / "maps"), "PMK_CONFIG_DIR": str(tmp_path / "config")}
    port = free_port()
    served = subprocess.Popen(
        [sys.executable, "-m", "pmk_nb.cli", "dashboard", "--kiosk", "--port", str(port), "--no-browser"],
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.DEVNULL,
        text=True,
    )
    try:
        assert served.stdout is not None
        line = served.stdout.readline()
        assert line.startswith("PMK dashboard: http://127.0.0.1:"), line
        assert re.search(r"\?token=[\w-]{16,}", line), f"the kiosk URL carries no token: {line}"
        printed = line.split()[2]
        bare = printed.split("?", 1)[0]
        started = time.monotonic()
        assert httpx.get(bare, timeout=60).status_code in (302, 403), "the kiosk page opened without the token"
        assert time.monotonic() - started < 30
        _kernel_id(httpx.get(printed, timeout=120))
    finally:
        stop_process(served)


# --- frames a kernel socket must not parse (issue 38, item 3) -----------------------------------------

#: read by jupyter_server's legacy deserializer (a closed socket's frames were): a count of 2**23
#: offsets, for which it built and cached a struct format of 2**23 codes (+270 MB, kept)
LEGACY_68 = (1 << 23).to_bytes(4, "big") + b"\0" * 64
#: as a v1 frame: a count of 2**24 offsets, which jupyter_server listed one by one (13 s, +260 MB for a while)
V1_68 = (1 << 24).to_bytes(8, "little") + b"\0" * 60
FLOOD_SECONDS = 20.0
GROWTH_LIMIT_MB = 50.0


def _flood(ws: RawWebSocket, voila: psutil.Process, baseline: float, until: float) -> int:
    """Send both crafted frames, alternately, until the server drops the connection or ``until``;
    stop at once (failing) if the server grows by :data:`GROWTH_LIMIT_MB` (it would go on by GB)."""
    sent = 0
    while time.monotonic() < until and not ws.ended.is_set() and ws.send(LEGACY_68 if sent % 2 == 0 else V1_68):
        sent += 1
        grown = rss_mb(voila) - baseline
        assert grown < GROWTH_LIMIT_MB, f"Voilà grew by {grown:.0f} MB after {sent} frames of 68 bytes"
    return sent


def _page_socket(port: int, kernel: str) -> RawWebSocket:
    """The page's socket (session "page"), once the server let go of its previous one."""
    path = f"/api/kernels/{kernel}/channels?session_id=page"
    opened: list[RawWebSocket] = []

    def admitted() -> bool:
        ws = RawWebSocket("127.0.0.1", port, path, subprotocol=V1_PROTOCOL, origin=f"http://127.0.0.1:{port}")
        if ws.status == 101:
            opened.append(ws)
        else:
            ws.close()
        return bool(opened)

    assert wait_until(admitted, 60) is not None, "the page's socket was not admitted again"
    return opened[0]


@pytest.mark.slow
@pytest.mark.timeout(300)
def test_crafted_frames_on_a_closed_or_open_socket_do_not_grow_voila(
    served: tuple[int, subprocess.Popen[bytes]], tmp_path: Path
) -> None:
    """68-byte frames after the server closed the socket (ping timeout: this client never answers a
    ping), then on an open one, and a flood of both for at most 20 s: Voilà's memory stays flat."""
    port, server = served
    voila = psutil.Process(server.pid)
    kernel = _kernel_id(httpx.get(f"http://127.0.0.1:{port}/", timeout=120))
    ws = _page_socket(port, kernel)
    baseline = rss_mb(voila)
    assert ws.closed_by_server.wait(60), "the server never closed a socket that answers no ping"
    assert ws.close_code is None  # jupyter_server's own close on a ping timeout
    until = time.monotonic() + FLOOD_SECONDS
    after_close = _flood(ws, voila, baseline, until)
    ws.close()

    ws = _page_socket(port, kernel)  # its kernel waits for the page: the same page reconnects
    assert ws.send(V1_68)
    assert ws.closed_by_server.wait(60) and ws.close_code == POLICY_VIOLATION, "a malformed frame was not refused"
    while_open = _flood(ws, voila, baseline, until)
    ws.close()

    assert after_close > 0 and while_open > 0
    assert httpx.get(f"http://127.0.0.1:{port}/login", timeout=120).status_code in (200, 302)
    grown = rss_mb(voila) - baseline
    assert grown < GROWTH_LIMIT_MB, f"Voilà grew by {grown:.0f} MB ({after_close} + {while_open} frames)"
    assert "a websocket sent a malformed frame" in _log(tmp_path)
