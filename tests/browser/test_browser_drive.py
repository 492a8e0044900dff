"""Driving from Home in a real browser: Voilà, headless Chromium, the simulated chair in its own process.

The chair's side is measured, not the page's: a separate roslibpy client records the simulator's
odometry and every /cmd_vel on the wire (:class:`tests.drive_world.ChairWatch`). The flows: hold
the joystick -> the chair drives at the profile's limit; release -> it stops within 0.5 s, after
one zero and then silence; a hidden page stops it; Stop stops it while an arrow key is still held
(and that press drives no more); a frozen websocket (no keepalives reach the kernel) stops it.
Screenshots go to ``test-artifacts/drive-*.png``.
"""

from __future__ import annotations

import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from tests.browser.kiosk_page import ARTIFACTS, VIEWPORT, chromium_page
from tests.drive_world import ChairWatch, DriveWorld, drive_world
from tests.page_probes import FreezableProxy

pytestmark = [pytest.mark.slow, pytest.mark.browser, pytest.mark.timeout(300)]

STOP_WITHIN = 0.5  # s, issue 11
HIDE_JS = """() => {
  Object.defineProperty(document, 'visibilityState', { value: 'hidden', configurable: true });
  Object.defineProperty(document, 'hidden', { value: true, configurable: true });
  document.dispatchEvent(new Event('visibilitychange'));
}"""
ACTIVE_CELL_JS = """() => Array.from(document.querySelectorAll('.jp-Notebook .jp-Cell'))
  .findIndex((c) => c.classList.contains('jp-mod-active'))"""
SHOW_JS = """() => {
  delete document.visibilityState; delete document.hidden;
  document.dispatchEvent(new Event('visibilitychange'));
}"""


@pytest.fixture
def world(tmp_path: Path) -> Iterator[DriveWorld]:
    with drive_world(tmp_path) as served:
        yield served


def shot(page: Any, name: str) -> None:
    ARTIFACTS.mkdir(exist_ok=True)
    page.screenshot(path=str(ARTIFACTS / f"drive-{name}.png"))


def ready(page: Any) -> tuple[float, float, float]:
    """Wait for Live and the joystick; returns the pad's centre and radius (CSS px)."""
    from playwright.sync_api import expect

    expect(page.locator(".pmk-home-info-state")).to_contain_text("Live", timeout=120_000)
    pad = page.locator(".pmk-drive-pad")
    expect(pad).to_be_hidden()  # nothing can drive until someone asks for the joystick
    page.locator(".pmk-drive-toggle").click()
    expect(pad).to_be_visible(timeout=30_000)
    expect(page.locator("button.pmk-drive-stop")).to_be_visible()
    page.wait_for_function("() => document.querySelector('.pmk-drive-pad[data-pmk-bound]') !== null")
    box = pad.bounding_box()
    assert box is not None
    return box["x"] + box["width"] / 2, box["y"] + box["height"] / 2, box["width"] / 2


def press_forward(page: Any, watch: ChairWatch, centre: tuple[float, float, float], hold_ms: int = 500) -> None:
    """Hold the stick at the top until the chair has been driving for ``hold_ms`` and still is.

    On this shared 2-core machine a kernel can fall behind by more than the deadman allows, and
    then the chair stops by itself, as it must; the press is then repeated (up to 4 times), so
    that what follows is measured from a driving chair.
    """
    cx, cy, r = centre
    for _ in range(4):
        page.mouse.move(cx, cy)
        t = time.monotonic()
        page.mouse.down()
        page.mouse.move(cx, cy - 1.3 * r, steps=3)  # beyond the rim: full speed (pointer capture)
        if watch.first(t, watch.moving, 5.0) is None:
            status = page.locator(".pmk-drive-status").inner_text()
            pytest.fail(f"the chair did not move while the stick was held; the page says: {status}")
        page.wait_for_timeout(hold_ms)
        if watch.moving(*watch.odom[-1][1:]):
            return
        page.mouse.up()
        page.wait_for_timeout(500)
    pytest.fail("the chair never kept driving while the stick was held (kernel too slow for the deadman)")


def test_joystick_drives_and_release_stops_within_half_a_second(world: DriveWorld) -> None:
    from playwright.sync_api import expect

    watch = ChairWatch(world.ros_port)
    try:
        with chromium_page(world.url, viewport=VIEWPORT, has_touch=True) as page:
            centre = ready(page)
            shot(page, "1-ready")
            assert watch.odom and all(watch.still(v, w) for _, v, w in watch.odom[-10:]), "the chair moved by itself"
            press_forward(page, watch, centre, hold_ms=1200)  # held still: keepalives carry the command
            _, v, w = watch.odom[-1]
            assert v == pytest.approx(0.5, abs=0.02) and abs(w) < 0.05, f"not 0.5 m/s ahead: {watch.cmds[-5:]}"
            expect(page.locator(".pmk-drive-status")).to_contain_text("Driving")
            shot(page, "2-driving")
            released = time.monotonic()
            page.mouse.up()
            stopped = watch.first(released, watch.still, 3.0)
            assert stopped is not None and stopped <= STOP_WITHIN, f"stopped {stopped} s after release"
            page.wait_for_timeout(1000)
            after = watch.cmds_since(released)
            zeros = [c for c in after if (c[1], c[2]) == (0.0, 0.0)]
            # one zero and nothing after it; commands sent before the release may still arrive late
            # on a loaded machine (how late is STOP_WITHIN's business above)
            assert len(zeros) == 1 and after[-1] == zeros[0], f"after release: {after}"
            shot(page, "3-released")
    finally:
        watch.close()


