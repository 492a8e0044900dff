"""Plots and the topic inspector in a real browser on the demo page (issue 29 item 4): Home's Plots
toggle opens the speed / turn-rate chart and the topic list; picking /odom shows its rate and latest
message. Screenshot: ``test-artifacts/plots.png`` (the demo chair patrols, so the chart has lines and
the simulator's planned path is drawn on the map)."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest

from pmk_nb.cli.demo_setup import DemoWorld
from tests.browser.kiosk_page import ARTIFACTS, VIEWPORT, chromium_page, serve_kiosk

pytestmark = [pytest.mark.slow, pytest.mark.browser, pytest.mark.timeout(240)]


@pytest.fixture
def demo_page(tmp_path: Path) -> Iterator[tuple[str, DemoWorld]]:
    with serve_kiosk(tmp_path, label="plots") as served:
        yield served


def test_plots_and_topic_inspector_on_the_demo_page(demo_page: tuple[str, DemoWorld]) -> None:
    from playwright.sync_api import expect

    url, _world = demo_page
    with chromium_page(url, viewport={**VIEWPORT, "height": 1300}) as page:  # tall: chart, list and message
        expect(page.locator(".pmk-home-info-state")).to_contain_text("Live", timeout=120_000)
        panel = page.locator(".pmk-plots-panel")
        expect(panel).to_be_hidden()
        page.locator(".pmk-plots-toggle").click()
        expect(panel).to_be_visible(timeout=10_000)
        expect(page.locator(".pmk-plots-legend")).to_contain_text("m/s", timeout=10_000)
        expect(page.locator(".pmk-topics-source")).to_contain_text("topics from rosapi", timeout=30_000)
        select = page.locator(".pmk-topics-list select")
        labels = select.locator("option").all_inner_texts()
        found = [i for i, label in enumerate(labels) if label.split()[:1] == ["/odom"]]
        assert found, labels
        odom = found[0]
        select.select_option(index=odom)
        expect(page.locator(".pmk-topics-info")).to_contain_text("Hz", timeout=20_000)
        message = page.locator(".pmk-topics-message")
        expect(message).to_contain_text('"twist"', timeout=20_000)
        page.wait_for_timeout(1500)  # a few chart redraws (2 Hz) with the chair patrolling
        ARTIFACTS.mkdir(exist_ok=True)
        page.locator(".pmk-plots-panel").evaluate("e => e.scrollIntoView()")  # the page scrolls inside the app
        page.screenshot(path=str(ARTIFACTS / "plots.png"))
