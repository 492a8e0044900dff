"""WCAG 2.2 AA in Chromium against the demo kiosk (Voilà + simulated chair), checked by axe-core.

- axe-core (tests/js, the WCAG 2.0/2.1/2.2 A and AA tags, no rule left out) finds no violation on
  Home (Drive on), Maps (a map selected) and Settings at phone, tablet portrait, 1024x768 and
  1280x800, then again with the profile's high-contrast theme and large text on (screenshots
  ``test-artifacts/a11y-high-contrast.png`` and ``a11y-large-text.png``).
- Home's status changes reach an ``aria-live`` region: going to a room, the polite region (the
  same element all along, so a screen reader keeps listening) says "Arrived at …".
- Home by keyboard alone: Tab reaches every control, each shows a focus ring of >= 2 px at
  >= 3:1 against what surrounds it, Space turns Drive on and Enter presses Stop (the drive's
  status says so and the assertive region announces it).

One Voilà server for the module (the tests run in this order: the theme test puts the profile
back, the Stop latch comes last); one page per test, resized between sizes.
"""

from __future__ import annotations

import re
import time
from collections.abc import Iterator
from typing import Any

import pytest
import shapely

from pmk_nb.chair.link import ChairLink
from pmk_nb.cli.demo_setup import DemoWorld
from pmk_nb.drive import StopReason
from pmk_nb.guide import load_rooms
from pmk_nb.ui.common.a11y_style import FOCUS_PX
from pmk_nb.ui.common.contrast import NON_TEXT_AA, contrast_ratio
from pmk_nb.ui.drive.panel import STOPPED
from tests.axe_probe import describe, run_axe
from tests.browser.kiosk_page import ARTIFACTS, chromium_page, serve_kiosk
from tests.browser.test_browser_layout import _open

pytestmark = [pytest.mark.slow, pytest.mark.browser, pytest.mark.timeout(300)]

SIZES = [(390, 844), (768, 1024), (1024, 768), (1280, 800)]
SCREENS = ("home", "maps", "settings")
#: Home's controls that Tab must reach (Drive on)
HOME_CONTROLS = {
    "pmk-nav-home",
    "pmk-nav-maps",
    "pmk-nav-settings",
    "pmk-home-disconnect",
    "pmk-home-sensors",
    "pmk-home-zoom-in",
    "pmk-home-zoom-out",
    "pmk-live-follow",
    "pmk-drive-toggle",
    "pmk-drive-stop",
    "pmk-drive-pad",
    "pmk-drive-slow",
    "pmk-goal-set",
    "pmk-rooms-search",
    "pmk-rooms-list",
    "pmk-rooms-go",
}
FOCUSED_JS = """() => {
  const el = document.activeElement;
  if (!el || el === document.body) return null;
  const named = (e) => { for (; e; e = e.parentElement) {
      const c = [...e.classList].find((k) => k.startsWith('pmk-')); if (c) return c; } return ''; };
  let bg = 'rgb(255, 255, 255)';
  for (let p = el.parentElement; p; p = p.parentElement) {
    const c = getComputedStyle(p).backgroundColor;
    if (c && c !== 'transparent' && !/rgba\\(.*, 0\\)$/.test(c)) { bg = c; break; }
  }
  const cs = getComputedStyle(el);
  const r = el.getBoundingClientRect();
  return {name: named(el), tag: el.tagName, inApp: !!el.closest('.pmk-app'), visible: r.width > 0 && r.height > 0,
          style: cs.outlineStyle, width: parseFloat(cs.outlineWidth), colour: cs.outlineColor, bg};
}"""


@pytest.fixture(scope="module")
def kiosk(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[str, DemoWorld]]:
    with serve_kiosk(tmp_path_factory.mktemp("a11y"), label="a11y") as served:
        yield served


def _hex(css: str) -> str:
    """``rgb(r, g, b)`` / ``rgba(r, g, b, a)`` -> ``#rrggbb`` (alpha left out)."""
    parts = re.findall(r"[\d.]+", css)
    if len(parts) < 3:
        raise AssertionError(f"not an rgb() colour: {css!r}")
    return "#" + "".join(f"{round(float(p)):02x}" for p in parts[:3])


