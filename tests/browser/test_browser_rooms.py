"""Rooms by name in Chromium against the simulated chair on the clinic sample (Voilà, real link).

"Go to" a named room: pick it in the searchable list, press Go; the route is drawn, the chair drives
there and the page says "Arrived"; the chair's own odometry is inside the room's polygon. Spoken
feedback: ``window.speechSynthesis`` is replaced before the page loads by a recorder (the phrases
must reach it), and, in a second page that has no speech synthesis, the espeak-ng WAV made in the
kernel must be played by an ``<audio>`` element (``play()`` resolved, audio of plausible length).
"""

from __future__ import annotations

import contextlib
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import shapely

from pmk_nb.chair.link import ChairLink
from pmk_nb.guide import RoomsMap, load_rooms
from tests.browser.kiosk_page import ARTIFACTS, CHROMIUM, CHROMIUM_ARGS, VIEWPORT, serve_kiosk
from tests.browser.test_browser_live import pixels

ROUTE_RGB = (0, 150, 70)  # pmk_nb.ui.rooms.layer.ROUTE_RGB

pytestmark = [pytest.mark.slow, pytest.mark.browser, pytest.mark.timeout(420)]

RECORD_SPEECH = """
window.__spokenByPage = [];
const fakeSpeech = {
  speak(u) { window.__spokenByPage.push({text: u.text, rate: u.rate, lang: u.lang}); },
  getVoices() { return []; }, cancel() {}, pause() {}, resume() {}, speaking: false, pending: false,
};
Object.defineProperty(window, 'speechSynthesis', {get() { return fakeSpeech; }, configurable: true});
if (typeof window.SpeechSynthesisUtterance !== 'function') {
  window.SpeechSynthesisUtterance = function (text) { this.text = text; };
}
"""
NO_SPEECH = """
Object.defineProperty(window, 'speechSynthesis', {get() { return undefined; }, configurable: true});
window.SpeechSynthesisUtterance = undefined;
window.__played = [];
const realPlay = HTMLMediaElement.prototype.play;
HTMLMediaElement.prototype.play = function () {
  const entry = {src: this.currentSrc || this.src, ok: null};
  window.__played.push(entry);
  const p = realPlay.call(this);
  p.then(() => { entry.ok = true; }, (e) => { entry.ok = String(e); });
  return p;
};
"""


@contextlib.contextmanager
def page_with(url: str, init_script: str) -> Iterator[Any]:
    if not CHROMIUM.exists():
        pytest.fail(f"{CHROMIUM} is missing: install Debian's chromium package (apt-get install -y chromium)")
    from playwright.sync_api import sync_playwright

    with sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=str(CHROMIUM), args=CHROMIUM_ARGS, headless=True)
        try:
            context = browser.new_context(viewport=VIEWPORT)
            context.add_init_script(init_script)
            page = context.new_page()
            page.set_default_timeout(60_000)
            page.goto(url, wait_until="domcontentloaded")
            yield page
        finally:
            browser.close()


def go_to(page: Any, rooms: RoomsMap, room: str) -> None:
    from playwright.sync_api import expect

    word = room.split()[0].lower()
    search = page.locator(".pmk-rooms-search input")
    search.fill(word)
    select = page.locator(".pmk-rooms-list select")
    expect(select).to_contain_text(room, timeout=10_000)
    expect(select.locator("option")).to_have_count(len(rooms.search(word)), timeout=10_000)  # filtered
    select.select_option(label=room)
    page.wait_for_timeout(500)  # the pick reaches the kernel before Go does
    page.locator("button.pmk-rooms-go").click()


def spoken(page: Any) -> list[str]:
    return [s["text"] for s in page.evaluate("window.__spokenByPage || []")]


def test_go_to_a_named_room_arrives_inside_it_and_the_phrases_fire(tmp_path: Path) -> None:
    from playwright.sync_api import expect

    with serve_kiosk(tmp_path, label="rooms") as (url, world):
        rooms = load_rooms(world.map_yaml)
        link = ChairLink("127.0.0.1", world.ros_port)
        link.connect(timeout=10.0)
        link.start_streams()
        try:
            with page_with(url, RECORD_SPEECH) as page:
                here = page.locator(".pmk-rooms-here")
                expect(here).to_contain_text("You are in:", timeout=120_000)
                target = "Exam room 1" if "Exam room 2" in here.inner_text() else "Exam room 2"
                go_to(page, rooms, target)
                status = page.locator(".pmk-rooms-status")
                expect(status).to_contain_text(f"Going to {target}", timeout=20_000)
                page.wait_for_timeout(1500)  # the route is drawn over the map
                rgba = pixels(page).astype(int)
                green = np.all(np.abs(rgba[..., :3] - ROUTE_RGB) < 40, axis=2) & (rgba[..., 3] > 200)
                assert int(green.sum()) > 50, "no route drawn on the live map"
                ARTIFACTS.mkdir(exist_ok=True)
                page.evaluate("document.querySelector('.pmk-home-preview-box').scrollIntoView({block: 'start'})")
                page.screenshot(path=str(ARTIFACTS / "rooms-route.png"))
                expect(status).to_contain_text(f"Arrived at {target}.", timeout=150_000)
                odom = link.latest_odom()
                assert odom is not None
                polygon = rooms.room(target).polygon
                assert shapely.contains_xy(polygon, odom.x, odom.y), (target, odom.x, odom.y)
                expect(here).to_contain_text(target, timeout=5_000)
                deadline = time.monotonic() + 10
                while time.monotonic() < deadline and f"Arrived at {target}." not in spoken(page):
                    time.sleep(0.2)
                said = spoken(page)
                assert f"Going to {target}." in said and f"Arrived at {target}." in said, said
                assert said.index(f"Going to {target}.") < said.index(f"Arrived at {target}.")
                page.screenshot(path=str(ARTIFACTS / "rooms-arrived.png"), full_page=True)

            with page_with(url, NO_SPEECH) as page:  # no speechSynthesis: espeak-ng audio from the kernel
                expect(page.locator(".pmk-rooms-here")).to_contain_text("You are in:", timeout=120_000)
                page.wait_for_timeout(1000)  # the page reports that it cannot speak
                go_to(page, rooms, "Office")
                expect(page.locator(".pmk-rooms-status")).to_contain_text("Going to Office", timeout=20_000)
                deadline = time.monotonic() + 15
                played: list[dict[str, Any]] = []
                while time.monotonic() < deadline and not any(p["ok"] is True for p in played):
                    played = page.evaluate("window.__played")
                    time.sleep(0.2)
                assert played and played[-1]["src"].startswith("data:audio/wav;base64,"), played
                assert played[-1]["ok"] is True, played  # the browser really played it
                duration = page.evaluate("document.querySelector('audio.pmk-speech-audio').duration")
                assert 0.5 < duration < 5.0, duration  # "Going to Office." at the set rate
                page.locator("button.pmk-rooms-cancel").click()
                expect(page.locator(".pmk-rooms-status")).to_contain_text("cancelled", timeout=20_000)
                page.screenshot(path=str(ARTIFACTS / "rooms-espeak-cancelled.png"), full_page=True)
        finally:
            link.close()
