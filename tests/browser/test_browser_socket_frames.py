"""A page script sends crafted kernel frames through the page's own kernel socket (issue 38, item 3).

The frame is the 68-byte one of the report: a kernel-protocol v1 frame whose 8-byte offset count says
16 M offsets. jupyter_server 2.21.1 would build a ``struct`` format of that size (hundreds of MB, kept);
our guard refuses any count the frame cannot hold before anything is allocated and closes the socket
(1008). The page's kernel connection reconnects and the attack is repeated, a bounded number of times;
Voilà's memory stays flat and the page still answers.
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any

import psutil
import pytest

from tests.browser.kiosk_page import VIEWPORT, chromium_page, serve_kiosk

pytestmark = [pytest.mark.slow, pytest.mark.browser, pytest.mark.timeout(300)]

ROUNDS = 4
GROWTH_MB = 50

#: Run in the page: send the crafted frame on the page's own kernel socket, wait for its close code,
#: wait for the kernel connection's next socket, and again.
ATTACK_JS = """async ([rounds]) => {
  const manager = await window.jupyterapp.widgetManagerPromise.promise;
  const kernel = manager.kernel;
  const sleep = ms => new Promise(r => setTimeout(r, ms));
  const openSocket = async previous => {
    for (let waited = 0; waited < 30000; waited += 100) {
      const ws = kernel._ws;
      if (ws && ws !== previous && ws.readyState === 1) return ws;
      await sleep(100);
    }
    return null;
  };
  const codes = [], protocols = [];
  let ws = await openSocket(null);
  for (let i = 0; i < rounds && ws; i++) {
    protocols.push(ws.protocol);
    const closed = new Promise(resolve => ws.addEventListener('close', e => resolve(e.code), {once: true}));
    const frame = new ArrayBuffer(68);
    new DataView(frame).setBigUint64(0, BigInt(2 ** 24), true);  // 16 M offsets claimed, 68 bytes sent
    ws.send(frame);
    codes.push(await Promise.race([closed, sleep(15000).then(() => -1)]));
    ws = await openSocket(ws);
  }
  return {codes, protocols, reconnected: ws !== null};
}"""


def _voila(url: str) -> psutil.Process:
    """The process listening on the page's port."""
    port = int(url.rstrip("/").rsplit(":", 1)[1])
    for conn in psutil.net_connections(kind="tcp"):
        if conn.laddr and conn.laddr.port == port and conn.status == psutil.CONN_LISTEN and conn.pid:
            return psutil.Process(conn.pid)
    raise AssertionError(f"no process listens on port {port}: Voilà is not serving the page")


def _attack(page: Any) -> dict[str, Any]:
    return page.evaluate(ATTACK_JS, [ROUNDS])


def test_a_page_script_sending_a_crafted_frame_is_cut_off_and_voila_stays_flat(tmp_path: Path) -> None:
    from playwright.sync_api import expect

    with serve_kiosk(tmp_path, label="socket-frames") as (url, _world):
        voila = _voila(url)
        with chromium_page(url, viewport=VIEWPORT) as page:
            expect(page.locator("button.pmk-nav-home")).to_be_visible(timeout=120_000)
            before = voila.memory_info().rss
            seen = _attack(page)
            after = voila.memory_info().rss
            assert seen["protocols"] and all(p == "v1.kernel.websocket.jupyter.org" for p in seen["protocols"]), seen
            assert seen["codes"] == [1008] * ROUNDS, f"the crafted frame did not close the socket each time: {seen}"
            assert (after - before) / 2**20 < GROWTH_MB, f"Voilà grew {(after - before) / 2**20:.0f} MB"
            assert seen["reconnected"], "the page's kernel connection did not come back"
            # the page still works on its new socket: a click reaches the kernel and changes the screen
            deadline = time.monotonic() + 60.0
            page.locator("button.pmk-nav-maps").click()
            expect(page.locator(".pmk-maps")).to_be_visible(timeout=max(1.0, deadline - time.monotonic()) * 1000)
