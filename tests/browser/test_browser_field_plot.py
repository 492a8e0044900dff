"""Plot anything in a real browser on the demo page (issue 40): in Home's Plots panel, pick /odom and
its pose.pose.position.x from the field plot's lists, Add, and a series is drawn: the legend names the
field with a latest value that moves on as the demo chair patrols, and the chart's canvas gains the
series' colour and keeps changing; the TF tree below shows map → odom → base_link.
Screenshot: ``test-artifacts/field-plot.png``."""

from __future__ import annotations

import io
import re
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from pmk_nb.cli.demo_setup import DemoWorld
from tests.browser.kiosk_page import ARTIFACTS, VIEWPORT, chromium_page, serve_kiosk

pytestmark = [pytest.mark.slow, pytest.mark.browser, pytest.mark.timeout(300)]

FIELD = "pose.pose.position.x"
LEGEND = re.compile(r"/odom pose\.pose\.position\.x = (-?[\d.e+-]+)")


def _chart(page: Any) -> np.ndarray:
    """The field plot's canvas as the page shows it (RGB)."""
    from PIL import Image

    png = page.locator(".pmk-fieldplot-chart").first.screenshot()
    return np.asarray(Image.open(io.BytesIO(png)).convert("RGB")).astype(int)


def _blue(rgb: np.ndarray) -> int:
    """Pixels of the first series' colour, rgb(25, 90, 220)."""
    r, g, b = rgb[..., 0], rgb[..., 1], rgb[..., 2]
    return int(((r < 90) & (g > 50) & (g < 140) & (b > 170)).sum())


def _drawn(page: Any) -> list[np.ndarray] | None:
    """[the chart] once the first series' line is on it (a list: an array has no truth value)."""
    shot = _chart(page)
    return [shot] if _blue(shot) > 20 else None


def _until(what: str, cond: Any, page: Any, timeout: float = 60.0) -> Any:
    """Poll ``cond()`` (truthy: done) on the page's time, up to ``timeout`` s; fail naming ``what``."""
    deadline = time.monotonic() + timeout
    while True:
        found = cond()
        if found or time.monotonic() > deadline:
            assert found, f"timed out waiting for {what}"
            return found
        page.wait_for_timeout(250)


@pytest.fixture
def demo_page(tmp_path: Path) -> Iterator[tuple[str, DemoWorld]]:
    with serve_kiosk(tmp_path, label="fieldplot") as served:
        yield served


def test_a_picked_field_is_plotted_on_the_demo_page(demo_page: tuple[str, DemoWorld]) -> None:
    from playwright.sync_api import expect

    url, _world = demo_page
    with chromium_page(url, viewport={**VIEWPORT, "height": 1300}) as page:
        expect(page.locator(".pmk-home-info-state")).to_contain_text("Live", timeout=120_000)
        page.locator(".pmk-plots-toggle").click()
        expect(page.locator(".pmk-plots-panel")).to_be_visible(timeout=20_000)
        expect(page.locator(".pmk-topics-source")).to_contain_text("topics from rosapi", timeout=60_000)
        page.locator(".pmk-fieldplot").evaluate("e => e.scrollIntoView()")
        before = _blue(_chart(page))
        topic = page.locator(".pmk-fieldplot-topic select")
        expect(topic.locator("option", has_text="/odom")).to_have_count(1, timeout=30_000)
        topic.select_option(label="/odom")
        status = page.locator(".pmk-fieldplot-status")
        expect(status).to_contain_text("numeric fields of", timeout=60_000)  # the type's fields listed
        field = page.locator(".pmk-fieldplot-field input")
        expect(page.locator(f".pmk-fieldplot-field option[value='{FIELD}']")).to_have_count(1, timeout=10_000)
        field.fill(FIELD)
        page.locator(".pmk-fieldplot-add").click()
        legend = page.locator(".pmk-fieldplot-legend")
        expect(legend).to_contain_text(f"/odom {FIELD} = ", timeout=60_000)
        first = _until("a value in the legend", lambda: LEGEND.search(legend.inner_text()), page)[1]
        # the demo chair patrols: the latest x moves on, and so does the drawn line
        _until("the legend's value to move on", lambda: LEGEND.search(legend.inner_text())[1] != first, page, 90.0)
        drawn = _until("the series on the canvas", lambda: _drawn(page), page)[0]
        assert before < 20, f"the series' colour on the chart before any series: {before} pixels"
        _until("the chart to change", lambda: not np.array_equal(_chart(page), drawn), page)
        tf = page.locator(".pmk-tftree-table")  # the TF tree below, on the same page
        expect(tf).to_contain_text("map → odom", timeout=60_000)
        expect(tf).to_contain_text("odom → base_link", timeout=10_000)
        expect(tf).to_contain_text("Hz", timeout=10_000)
        ARTIFACTS.mkdir(exist_ok=True)
        page.screenshot(path=str(ARTIFACTS / "field-plot.png"))
