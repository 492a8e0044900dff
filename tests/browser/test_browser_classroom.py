"""Two classroom pages in a real browser (issue 26): each its own chair; driving one leaves the other still.

``pmk demo --classroom``'s world (:func:`pmk_nb.cli.demo_classroom.prepare_classroom`) served by a real
Voilà: each page's kernel starts its own simulated chair (``chairs.json`` in the class's state folder
lists them, with their ports); a separate roslibpy client watches each chair's odometry.  Page A's
stick turns A's chair while B's stays still, and closing page A ends its kernel and with it its chair.
Screenshot: ``test-artifacts/classroom-two-pages.png``.
"""

from __future__ import annotations

import json
import subprocess
import time
from pathlib import Path
from typing import Any

import pytest

from pmk_nb.serve.procs import free_port, stop_process, wait_for_port
from pmk_nb.serve.voila import voila_command, write_dashboard_notebook
from pmk_nb.ui import KIOSK_ENV
from tests.browser.kiosk_page import ARTIFACTS, VIEWPORT, chromium_page
from tests.browser.test_browser_drive import ready
from tests.drive_world import ChairWatch

pytestmark = [pytest.mark.slow, pytest.mark.browser, pytest.mark.timeout(300)]


def _chairs(state_dir: Path) -> dict[int, dict[str, Any]]:
    path = state_dir / "chairs.json"
    return {int(k): v for k, v in json.loads(path.read_text()).items()} if path.exists() else {}


def _wait_for(pred: Any, timeout: float) -> bool:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if pred():
            return True
        time.sleep(0.2)
    return bool(pred())


def test_two_classroom_pages_drive_their_own_chairs(tmp_path: Path) -> None:
    from playwright.sync_api import expect

    from pmk_nb.cli.demo_classroom import prepare_classroom

    room = prepare_classroom(tmp_path / "demo", max_chairs=4)
    room.env[KIOSK_ENV] = "0"
    state = Path(room.settings.state_dir)
    port = free_port()
    notebook = write_dashboard_notebook(tmp_path / "served")
    log = (tmp_path / "voila.log").open("wb")
    voila = subprocess.Popen(
        voila_command(notebook, port=port), env=room.env, cwd=notebook.parent, stdout=log, stderr=log
    )
    watches: list[ChairWatch] = []
    try:
        wait_for_port("127.0.0.1", port, voila, "Voilà", 120.0)
        url = f"http://127.0.0.1:{port}/"
        with chromium_page(url, viewport=VIEWPORT) as page_a:
            page_b: Any = page_a.context.browser.new_page(viewport=VIEWPORT)
            page_b.set_default_timeout(60_000)
            page_b.goto(url, wait_until="domcontentloaded")
            centre = ready(page_a)
            ready(page_b)
            expect(page_a.locator(".pmk-app")).to_contain_text("this chair is yours alone")
            chairs = _chairs(state)
            assert len(chairs) == 2, chairs  # a chair per page, each in its page's kernel
            ports = sorted(int(c["ros_port"]) for c in chairs.values())
            assert ports[0] != ports[1]
            watches = [ChairWatch(p) for p in ports]
            time.sleep(1.0)
            assert all(w.still(*w.odom[-1][1:]) for w in watches)  # parked, no patrol
            cx, cy, r = centre
            start = time.monotonic()
            for _ in range(3):  # a kernel that falls behind on this shared machine stops by itself (deadman)
                page_a.mouse.move(cx, cy)
                page_a.mouse.down()
                page_a.mouse.move(cx + 1.3 * r, cy, steps=3)  # full right: turn on the spot, no wall in the way
                if _wait_for(lambda: any(w.first(start, w.moving, 0.0) is not None for w in watches), 10.0):
                    break
                page_a.mouse.up()
            page_a.wait_for_timeout(500)
            page_a.mouse.up()
            moved = [w.first(start, w.moving, 0.0) for w in watches]
            ARTIFACTS.mkdir(exist_ok=True)
            page_a.screenshot(path=str(ARTIFACTS / "classroom-two-pages.png"))
            assert sum(m is not None for m in moved) == 1, f"chairs that moved: {moved}"  # A's, and only A's
            b = watches[[m is None for m in moved].index(True)]
            assert all(b.still(v, w) for t, v, w in b.odom if t >= start), "page B's chair moved"
            page_a.close()  # page A's kernel ends with its page, and its chair with it
            assert _wait_for(lambda: len(_chairs(state)) == 1, 60.0), _chairs(state)
    finally:
        for w in watches:
            w.close()
        stop_process(voila)
        log.close()
    assert _wait_for(lambda: not _chairs(state), 30.0), f"chairs left after Voilà stopped: {_chairs(state)}"
