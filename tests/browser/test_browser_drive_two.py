"""Two pages of one dashboard drive one chair (issue 30, finding 3), in a real browser.

Page A holds the stick; page B (its own Voilà kernel) shows "Driven from another page", its stick
is greyed and refused; B's Stop stops the chair within 0.5 s while A's finger stays down, and A's
page says why. Before the fix, B showed "Stopped." while the chair kept turning under A's stick.
Screenshot: ``test-artifacts/drive-two-pages.png``.
"""

from __future__ import annotations

import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from tests.browser.kiosk_page import VIEWPORT, chromium_page
from tests.browser.test_browser_drive import STOP_WITHIN, press_forward, ready, shot
from tests.drive_world import ChairWatch, DriveWorld, drive_world

pytestmark = [pytest.mark.slow, pytest.mark.browser, pytest.mark.timeout(300)]


@pytest.fixture
def world(tmp_path: Path) -> Iterator[DriveWorld]:
    with drive_world(tmp_path) as served:
        yield served


def test_stop_on_another_page_stops_the_chair_and_that_page_cannot_drive(world: DriveWorld) -> None:
    from playwright.sync_api import expect

    watch = ChairWatch(world.ros_port)
    try:
        with chromium_page(world.url, viewport=VIEWPORT) as page_a:
            page_b: Any = page_a.context.browser.new_page(viewport=VIEWPORT)
            page_b.set_default_timeout(60_000)
            page_b.goto(world.url, wait_until="domcontentloaded")
            centre = ready(page_a)
            ready(page_b)
            press_forward(page_a, watch, centre)
            status_b = page_b.locator(".pmk-drive-status")
            expect(status_b).to_contain_text("Driven from another page (since ", timeout=5_000)
            expect(page_b.locator(".pmk-drive-locked .pmk-drive-pad")).to_be_visible()
            expect(page_b.locator("button.pmk-drive-claim")).to_contain_text("Take over driving")
            for _ in range(3):  # a kernel that falls behind on this shared machine stops by itself (deadman)
                if watch.moving(*watch.odom[-1][1:]):
                    break
                page_a.mouse.up()
                page_a.wait_for_timeout(300)
                press_forward(page_a, watch, centre)
            assert watch.moving(*watch.odom[-1][1:]), "A stopped driving before B's Stop"
            stop = time.monotonic()
            page_b.locator("button.pmk-drive-stop").click()
            stopped = watch.first(stop, watch.still, 3.0)
            assert stopped is not None and stopped <= STOP_WITHIN, f"stopped {stopped} s after B's Stop"
            page_a.wait_for_timeout(800)  # A's finger is still down: its keepalives come, nothing moves
            assert all(watch.still(v, w) for t, v, w in watch.odom if t > stop + STOP_WITHIN)
            expect(page_a.locator(".pmk-drive-status")).to_contain_text("Stopped from another page (since ")
            expect(status_b).to_contain_text("Stopped from this page")
            expect(page_b.locator("button.pmk-drive-claim")).to_contain_text("Release the Stop")
            shot(page_b, "two-pages")
            page_a.mouse.up()
    finally:
        watch.close()
