"""Home for the person in the chair, in Chromium against Voilà and the simulated chair (issue 28).

One page, resized between checks (phone, portrait tablet, two landscape tablets): the live map
covers at least 60 % of the first screen; with Drive on, the joystick column docks at the side and
the chair's drawn position (``.pmk-home-chair-at``, canvas pixels from the view's maths) stays out
from under it; every visible button on Home is at least 48 x 48 CSS px.  A screenshot per size
goes to ``test-artifacts/home-<size>.png``.
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any

import pytest

from tests.browser.kiosk_page import ARTIFACTS, chromium_page, serve_kiosk

pytestmark = [pytest.mark.slow, pytest.mark.browser, pytest.mark.timeout(300)]

SIZES = [
    ("phone-390x844", 390, 844),
    ("tablet-portrait-768x1024", 768, 1024),
    ("tablet-1024x768", 1024, 768),
    ("tablet-1280x800", 1280, 800),
]
MIN_SHARE = 0.60
MIN_TARGET = 48

#: the live canvas's share of the window (the part of its box inside the window), and whether
#: the canvas is drawn 1:1 (its pixel size is its box: the page's room, not a stretched picture)
SHARE_JS = """() => {
  const cs = document.querySelectorAll('.pmk-home-map-stack canvas:not(.pmk-live-page)'), c = cs[cs.length - 1];
  if (!c) return null;
  const r = c.getBoundingClientRect(), W = window.innerWidth, H = window.innerHeight;
  const w = Math.max(0, Math.min(r.right, W) - Math.max(r.left, 0));
  const h = Math.max(0, Math.min(r.bottom, H) - Math.max(r.top, 0));
  return { share: (w * h) / (W * H), oneToOne: Math.abs(c.width - r.width) < 2 && Math.abs(c.height - r.height) < 2,
           box: [r.left, r.top, r.width, r.height], px: [c.width, c.height] };
}"""

#: every visible button of Home (the screen and the panels over its map) smaller than the target
SMALL_JS = """(min) => [...document.querySelectorAll('.pmk-home button, .pmk-home [role=button]')]
  .filter((b) => b.offsetParent !== null && b.getClientRects().length > 0)
  .map((b) => { const r = b.getBoundingClientRect();
                return { name: (b.textContent || b.title || b.className).trim().slice(0, 40),
                         w: r.width, h: r.height }; })
  .filter((b) => b.w < min - 0.5 || b.h < min - 0.5)"""

#: the chair's drawn centre in window coordinates, and the joystick column's box
CHAIR_JS = """() => {
  const at = document.querySelector('.pmk-home-chair-at span');
  const cs = document.querySelectorAll('.pmk-home-map-stack canvas:not(.pmk-live-page)'), c = cs[cs.length - 1];
  const drive = document.querySelector('.pmk-home-map-stack .pmk-drive');
  if (!at || !c || !drive || drive.offsetParent === null) return null;
  const r = c.getBoundingClientRect(), k = r.width / c.width;
  const d = drive.getBoundingClientRect();
  return { x: r.left + Number(at.dataset.x) * k, y: r.top + Number(at.dataset.y) * k,
           drive: [d.left, d.top, d.right, d.bottom], canvas: [r.left, r.top, r.right, r.bottom] };
}"""


def _settled_share(page: Any, timeout: float = 30.0) -> dict[str, Any]:
    """The canvas once the kernel has given it the page's room (drawn 1:1), else the last reading."""
    deadline = time.monotonic() + timeout
    last: dict[str, Any] | None = None
    while time.monotonic() < deadline:
        last = page.evaluate(SHARE_JS)
        if last is not None and last["oneToOne"] and last["share"] >= MIN_SHARE:
            time.sleep(0.3)
            again = page.evaluate(SHARE_JS)
            if again == last:
                return last
        time.sleep(0.4)
    assert last is not None, "no live canvas on Home"
    return last


def _chair_clear(page: Any, timeout: float = 20.0) -> tuple[bool, dict[str, Any] | None]:
    """Whether the chair's drawn centre is inside the map and outside the joystick column."""
    deadline = time.monotonic() + timeout
    seen: dict[str, Any] | None = None
    while time.monotonic() < deadline:
        seen = page.evaluate(CHAIR_JS)
        if seen is not None:
            x, y = seen["x"], seen["y"]
            left, top, right, bottom = seen["drive"]
            in_map = seen["canvas"][0] <= x <= seen["canvas"][2] and seen["canvas"][1] <= y <= seen["canvas"][3]
            covered = left <= x <= right and top <= y <= bottom
            if in_map and not covered:
                return True, seen
        time.sleep(0.4)
    return False, seen


