"""The kiosk over HTTPS in a real browser (issue 24): ``pmk dashboard --kiosk --https`` and Chromium.

The tablet's view is reproduced on 127.0.0.1 only: Chromium resolves the name ``tablet.pmk.test`` to
127.0.0.1 (``--host-resolver-rules``), so the page's origin is not loopback, as a LAN tablet's is
not.  Over HTTPS the kiosk loads, talks to its kernel (a ``wss:`` websocket: the PIN screen answers)
and holds its Screen Wake Lock; the same wake-lock script served over plain HTTP under that name has
no ``navigator.wakeLock`` at all (no secure context), which is why beyond loopback HTTP needs ``--insecure``.
"""

from __future__ import annotations

import http.server
import os
import subprocess
import sys
import threading
from pathlib import Path

import pytest

from pmk_nb.serve import tablet_tls
from pmk_nb.serve.procs import free_port, stop_process
from pmk_nb.ui.kiosk.mode import wake_lock_html
from tests.browser.kiosk_page import ARTIFACTS, CHROMIUM, CHROMIUM_ARGS, VIEWPORT

pytestmark = [pytest.mark.slow, pytest.mark.browser, pytest.mark.timeout(180)]

TABLET_NAME = "tablet.pmk.test"  # .test: reserved, never a real name
#: counts the page's wake-lock requests and how each ended, before any page script runs
COUNT_WAKE_LOCKS = """
window.__wake = {asked: 0, granted: 0, refused: 0};
if (navigator.wakeLock) {
  const request = navigator.wakeLock.request.bind(navigator.wakeLock);
  navigator.wakeLock.request = async (kind) => {
    window.__wake.asked += 1;
    try { const s = await request(kind); window.__wake.granted += 1; return s; }
    catch (e) { window.__wake.refused += 1; throw e; }
  };
}
"""


class _PlainPage(http.server.BaseHTTPRequestHandler):
    """The kiosk's wake-lock script on a plain HTTP page."""

    def do_GET(self) -> None:
        body = f"<!doctype html><html><body>{wake_lock_html()}</body></html>".encode()
        self.send_response(200)
        self.send_header("Content-Type", "text/html; charset=utf-8")
        self.send_header("Content-Length", str(len(body)))
        self.end_headers()
        self.wfile.write(body)

    def log_message(self, *args: object) -> None:
        pass


def _state(page: object) -> dict[str, object]:
    return page.evaluate(  # type: ignore[attr-defined, no-any-return]
        "() => ({secure: window.isSecureContext, api: 'wakeLock' in navigator, wake: window.__wake,"
        " shown: document.querySelector('.pmk-wakelock')?.dataset.state})"
    )


def test_the_kiosk_over_https_holds_its_wake_lock_where_plain_http_cannot(tmp_path: Path) -> None:
    from playwright.sync_api import expect, sync_playwright

    if not CHROMIUM.exists():
        pytest.fail(f"{CHROMIUM} is missing: install Debian's chromium package (apt-get install -y chromium)")
    config = tmp_path / "config"
    # the certificate `--https` made on an earlier run, with the tablet's name: this run must reuse it
    made = tablet_tls.self_signed(config / tablet_tls.TLS_DIR, [*tablet_tls.served_hosts("127.0.0.1"), TABLET_NAME])
    env = {**os.environ, "PMK_MAPS_DIR": str(tmp_path / "maps"), "PMK_CONFIG_DIR": str(config)}
    port = free_port()
    cmd = [sys.executable, "-m", "pmk_nb.cli", "dashboard", "--kiosk", "--https", "--port", str(port), "--no-browser"]
    log = (tmp_path / "voila.log").open("wb")
    served = subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=log, text=True)
    plain = http.server.ThreadingHTTPServer(("127.0.0.1", 0), _PlainPage)
    threading.Thread(target=plain.serve_forever, daemon=True).start()
    try:
        assert served.stdout is not None
        printed = [served.stdout.readline() for _ in range(3)]
        assert printed[0].startswith(f"PMK dashboard: https://127.0.0.1:{port}/?token="), printed
        assert printed[1].split()[-1] == made.fingerprint, printed  # reused, not made anew
        url = printed[0].split()[2].replace("127.0.0.1", TABLET_NAME)
        rules = f"--host-resolver-rules=MAP {TABLET_NAME} 127.0.0.1"
        with sync_playwright() as pw:
            browser = pw.chromium.launch(executable_path=str(CHROMIUM), args=[*CHROMIUM_ARGS, rules], headless=True)
            try:
                # the certificate is not in Chromium's store: the errors a tablet would have trusted away
                page = browser.new_page(viewport=VIEWPORT, has_touch=True, ignore_https_errors=True)
                page.set_default_timeout(60_000)
                page.add_init_script(COUNT_WAKE_LOCKS)
                page.goto(url, wait_until="domcontentloaded")
                expect(page.locator(".pmk-kiosk button.pmk-nav-home")).to_be_visible(timeout=90_000)
                expect(page.locator(".pmk-wakelock")).to_have_attribute("data-state", "on", timeout=30_000)
                secure = _state(page)
                assert secure["secure"] and secure["api"], secure
                assert secure["wake"] == {"asked": 1, "granted": 1, "refused": 0}, secure
                login = [c for c in page.context.cookies() if c["name"].startswith("username-")]
                assert login and all(c["secure"] for c in login), page.context.cookies()  # HTTPS only
                # the kernel answers over wss: (no PIN yet, so Settings opens and says so)
                page.locator("button.pmk-nav-settings").click()
                expect(page.locator(".pmk-kiosk-pin-state")).to_contain_text("No PIN yet", timeout=60_000)
                ARTIFACTS.mkdir(exist_ok=True)
                page.screenshot(path=str(ARTIFACTS / "kiosk-https.png"))
                # the same script over plain HTTP under the same non-loopback name: no wake lock at all
                page.goto(f"http://{TABLET_NAME}:{plain.server_address[1]}/", wait_until="domcontentloaded")
                expect(page.locator(".pmk-wakelock")).to_have_attribute("data-state", "off")
                insecure = _state(page)
                assert not insecure["secure"] and not insecure["api"], insecure
                assert insecure["wake"] == {"asked": 0, "granted": 0, "refused": 0}, insecure
            finally:
                browser.close()
    finally:
        plain.shutdown()
        stop_process(served)
        log.close()
