"""What floats over Home's map covers nothing it must show, at 1280x800 in Chromium (issue 40, items 4 and 7).

Against Voilà and the simulated chair (:func:`tests.browser.kiosk_page.serve_kiosk`): the status pill
leaves the scale bar visible (the bar is looked for in the screenshot where the view's insets put it),
the Details heading is one line, and the open Fleet card leaves its own Fleet button uncovered and has a
Close button that closes it.  Screenshots: ``test-artifacts/overlaps-*.png``.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from tests.browser.kiosk_page import ARTIFACTS, chromium_page, serve_kiosk
from tests.browser.test_browser_kiosk import _pixels
from tests.page_view import settled_state

pytestmark = [pytest.mark.slow, pytest.mark.browser, pytest.mark.timeout(300)]

BOX_JS = """(sel) => { const e = document.querySelector(sel);
  if (!e || e.offsetParent === null) return null;
  const r = e.getBoundingClientRect(); return [r.left, r.top, r.right, r.bottom]; }"""
CANVAS_JS = """() => {
  const cs = document.querySelectorAll('.pmk-home-map-stack canvas:not(.pmk-live-page)'), c = cs[cs.length - 1];
  const r = c.getBoundingClientRect(); return [r.left, r.top]; }"""
#: the map's name in the Details card as a long plan name would show it (the page's text, not the kernel's)
LONG_NAME_JS = """() => { const e = document.querySelector('.pmk-home-details .pmk-home-map .widget-html-content')
  || document.querySelector('.pmk-home-details .pmk-home-map');
  e.innerHTML = 'Current map: <b>' + 'uni_campus_north_building_B_'.repeat(4) + 'storey_F2</b>'; }"""
DARK = (20, 20, 20)  # the scale bar's stroke (pmk_nb.ui.live.tools)


def _overlap(a: list[float], b: list[float]) -> bool:
    return a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]


def test_panels_over_the_map_cover_nothing_they_must_not(tmp_path: Path) -> None:
    from playwright.sync_api import expect

    with (
        serve_kiosk(tmp_path, label="overlaps") as (url, _world),
        chromium_page(url, viewport={"width": 1280, "height": 800}) as page,
    ):
        expect(page.locator(".pmk-home-info-state")).to_contain_text("Live", timeout=120_000)
        ARTIFACTS.mkdir(exist_ok=True)
        failures: list[str] = []
        failures += _scale_bar_is_visible(page)
        failures += _details_heading_is_one_line(page)
        failures += _fleet_card_leaves_its_button(page)
        assert not failures, "\n".join(failures)


def _scale_bar_is_visible(page: Any) -> list[str]:
    """The bar's dark stroke where the view draws it (the uncovered part's bottom-left), outside the pill."""
    state = settled_state(page)
    left, _top, _right, bottom = state["insets"]
    height = state["px"][1]
    cx, cy = page.evaluate(CANVAS_JS)
    x0, y0 = cx + left + 12.0, cy + height - bottom - 14.0
    pill = page.evaluate(BOX_JS, ".pmk-home-statusline")
    png = page.screenshot(path=str(ARTIFACTS / "overlaps-scale-bar.png"))
    row = _pixels(png)[round(y0) - 1 : round(y0) + 2, round(x0) + 2 : round(x0) + 30]
    dark = (abs(row - list(DARK)).max(axis=2) <= 40).any(axis=0).mean()
    failures = []
    if pill is not None and _overlap([x0, y0 - 20, x0 + 30, y0 + 4], pill):
        failures.append(f"the scale bar at ({x0:.0f}, {y0:.0f}) is under the status pill {pill}")
    if dark < 0.8:
        failures.append(f"no scale bar to be seen at ({x0:.0f}, {y0:.0f}): {dark:.0%} of its stroke is dark")
    return failures


def _details_heading_is_one_line(page: Any) -> list[str]:
    from playwright.sync_api import expect

    page.locator(".pmk-home-details-toggle").click()
    expect(page.locator(".pmk-home-details")).to_be_visible(timeout=30_000)
    page.evaluate(LONG_NAME_JS)  # a map named as plans often are: long, few places to break
    box = page.evaluate(BOX_JS, ".pmk-home-details .pmk-heading")
    page.screenshot(path=str(ARTIFACTS / "overlaps-details.png"))
    page.locator(".pmk-home-details-toggle").click()
    if box is None:
        return ["the Details heading is not shown"]
    width, height = box[2] - box[0], box[3] - box[1]
    return [] if width > 2 * height else [f"the Details heading 'Home' is {width:.0f} x {height:.0f} px: not one line"]


def _fleet_card_leaves_its_button(page: Any) -> list[str]:
    from playwright.sync_api import expect

    page.locator(".pmk-fleet-toggle").click()
    expect(page.locator(".pmk-fleet-card")).to_be_visible(timeout=30_000)
    card, toggle = page.evaluate(BOX_JS, ".pmk-fleet-card"), page.evaluate(BOX_JS, ".pmk-fleet-toggle")
    page.screenshot(path=str(ARTIFACTS / "overlaps-fleet.png"))
    failures = []
    if card is None or toggle is None or _overlap(card, toggle):
        failures.append(f"the Fleet card {card} covers its own Fleet button {toggle}")
    if page.locator("button.pmk-fleet-close").count() == 0:
        return [*failures, "the Fleet card has no Close button"]
    page.locator("button.pmk-fleet-close").click()
    expect(page.locator(".pmk-fleet-card")).to_be_hidden(timeout=30_000)
    return failures
