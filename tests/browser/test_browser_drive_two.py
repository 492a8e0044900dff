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


CLICK_JS = """async (cls) => {
  const manager = await window.jupyterapp.widgetManagerPromise.promise;
  const held = manager._models instanceof Map ? [...manager._models.values()] : Object.values(manager._models);
  const models = (await Promise.all(held.map(p => Promise.resolve(p).catch(() => null)))).filter(m => m && m.comm_live);
  const hits = models.filter(m => (m.get('_dom_classes') || []).includes(cls));
  for (const m of hits) m.send({event: 'click'}, {});
  return hits.length;
}"""


def test_on_a_kiosk_taking_over_needs_the_pin_and_stop_does_not(tmp_path: Path) -> None:
    """Issue 38 (low): page B of a kiosk takes over driving from page A only with the PIN; a page
    script that clicks Take over driving (as often as it likes) takes nothing; Stop needs no PIN."""
    from playwright.sync_api import expect

    from pmk_nb.ui.kiosk.pin import KIOSK_ENV, PinStore

    with drive_world(tmp_path, extra_env={KIOSK_ENV: "1"}) as world:
        PinStore(world.root / "config").set_pin("4711", "4711")  # before the pages (and kernels) start
        watch = ChairWatch(world.ros_port)
        try:
            with chromium_page(world.url, viewport=VIEWPORT) as page_a:
                page_b: Any = page_a.context.browser.new_page(viewport=VIEWPORT)
                page_b.set_default_timeout(60_000)
                page_b.goto(world.url, wait_until="domcontentloaded")
                centre = ready(page_a)
                ready(page_b)
                press_forward(page_a, watch, centre)
                status_a, status_b = page_a.locator(".pmk-drive-status"), page_b.locator(".pmk-drive-status")
                claim_b = page_b.locator("button.pmk-drive-claim")
                expect(claim_b).to_contain_text("Take over driving", timeout=5_000)
                expect(page_b.locator(".pmk-drive-pin input")).to_be_visible()
                claim_b.click()
                claim_b.click()  # the double tap that takes over elsewhere: not on a kiosk with a PIN
                assert page_b.evaluate(CLICK_JS, "pmk-drive-claim") == 1  # a page script's clicks too
                assert page_b.evaluate(CLICK_JS, "pmk-drive-claim") == 1
                expect(status_b).to_contain_text("Type the kiosk PIN", timeout=5_000)
                expect(status_b).to_contain_text("Driven from another page")
                page_b.locator(".pmk-drive-pin input").fill("1234")
                claim_b.click()
                expect(status_b).to_contain_text("Wrong PIN", timeout=5_000)
                expect(status_a).not_to_contain_text("Driven from another page")
                page_b.locator(".pmk-drive-pin input").fill("4711")
                claim_b.click()
                expect(status_a).to_contain_text("Driven from another page", timeout=5_000)
                expect(claim_b).to_be_hidden()
                page_a.mouse.up()
                stop = time.monotonic()
                page_a.locator("button.pmk-drive-stop").click()  # Stop on a kiosk page: no PIN
                assert watch.first(stop, watch.still, 3.0) is not None
                expect(status_b).to_contain_text("Stopped from another page", timeout=5_000)
                shot(page_b, "kiosk-take-over")
        finally:
            watch.close()
