"""The kiosk in a real browser: Voilà serving the dashboard, headless Chromium driven by Playwright.

Walks the user's flow against the simulated chair (started like ``pmk demo`` does): Settings ->
Test connection -> Connected; Maps -> Convert -> Send; Home -> Preview, and checks that the live
canvas changes while the chair patrols.  Screenshots of every screen go to ``test-artifacts/``.
"""

from __future__ import annotations

import io
import shutil
import subprocess
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from pmk_nb.ui.cli import free_port, stop_process, wait_for_port
from pmk_nb.ui.demo import DemoWorld, prepare_demo
from pmk_nb.ui.voila_config import voila_command, write_dashboard_notebook

CHROMIUM = Path("/usr/bin/chromium")
CHROMIUM_ARGS = [
    "--no-sandbox", "--headless", "--disable-gpu", "--disable-quic", "--no-first-run",
    "--disable-background-networking", "--disable-component-update", "--disable-sync",
]  # fmt: skip
ARTIFACTS = Path(__file__).resolve().parents[1] / "test-artifacts"
VIEWPORT = {"width": 1280, "height": 800}  # a landscape tablet

pytestmark = [pytest.mark.slow, pytest.mark.browser, pytest.mark.timeout(300)]


@pytest.fixture
def kiosk(tmp_path: Path) -> Iterator[tuple[str, DemoWorld]]:
    world = prepare_demo(tmp_path / "demo")
    port = free_port()
    notebook = write_dashboard_notebook(tmp_path / "kiosk")
    log = (tmp_path / "voila.log").open("wb")
    voila = subprocess.Popen(
        voila_command(notebook, port=port), env=world.env, cwd=notebook.parent, stdout=log, stderr=subprocess.STDOUT
    )
    try:
        wait_for_port("127.0.0.1", port, voila, "Voilà", 120.0)
        yield f"http://127.0.0.1:{port}/", world
    finally:
        stop_process(voila)
        world.stop()
        log.close()
        ARTIFACTS.mkdir(exist_ok=True)
        shutil.copy(tmp_path / "voila.log", ARTIFACTS / "kiosk-voila.log")
        if world.log_path and world.log_path.exists():
            shutil.copy(world.log_path, ARTIFACTS / "kiosk-sim.log")


def _pixels(png: bytes) -> np.ndarray:
    from PIL import Image

    return np.asarray(Image.open(io.BytesIO(png)).convert("RGB"), dtype=np.int16)


def _shot(page: Any, name: str) -> None:
    ARTIFACTS.mkdir(exist_ok=True)
    page.screenshot(path=str(ARTIFACTS / f"kiosk-{name}.png"))


def test_kiosk_flow_in_chromium(kiosk: tuple[str, DemoWorld]) -> None:
    if not CHROMIUM.exists():
        pytest.fail(f"{CHROMIUM} is missing: install Debian's chromium package (apt-get install -y chromium)")
    from playwright.sync_api import expect, sync_playwright

    url, _world = kiosk
    with sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=str(CHROMIUM), args=CHROMIUM_ARGS, headless=True)
        try:
            page = browser.new_page(viewport=VIEWPORT)
            page.set_default_timeout(60_000)
            page.goto(url, wait_until="domcontentloaded")
            expect(page.locator("button.pmk-nav-home")).to_be_visible(timeout=120_000)
            expect(page.locator(".pmk-home-map")).to_contain_text("clinic_floor")
            _shot(page, "1-home")
            # -- nothing but the app: no notebook code, no traceback
            assert "build_app" not in page.content()
            assert page.locator(".jp-OutputArea-output pre").count() == 0

            # -- Settings: the demo profile is pre-filled; Test connection -> Connected + map info
            page.locator("button.pmk-nav-settings").click()
            expect(page.locator(".pmk-settings-name input")).to_have_value("Simulated chair")
            page.locator("button.pmk-settings-test").click()
            expect(page.locator(".pmk-settings-status")).to_contain_text("Connected", timeout=30_000)
            expect(page.locator(".pmk-settings-mapinfo")).to_contain_text("Map width")
            _shot(page, "2-settings-connected")

            # -- Maps: select, convert, send
            page.locator("button.pmk-nav-maps").click()
            page.locator(".pmk-maps-list select").select_option(index=0)
            expect(page.locator(".pmk-maps-details")).to_contain_text("clinic_floor")
            page.locator(".pmk-maps-resolution input").fill("0.1")
            page.locator(".pmk-maps-resolution input").press("Enter")
            page.locator("button.pmk-maps-convert").click()
            expect(page.locator(".pmk-maps-status")).to_contain_text("Converted", timeout=90_000)
            expect(page.locator(".pmk-maps-card")).to_contain_text("0.1 m")
            expect(page.locator(".pmk-maps-preview").first).to_be_visible()
            _shot(page, "3-maps-converted")
            page.locator("button.pmk-maps-send").first.click()
            expect(page.locator(".pmk-maps-status")).to_contain_text("Sent", timeout=90_000)
            _shot(page, "4-maps-sent")
            page.get_by_role("tab", name="Download").click()
            expect(page.locator("button.pmk-maps-download")).to_be_visible()
            _shot(page, "4b-maps-download")

            # -- Home: preview shows the moving chair
            page.locator("button.pmk-nav-home").click()
            page.locator("button.pmk-home-preview").click()
            canvas = page.locator(".pmk-home-preview-box canvas").last
            expect(canvas).to_be_visible()
            time.sleep(3.0)
            before = _pixels(page.locator(".pmk-home-preview-box").screenshot())
            _shot(page, "5-home-preview")
            changed = 0.0
            deadline = time.monotonic() + 20.0
            while time.monotonic() < deadline and changed < 1e-4:
                time.sleep(1.0)
                after = _pixels(page.locator(".pmk-home-preview-box").screenshot())
                changed = float(np.mean(np.any(before != after, axis=2))) if after.shape == before.shape else 1.0
            assert changed >= 1e-4, "the live canvas did not change while the chair moves"
            _shot(page, "6-home-moving")
            # something was drawn: the map is not a blank canvas
            assert float(np.std(after)) > 5.0
        finally:
            browser.close()