def test_hidden_page_and_stop_button_stop_the_chair(world: DriveWorld) -> None:
    from playwright.sync_api import expect

    watch = ChairWatch(world.ros_port)
    try:
        with chromium_page(world.url, viewport=VIEWPORT) as page:
            centre = ready(page)
            # -- the page goes hidden while the stick is held (another tab, the screen turned off)
            press_forward(page, watch, centre)
            hidden = time.monotonic()
            page.evaluate(HIDE_JS)
            stopped = watch.first(hidden, watch.still, 3.0)
            assert stopped is not None and stopped <= STOP_WITHIN, f"stopped {stopped} s after the page was hidden"
            page.mouse.up()
            page.evaluate(SHOW_JS)
            expect(page.locator(".pmk-drive-status")).to_contain_text("hidden")
            # -- arrow keys drive (the pad has the focus), Stop stops while the key is still held
            page.locator(".pmk-drive-pad").focus()
            t = time.monotonic()
            page.keyboard.down("ArrowLeft")
            assert watch.first(t, lambda v, w: w > 0.5, 3.0) is not None, "ArrowLeft did not turn the chair left"
            stop = time.monotonic()
            page.locator("button.pmk-drive-stop").click()
            stopped = watch.first(stop, watch.still, 3.0)
            assert stopped is not None and stopped <= STOP_WITHIN, f"stopped {stopped} s after Stop"
            page.wait_for_timeout(800)  # the key is still down: keepalives come, the chair stays put
            assert all(watch.still(v, w) for t_, v, w in watch.odom if t_ > stop + STOP_WITHIN)
            expect(page.locator(".pmk-drive-status")).to_contain_text("Stopped")
            shot(page, "4-stopped")
            page.keyboard.up("ArrowLeft")
    finally:
        watch.close()


def test_keepalive_loss_stops_the_chair(world: DriveWorld) -> None:
    """The websocket between page and server goes silent (a tablet out of Wi-Fi range)."""
    proxy = FreezableProxy(world.voila_port)
    watch = ChairWatch(world.ros_port)
    try:
        with chromium_page(f"http://127.0.0.1:{proxy.port}/", viewport=VIEWPORT) as page:
            centre = ready(page)
            press_forward(page, watch, centre)
            frozen = time.monotonic()
            proxy.freeze()
            try:
                stopped = watch.first(frozen, watch.still, 3.0)
                page.wait_for_timeout(500)
            finally:
                page.mouse.up()
                proxy.thaw()
            assert stopped is not None and stopped <= STOP_WITHIN, f"stopped {stopped} s after the page fell silent"
            # the keepalives queued in the proxy arrive late now: they must not start the chair again
            page.wait_for_timeout(1000)
            assert all(watch.still(v, w) for t_, v, w in watch.odom if t_ > frozen + STOP_WITHIN)
    finally:
        watch.close()
        proxy.close()


def test_arrow_keys_drive_in_jupyterlab(tmp_path: Path) -> None:
    """In JupyterLab the arrow keys drive while the stick has the focus, and JupyterLab's own
    arrow-key shortcuts (move between cells) stay out of the way."""
    from playwright.sync_api import expect

    with drive_world(tmp_path, server="lab") as lab:
        watch = ChairWatch(lab.ros_port)
        try:
            with chromium_page(lab.url, viewport=VIEWPORT) as page:
                cell = page.locator(".jp-Notebook .jp-Cell").first
                expect(cell).to_be_visible(timeout=120_000)
                page.wait_for_timeout(3000)  # the kernel starts (a cell run meanwhile waits for it)
                cell.click()
                page.keyboard.press("Shift+Enter")  # run the dashboard cell
                expect(page.locator(".pmk-home-info-state")).to_contain_text("Live", timeout=120_000)
                page.locator(".pmk-drive-toggle").click()
                pad = page.locator(".pmk-drive-pad")
                expect(pad).to_be_visible(timeout=60_000)
                page.wait_for_function("() => document.querySelector('.pmk-drive-pad[data-pmk-bound]') !== null")
                pad.focus()  # (JupyterLab makes the cell holding the focus the active one)
                page.wait_for_timeout(300)
                active_before = page.evaluate(ACTIVE_CELL_JS)
                t = time.monotonic()
                page.keyboard.down("ArrowDown")  # reverse; in command mode JupyterLab would go to the next cell
                moved = watch.first(t, lambda v, w: v < -0.1, 5.0)
                page.wait_for_timeout(400)
                released = time.monotonic()
                page.keyboard.up("ArrowDown")
                stopped = watch.first(released, watch.still, 3.0)
                shot(page, "5-jupyterlab")
                assert moved is not None, "ArrowDown on the focused stick did not back the chair up in JupyterLab"
                assert stopped is not None and stopped <= STOP_WITHIN, f"stopped {stopped} s after the key went up"
                active_after = page.evaluate(ACTIVE_CELL_JS)
                assert active_after == active_before, "JupyterLab moved to another cell on the arrow key"
        finally:
            watch.close()
