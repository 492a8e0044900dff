"""The kiosk's layout on a phone, a portrait tablet, two landscape tablets and JupyterLab's main area.

For each size Home, Maps (a converted map selected, so its Send button shows) and Settings are
visited in Chromium and every visible control is MEASURED (``tests/js/measure_controls.js``): a
button whose text is cut off ("Disconn…"), a control outside the window or the app, a list row
wider than its list, a field squeezed too narrow to type in, or, on a phone, a touch target under
44 px fails the test, as does a page that scrolls sideways.  A screenshot per size and screen goes
to ``test-artifacts/layout-*.png``.

JupyterLab is emulated, not run: a 1000 px window whose app sits in a 700 px box, as in Lab's main
area beside the file browser.  The layout follows the app's own width (a CSS container), so the
box is what matters, not the window.
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any

import pytest

from tests.browser.kiosk_page import ARTIFACTS, chromium_page, serve_kiosk

pytestmark = [pytest.mark.slow, pytest.mark.browser, pytest.mark.timeout(600)]

MEASURE_JS = (Path(__file__).parents[1] / "js" / "measure_controls.js").read_text(encoding="utf-8")
#: (label, window width, window height, width of the app's box or None for the whole window)
SIZES: list[tuple[str, int, int, int | None]] = [
    ("phone-390x844", 390, 844, None),
    ("tablet-portrait-800x1280", 800, 1280, None),
    ("tablet-1024x768", 1024, 768, None),
    ("tablet-1280x800", 1280, 800, None),
    ("jupyterlab-main-700", 1000, 800, 700),
]
PHONE_MAX = 600
MIN_TOUCH = 44
#: What each screen must show, whatever the size.
MUST_SHOW = {
    "home": [
        "button.pmk-home-disconnect",
        "button.pmk-home-zoom-in",
        "button.pmk-home-zoom-out",
        ".pmk-home-sensors",
        ".pmk-drive-toggle",
        "button.pmk-drive-stop",
        ".pmk-drive-pad",
        ".pmk-drive-slow",
        ".pmk-goal-set",
    ],
    "maps": [
        ".pmk-maps-list select",
        "button.pmk-maps-refresh",
        ".pmk-maps-import",
        ".pmk-maps-resolution input",
        "button.pmk-maps-convert",
        "button.pmk-maps-send",
    ],
    "settings": [
        ".pmk-settings-name input",
        ".pmk-settings-host input",
        ".pmk-settings-auth",
        ".pmk-settings-goals-on-link-loss",
        "button.pmk-settings-save",
        "button.pmk-settings-test",
    ],
}


def _constrain_app(page: Any, width: int | None) -> None:
    """Put the app in a box of ``width`` px (JupyterLab's main area), or give it the window back."""
    page.evaluate(
        """(width) => {
            const app = document.querySelector('.pmk-app');
            // every box around the app, as Lab's main area holds its output area
            for (let box = app.parentElement; box && box !== document.body; box = box.parentElement) {
                box.style.maxWidth = width ? width + 'px' : '';
            }
            app.parentElement.style.outline = width ? '2px dashed #888' : '';
        }""",
        width,
    )


def _open(page: Any, screen: str) -> None:
    from playwright.sync_api import expect

    page.locator(f"button.pmk-nav-{screen}").click()
    if screen == "maps":
        if page.locator(".pmk-maps-list select").input_value() == "":
            page.locator(".pmk-maps-list select").select_option(index=0)
        expect(page.locator("button.pmk-maps-send").first).to_be_visible(timeout=30_000)
    elif screen == "home":
        expect(page.locator("button.pmk-home-disconnect")).to_be_visible(timeout=30_000)
        if page.locator("button.pmk-drive-stop").is_hidden():  # Drive on: the joystick is measured too
            page.locator(".pmk-drive-toggle").click()
        expect(page.locator("button.pmk-drive-stop")).to_be_visible(timeout=30_000)
    else:
        expect(page.locator("button.pmk-settings-save")).to_be_visible(timeout=30_000)
    time.sleep(0.7)  # the canvas and the lists settle after the screen swap


def _check_shell(page: Any, width: int) -> list[str]:
    """A top bar on a narrow app, the navigation column beside the content on a wide one."""
    nav = page.locator(".pmk-nav").bounding_box()
    content = page.locator(".pmk-content").bounding_box()
    assert nav is not None and content is not None
    top_bar = content["y"] >= nav["y"] + nav["height"] - 1
    if width <= PHONE_MAX and not top_bar:
        return [f"app {width} px wide: the navigation is not a top bar"]
    if width > 900 and top_bar:
        return [f"app {width} px wide: the navigation should be a column beside the content"]
    if content["width"] < 0.5 * width:
        return [f"app {width} px wide: the content has only {content['width']:.0f} px"]
    return []


def _reachable(page: Any, selector: str, height: int) -> str | None:
    """Shown, and brought fully into the window by scrolling (the content scrolls vertically)."""
    item = page.locator(selector).first
    if not item.is_visible():
        return f"{selector} is not shown"
    item.scroll_into_view_if_needed()
    box = item.bounding_box()
    if box is None or box["y"] < -0.5 or box["y"] + box["height"] > height + 0.5:
        return f"{selector} cannot be scrolled into the window ({box})"
    # what a finger at its centre touches: another element drawn over it, or a parent that clips it
    on_top = item.evaluate(
        "(el) => { const r = el.getBoundingClientRect();"
        " const hit = document.elementFromPoint(r.x + r.width / 2, r.y + r.height / 2);"
        " return hit !== null && (el.contains(hit) || hit.contains(el)); }"
    )
    if not on_top:
        return f"{selector} is covered or clipped at its centre"
    return None


def _measure(page: Any, label: str, screen: str, app_width: int, height: int) -> list[str]:
    problems = [p for p in (_reachable(page, s, height) for s in MUST_SHOW[screen]) if p]
    page.evaluate("() => { document.querySelectorAll('*').forEach((e) => { if (e.scrollTop) e.scrollTop = 0; }); }")
    result = page.evaluate(
        MEASURE_JS, {"minTouch": MIN_TOUCH if app_width <= PHONE_MAX else 0, "appSelector": ".pmk-app"}
    )
    assert result["controls"] >= len(MUST_SHOW[screen]), result
    problems += result["problems"]
    if result["horizontalScroll"]:
        problems.append(f"the page scrolls sideways ({result['scrollWidth']} px in {result['clientWidth']} px)")
    if result["appWidth"] > app_width or result["appWidth"] < app_width - 40:  # the page's own margins
        problems.append(f"the app is {result['appWidth']:.0f} px wide in a {app_width} px box")
    ARTIFACTS.mkdir(exist_ok=True)
    # the whole app, also what lies below the window on a phone: Voilà scrolls inside the page, so
    # the window is made as tall as the app for the picture
    size = page.viewport_size
    tall = page.evaluate("() => document.querySelector('.pmk-app').getBoundingClientRect().height")
    page.set_viewport_size({"width": size["width"], "height": max(size["height"], int(tall) + 60)})
    time.sleep(0.3)
    page.locator(".pmk-app").screenshot(path=str(ARTIFACTS / f"layout-{label}-{screen}.png"))
    page.set_viewport_size(size)
    return [f"{label} {screen}: {p}" for p in problems]


def test_every_control_fits_at_every_size(tmp_path: Path) -> None:
    from playwright.sync_api import expect

    with serve_kiosk(tmp_path, label="layout") as (url, _world):
        first = SIZES[0]
        with chromium_page(url, viewport={"width": first[1], "height": first[2]}, has_touch=True) as page:
            expect(page.locator("button.pmk-nav-home")).to_be_visible(timeout=120_000)
            failures: list[str] = []
            for label, width, height, box in SIZES:
                page.set_viewport_size({"width": width, "height": height})
                _constrain_app(page, box)
                time.sleep(0.5)
                app_width = box or width
                failures += [f"{label}: {p}" for p in _check_shell(page, app_width)]
                for screen in ("home", "maps", "settings"):
                    _open(page, screen)
                    failures += _measure(page, label, screen, app_width, height)
            assert not failures, "\n".join(failures)
