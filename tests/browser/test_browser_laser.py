"""A blind laser on Home, in a real browser: null rays are shown as unknown, and summarised.

The simulated chair's laser is blind from 20° right to 40° left of its heading (``pmk sim
--laser-blind=-20:40``: NaN readings, sent as JSON null like every rosbridge server does). Home
must say "Laser blind ahead" and draw no free rays there; the screenshot goes to
``test-artifacts/kiosk-home-laser-blind.png``.

A ray that hits nothing within range_max is +inf, which rosbridge also sends as null: next to the
blind sector it widens what the client can see as blind (a CI run read 75° while the patrolling chair
faced a long corridor). The laser's range is therefore set past the sample floor, and the width is
read until it settles; it may never read narrower than the sector.
"""

from __future__ import annotations

import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from pmk_nb.cli.demo_setup import DemoWorld
from tests.browser.kiosk_page import ARTIFACTS, VIEWPORT, chromium_page, serve_kiosk

pytestmark = [pytest.mark.slow, pytest.mark.browser, pytest.mark.timeout(240)]


@pytest.fixture
def blind_kiosk(tmp_path: Path) -> Iterator[tuple[str, DemoWorld]]:
    with serve_kiosk(tmp_path, ["--laser-blind=-20:40", "--laser-range=100"], label="laser-blind") as served:
        yield served


def test_home_shows_a_blind_laser_sector(blind_kiosk: tuple[str, DemoWorld]) -> None:
    from playwright.sync_api import expect

    url, _world = blind_kiosk
    with chromium_page(url, viewport=VIEWPORT) as page:
        expect(page.locator(".pmk-home-info-state")).to_contain_text("Live", timeout=120_000)
        laser = page.locator(".pmk-home-info-laser")
        expect(laser).to_contain_text("Laser blind ahead", timeout=30_000)
        seen = _blind_widths(page, laser, within=30.0)
        assert min(seen) >= 55, f"the blind sector is 60° wide, Home said {min(seen)}° (readings {seen})"
        assert any(55 <= d <= 65 for d in seen), f"the blind sector is 60° wide, Home said {seen}"
        ARTIFACTS.mkdir(exist_ok=True)
        page.locator("button.pmk-home-zoom-in").click()
        page.locator("button.pmk-home-zoom-in").click()
        page.wait_for_timeout(1500)
        page.screenshot(path=str(ARTIFACTS / "kiosk-home-laser-blind.png"))


def _blind_widths(page: Any, laser: Any, within: float) -> list[int]:
    """Home's blind-sector widths, read every 0.5 s until one is 55-65° or ``within`` seconds pass."""
    seen: list[int] = []
    deadline = time.monotonic() + within
    while time.monotonic() < deadline:
        text = laser.inner_text()
        if "ahead," in text:
            seen.append(int(text.split("ahead,")[1].split("°")[0].strip()))
            if 55 <= seen[-1] <= 65:
                break
        page.wait_for_timeout(500)
    assert seen, "Home stopped saying 'Laser blind ahead'"
    return seen