def _axe_everywhere(page: Any, label: str, sizes: list[tuple[int, int]]) -> list[str]:
    """axe on each screen at each size: a screen is opened once and the window resized under it."""
    failures = []
    for screen in SCREENS:
        page.set_viewport_size({"width": sizes[0][0], "height": sizes[0][1]})
        _open(page, screen)
        for i, (width, height) in enumerate(sizes):
            if i:
                page.set_viewport_size({"width": width, "height": height})
                page.wait_for_timeout(400)  # the container rules and the canvas settle
            violations = run_axe(page)
            if violations:
                failures.append(f"{label} {screen} {width}x{height}:\n{describe(violations)}")
    return failures


def _shot_home(page: Any, name: str) -> None:
    page.set_viewport_size({"width": 1280, "height": 800})
    _open(page, "home")
    page.screenshot(path=str(ARTIFACTS / name))


def _set_display(page: Any, high_contrast: bool, large_text: bool) -> None:
    """Settings: the two display choices, Save; the app root takes the classes."""
    from playwright.sync_api import expect

    _open(page, "settings")
    choice = {True: 1, False: 0}
    page.locator(".pmk-settings-high-contrast button").nth(choice[high_contrast]).click()
    page.locator(".pmk-settings-large-text button").nth(choice[large_text]).click()
    page.wait_for_timeout(400)  # the choices reach the kernel before Save does
    page.locator("button.pmk-settings-save").click()
    expect(page.locator(".pmk-settings-message")).to_contain_text("Saved", timeout=30_000)
    app = page.locator(".pmk-app")
    for css, on in (("pmk-high-contrast", high_contrast), ("pmk-large-text", large_text)):
        if on:
            expect(app).to_have_class(re.compile(rf"\b{css}\b"), timeout=10_000)
        else:
            expect(app).not_to_have_class(re.compile(rf"\b{css}\b"), timeout=10_000)


def test_axe_finds_no_wcag_violation_at_any_size_nor_with_the_display_settings(
    kiosk: tuple[str, DemoWorld],
) -> None:
    from playwright.sync_api import expect

    url, _world = kiosk
    with chromium_page(url, viewport={"width": 390, "height": 844}, has_touch=True) as page:
        expect(page.locator("button.pmk-nav-home")).to_be_visible(timeout=120_000)
        failures = _axe_everywhere(page, "standard", SIZES)
        ARTIFACTS.mkdir(exist_ok=True)
        try:
            # the themes change colours and sizes, not the layout's breakpoints: the smallest and
            # the largest size for high contrast, a middle one for large text (the suite stays quick)
            _set_display(page, high_contrast=True, large_text=False)
            failures += _axe_everywhere(page, "high contrast", [SIZES[0], SIZES[-1]])
            _shot_home(page, "a11y-high-contrast.png")
            _set_display(page, high_contrast=False, large_text=True)
            failures += _axe_everywhere(page, "large text", [SIZES[2]])
            _shot_home(page, "a11y-large-text.png")
        finally:
            _set_display(page, high_contrast=False, large_text=False)
        assert not failures, "\n".join(failures)


def _nearest_room(world: DemoWorld) -> str:
    """The destination closest to where the simulated chair is now (a short drive)."""
    rooms = load_rooms(world.map_yaml)
    link = ChairLink("127.0.0.1", world.ros_port)
    try:
        link.connect(timeout=30.0)
        link.start_streams()
        deadline = time.monotonic() + 20
        while (odom := link.latest_odom()) is None and time.monotonic() < deadline:
            time.sleep(0.2)
        assert odom is not None, "no odometry from the simulated chair"
        here = shapely.Point(odom.x, odom.y)
        return min(rooms.destinations(), key=lambda r: r.polygon.distance(here)).label
    finally:
        link.close()


