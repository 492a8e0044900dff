"""A hostile second websocket to a page's own kernel, in Chromium against the simulated chair (issue 30, finding 2).

A page script (or anything that learned the kernel id) opened one more websocket to its kernel,
spoke the legacy JSON protocol and never read: Voilà queued the live view's output for it and grew
from 102 MB to 1.7 GB in 30 s, new pages got no answer, and the kernel outlived its page.  Here the
live view runs in Chromium while such sockets (legacy, and v1 with another session) stay open for
:data:`HOLD_S` s: the server and its kernels stay flat, a second page still loads, and the page's
kernel still ends with the page.
"""

from __future__ import annotations

import base64
import os
import re
import socket
import time
from pathlib import Path

import httpx
import pytest

from tests.browser.kiosk_page import chromium_page, serve_kiosk
from tests.page_probes import kernels, rss_mb, voila_process, wait_until

pytestmark = [pytest.mark.slow, pytest.mark.browser, pytest.mark.timeout(400)]

HOLD_S = 20.0  # an unguarded server grows ~50 MB/s: 20 s shows it 20 times over
MAX_GROWTH_MB = 50.0
ABORT_GROWTH_MB = 400.0  # the unguarded server grows ~50 MB/s: stop before the machine suffers
VIEWPORT = {"width": 1280, "height": 800}


def open_silent_socket(port: int, path: str, protocol: str | None) -> tuple[socket.socket, int]:
    """A websocket upgrade for ``path`` that is never read after the status line; (socket, HTTP status)."""
    sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)  # the kernel's buffer fills at once
    sock.settimeout(60)
    sock.connect(("127.0.0.1", port))
    key = base64.b64encode(os.urandom(16)).decode()
    lines = [
        f"GET {path} HTTP/1.1",
        f"Host: 127.0.0.1:{port}",
        f"Origin: http://127.0.0.1:{port}",
        "Upgrade: websocket",
        "Connection: Upgrade",
        f"Sec-WebSocket-Key: {key}",
        "Sec-WebSocket-Version: 13",
    ]
    if protocol:
        lines.append(f"Sec-WebSocket-Protocol: {protocol}")
    sock.sendall(("\r\n".join(lines) + "\r\n\r\n").encode())
    head = b""
    while len(head) < 12:
        chunk = sock.recv(12 - len(head))
        if not chunk:
            break
        head += chunk
    return sock, int(head[9:12]) if len(head) >= 12 else 0


def _total_mb(voila: object) -> float:
    return rss_mb(voila) + sum(rss_mb(k) for k in kernels(voila))  # type: ignore[arg-type]


def test_a_hostile_second_socket_cannot_grow_the_server_starve_pages_or_keep_the_kernel(tmp_path: Path) -> None:
    from playwright.sync_api import expect

    with serve_kiosk(tmp_path, label="sockets") as (url, _world):
        port = int(url.rstrip("/").rsplit(":", 1)[1])
        voila = voila_process(port)
        with chromium_page(url, viewport=VIEWPORT) as page:
            expect(page.locator(".pmk-home-info-state")).to_contain_text("Live", timeout=120_000)
            kernel_id = re.search(r'"kernelId":\s*"([0-9a-f-]{36})"', page.content())
            assert kernel_id, "the page names no kernel"
            channels = f"/api/kernels/{kernel_id.group(1)}/channels?session_id=hostile-"
            mine = [k for k in kernels(voila) if kernel_id.group(1) in " ".join(k.cmdline())]
            assert len(mine) == 1, "the page's kernel process was not found"
            time.sleep(3.0)  # the live view's first map image is out
            before = _total_mb(voila)
            legacy, legacy_status = open_silent_socket(port, channels + "legacy", None)
            v1, v1_status = open_silent_socket(port, channels + "v1", "v1.kernel.websocket.jupyter.org")
            try:
                peak, start = before, time.monotonic()
                while time.monotonic() - start < HOLD_S and peak - before < ABORT_GROWTH_MB:
                    time.sleep(2.0)
                    peak = max(peak, _total_mb(voila))
                print(f"Voilà + kernels: {before:.0f} MB before, peak {peak:.0f} MB over {HOLD_S:.0f} s")
                assert peak - before < MAX_GROWTH_MB, f"grew {peak - before:.0f} MB with a silent second socket"
                started = time.monotonic()
                second = httpx.get(url, timeout=90.0)
                assert second.status_code == 200 and '"kernelId"' in second.text, "a second page did not load"
                print(f"a second page rendered in {time.monotonic() - started:.1f} s")
                expect(page.locator(".pmk-home-info-state")).to_contain_text("Live")
                # refused at the door: a kernel has its page's channel only
                assert legacy_status != 101 and v1_status != 101, (legacy_status, v1_status)
            finally:
                page.close()
                gone = wait_until(lambda: not any(k.is_running() and k.status() != "zombie" for k in mine), 30.0)
                legacy.close()
                v1.close()
            assert gone is not None, "the page's kernel outlived its page"