def test_the_map_is_the_screen_and_nothing_covers_the_chair(tmp_path: Path) -> None:
    from playwright.sync_api import expect

    with serve_kiosk(tmp_path, label="home") as (url, _world):
        _label, w0, h0 = SIZES[0]
        with chromium_page(url, viewport={"width": w0, "height": h0}, has_touch=True) as page:
            expect(page.locator("button.pmk-home-disconnect")).to_be_visible(timeout=120_000)
            expect(page.locator(".pmk-home-info-state")).to_contain_text("Live", timeout=60_000)
            failures: list[str] = []
            ARTIFACTS.mkdir(exist_ok=True)
            for label, width, height in SIZES:
                page.set_viewport_size({"width": width, "height": height})
                reading = _settled_share(page)
                if reading["share"] < MIN_SHARE or not reading["oneToOne"]:
                    failures.append(f"{label}: the map covers {reading['share']:.0%} of the window ({reading})")
                if page.locator(".pmk-drive-toggle.mod-active").count() == 0:
                    page.locator(".pmk-drive-toggle").click()
                expect(page.locator("button.pmk-drive-stop")).to_be_visible(timeout=30_000)
                clear, seen = _chair_clear(page)
                if not clear:
                    failures.append(f"{label}: the joystick covers the chair or the chair is off the map ({seen})")
                small = page.evaluate(SMALL_JS, MIN_TARGET)
                failures += [f"{label}: button {b['name']!r} is {b['w']:.0f}x{b['h']:.0f} px" for b in small]
                page.screenshot(path=str(ARTIFACTS / f"home-{label}.png"))
                print(f"{label}: map share {reading['share']:.1%}, canvas {reading['px']}")
            failures += _two_taps_to_a_room(page)
            assert not failures, "\n".join(failures)


def _two_taps_to_a_room(page: Any) -> list[str]:
    """Phone: Set destination shows the heading buttons (no drag needed); Go to, then a room, and
    the chair is on its way; every button shown on the way is big enough."""
    from playwright.sync_api import expect

    page.set_viewport_size({"width": SIZES[0][1], "height": SIZES[0][2]})
    failures: list[str] = []
    page.locator(".pmk-goal-set").click()
    expect(page.locator(".pmk-heading-buttons")).to_be_visible(timeout=30_000)
    failures += [f"heading: {b['name']!r} is {b['w']:.0f}x{b['h']:.0f} px" for b in page.evaluate(SMALL_JS, MIN_TARGET)]
    page.screenshot(path=str(ARTIFACTS / "home-phone-heading.png"))
    page.locator(".pmk-goal-set").click()
    expect(page.locator(".pmk-heading-buttons")).to_be_hidden(timeout=30_000)
    page.locator(".pmk-home-goto").click()  # tap 1
    room = page.locator("button.pmk-goto-room").first
    expect(room).to_be_visible(timeout=30_000)
    failures += [f"Go to: {b['name']!r} is {b['w']:.0f}x{b['h']:.0f} px" for b in page.evaluate(SMALL_JS, MIN_TARGET)]
    page.screenshot(path=str(ARTIFACTS / "home-phone-goto.png"))
    name = room.inner_text().strip()
    room.click()  # tap 2
    expect(page.locator(".pmk-rooms-status")).to_contain_text(f"Going to {name}", timeout=60_000)
    expect(page.locator(".pmk-home-goto-card")).to_be_hidden()
    # the room gone to comes first next time; a starred room comes before it (kept in the settings folder)
    page.locator(".pmk-home-goto").click()
    expect(page.locator("button.pmk-goto-room").first).to_have_text(name, timeout=30_000)
    other = page.locator(".pmk-goto-row").last
    other_name = other.locator("button.pmk-goto-room").inner_text().strip()
    other.locator("button.pmk-goto-fav").click()
    expect(page.locator("button.pmk-goto-room").first).to_have_text(other_name, timeout=30_000)
    expect(page.locator("button.pmk-goto-room").nth(1)).to_have_text(name)
    page.screenshot(path=str(ARTIFACTS / "home-phone-goto-picks.png"))
    page.locator("button.pmk-goto-close").click()
    expect(page.locator(".pmk-home-goto-card")).to_be_hidden()
    return failures