def test_arrival_is_announced_in_a_polite_live_region(kiosk: tuple[str, DemoWorld]) -> None:
    from playwright.sync_api import expect

    url, world = kiosk
    with chromium_page(url, viewport={"width": 1280, "height": 800}) as page:
        expect(page.locator(".pmk-rooms-here")).to_contain_text("You are in:", timeout=120_000)
        polite = page.locator(".pmk-live-polite > .widget-html-content")
        assertive = page.locator(".pmk-live-assertive > .widget-html-content")
        expect(polite).to_have_attribute("aria-live", "polite", timeout=10_000)
        expect(polite).to_have_attribute("role", "status")
        expect(assertive).to_have_attribute("aria-live", "assertive")
        expect(assertive).to_have_attribute("role", "alert")
        region = polite.element_handle()
        target = _nearest_room(world)
        page.locator(".pmk-rooms-search input").fill(target.split()[0])
        page.locator(".pmk-rooms-list select").select_option(label=target)
        page.wait_for_timeout(500)  # the pick reaches the kernel before Go does
        page.locator("button.pmk-rooms-go").click()
        expect(polite).to_contain_text(f"Going to {target}.", timeout=20_000)
        expect(polite).to_contain_text(f"Arrived at {target}.", timeout=120_000)
        # the same element heard the whole time (a region created anew is often not announced)
        assert region.evaluate("(el) => el.isConnected && el.textContent.includes('Arrived')")


def test_home_works_from_the_keyboard_with_a_visible_focus(kiosk: tuple[str, DemoWorld]) -> None:
    from playwright.sync_api import expect

    url, _world = kiosk
    with chromium_page(url, viewport={"width": 1280, "height": 800}) as page:
        expect(page.locator("button.pmk-home-disconnect")).to_be_visible(timeout=120_000)
        expect(page.locator(".pmk-drive-toggle")).to_be_visible(timeout=30_000)
        page.locator("body").click(position={"x": 2, "y": 2})  # start from the page, not a control
        reached: dict[str, dict[str, Any]] = {}
        problems: list[str] = []
        stopped = False
        for _ in range(120):
            page.keyboard.press("Tab")
            focus = page.evaluate(FOCUSED_JS)
            if focus is None or not focus["inApp"]:
                continue
            name = focus["name"]
            if name in reached and set(HOME_CONTROLS) <= set(reached) and "pmk-drive-claim" in reached:
                break  # round the page once, and past Stop's "Release the Stop"
            reached.setdefault(name, focus)
            ratio = contrast_ratio(_hex(focus["colour"]), _hex(focus["bg"]))
            if focus["style"] == "none" or focus["width"] < 2 or ratio < NON_TEXT_AA:
                problems.append(f"{name} ({focus['tag']}): ring {focus['style']} {focus['width']} px, {ratio:.2f}:1")
            if name == "pmk-drive-toggle" and page.locator("button.pmk-drive-stop").is_hidden():
                page.keyboard.press("Space")  # Drive on: the joystick, Stop and Slow come after it
                expect(page.locator("button.pmk-drive-stop")).to_be_visible(timeout=30_000)
            # Stop on the second round: the page that pressed it shows "Release the Stop" in Slow's place
            if name == "pmk-drive-stop" and not stopped and "pmk-drive-slow" in reached:
                page.keyboard.press("Enter")
                expect(page.locator(".pmk-drive-status")).to_contain_text(
                    STOPPED[StopReason.STOP_BUTTON], timeout=10_000
                )
                expect(page.locator(".pmk-live-assertive > .widget-html-content")).to_contain_text(
                    "Stopped", timeout=10_000
                )
                stopped = True
        page.screenshot(path=str(ARTIFACTS / "a11y-keyboard.png"))
        missing = sorted(HOME_CONTROLS - set(reached))
        assert not missing, f"Tab never reached {missing}; reached {sorted(reached)}"
        assert stopped, "Stop was never focused"
        assert "pmk-drive-claim" in reached, "Tab never reached Release the Stop after Stop"
        assert not problems, "focus not visible enough:\n" + "\n".join(problems)
        assert min(f["width"] for f in reached.values()) >= FOCUS_PX - 0.5
