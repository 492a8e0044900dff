"""Nav2's layers on Home's live map in a real browser (issue 40 item 4): the demo's simulated chair
publishes a global costmap inflated from its map and the chair's footprint under the navigation stack's
names (move_base's on its ROS 1 demo chair); switching their toggles on draws them. Asserted on the
page's own report of what is drawn and on the pixels of the live canvas as shown (a screenshot: all
layers composed): the costmap's inscribed band (cyan) and lethal walls (magenta), the footprint
(green), none of which is on the map before. Screenshot: ``test-artifacts/layers-costmap.png``."""

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

pytestmark = [pytest.mark.slow, pytest.mark.browser, pytest.mark.timeout(240)]


def _counts(page: Any) -> dict[str, int]:
    """Pixels of each colour on the live map as the page shows it (a screenshot of the canvas: all its
    layers composed): RViz's costmap colours at alpha 0.7 and the footprint's green."""
    from PIL import Image

    png = page.locator(".pmk-live-canvas").first.screenshot()
    rgb = np.asarray(Image.open(io.BytesIO(png)).convert("RGB")).astype(int)
    r, g, b = rgb[..., 0], rgb[..., 1], rgb[..., 2]
    return {
        "cyan": int(((r < 140) & (g > 200) & (b > 200)).sum()),  # inscribed: (0, 255, 255) over the floor
        "magenta": int(((r > 140) & (g < 60) & (b > 140)).sum()),  # lethal: (255, 0, 255) over the walls
        "green": int(((g > 150) & (r < 60) & (b < 60)).sum()),  # the footprint: rgb(0, 190, 0)
    }


@pytest.fixture
def demo_page(tmp_path: Path) -> Iterator[tuple[str, DemoWorld]]:
    with serve_kiosk(tmp_path, label="layers") as served:
        yield served


def test_costmap_and_footprint_from_the_simulated_chair(demo_page: tuple[str, DemoWorld]) -> None:
    from playwright.sync_api import expect

    url, _world = demo_page
    with chromium_page(url, viewport=VIEWPORT) as page:
        expect(page.locator(".pmk-home-info-state")).to_contain_text("Live", timeout=120_000)
        page.wait_for_timeout(1000)  # a few frames of the chair alone
        before = _counts(page)
        assert before["cyan"] < 50 and before["magenta"] < 50, f"costmap colours before any layer is on: {before}"
        page.locator(".pmk-layer-global-costmap").click()
        page.locator(".pmk-layer-footprint").click()
        state = page.locator(".pmk-live-layers-state small")
        # Nav2's names on a ROS 2 chair, move_base's (/move_base/...) on a ROS 1 one
        costmap = re.compile(r"\d+x\d+ cells, .*global_costmap/costmap$")
        footprint = re.compile(r"points, .*footprint$")
        expect(state).to_have_attribute("data-global-costmap", costmap, timeout=60_000)
        expect(state).to_have_attribute("data-footprint", footprint, timeout=60_000)
        # the next frames: the costmap on the map layer, the footprint on the chair's
        after, deadline = before, time.monotonic() + 60.0
        while time.monotonic() < deadline:
            after = _counts(page)
            if after["cyan"] > 500 and after["magenta"] > 200 and after["green"] > 20:
                break
            page.wait_for_timeout(250)
        ARTIFACTS.mkdir(exist_ok=True)
        page.screenshot(path=str(ARTIFACTS / "layers-costmap.png"))
        assert after["cyan"] > 500, f"no inscribed band on the canvas: {after} (before: {before})"
        assert after["magenta"] > 200, f"no lethal walls on the canvas: {after} (before: {before})"
        assert after["green"] > 20, f"no footprint on the canvas: {after} (before: {before})"
