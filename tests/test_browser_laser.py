"""A blind laser on Home, in a real browser: null rays are shown as unknown, and summarised.

The simulated chair's laser is blind from 20° right to 40° left of its heading (``pmk sim
--laser-blind=-20:40``: NaN readings, sent as JSON null like every rosbridge server does). Home
must say "Laser blind ahead" and draw no free rays there; the screenshot goes to
``test-artifacts/kiosk-home-laser-blind.png``.
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest

from pmk_nb.cli.demo_setup import DemoWorld
from tests.test_browser_kiosk import ARTIFACTS, VIEWPORT, chromium_page, serve_kiosk

pytestmark = [pytest.mark.slow, pytest.mark.browser, pytest.mark.timeout(240)]


@pytest.fixture
def blind_kiosk(tmp_path: Path) -> Iterator[tuple[str, DemoWorld]]:
    with serve_kiosk(tmp_path, ["--laser-blind=-20:40"], label="laser-blind") as served:
        yield served


def test_home_shows_a_blind_laser_sector(blind_kiosk: tuple[str, DemoWorld]) -> None:
    from playwright.sync_api import expect

    url, _world = blind_kiosk
    with chromium_page(url, viewport=VIEWPORT) as page:
        expect(page.locator(".pmk-home-info-state")).to_contain_text("Live", timeout=120_000)
        laser = page.locator(".pmk-home-info-laser")
        expect(laser).to_contain_text("Laser blind ahead", timeout=30_000)
        degrees = int(laser.inner_text().split("ahead,")[1].strip().rstrip("°"))
        assert 55 <= degrees <= 65, f"the blind sector is 60° wide, Home says {degrees}°"
        ARTIFACTS.mkdir(exist_ok=True)
        page.locator("button.pmk-home-zoom-in").click()
        page.locator("button.pmk-home-zoom-in").click()
        page.wait_for_timeout(1500)
        page.screenshot(path=str(ARTIFACTS / "kiosk-home-laser-blind.png"))
