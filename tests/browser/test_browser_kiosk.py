"""The kiosk in a real browser: Voilà serving the dashboard, headless Chromium driven by Playwright.

Walks the user's flow against the simulated chair (started like ``pmk demo`` does): the first page
already shows the chair moving (the demo starts the preview by itself), laid out to fit a 1280 x 800
and a 1024 x 768 landscape tablet; Settings -> Test connection -> Connected; Maps -> Convert ->
Send; Home -> Disconnect -> Preview, and checks that the live canvas changes while the chair
patrols.  Screenshots of every screen go to ``test-artifacts/``.
"""

from __future__ import annotations

import io
import re
import subprocess
import time
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from pmk_nb.cli.demo_setup import DemoWorld
from pmk_nb.serve.procs import free_port, stop_process
from tests.browser.kiosk_page import (
    ARTIFACTS,
    SMALL_VIEWPORT,
    VIEWPORT,
    chromium_page,
    serve_kiosk,
)

pytestmark = [pytest.mark.slow, pytest.mark.browser, pytest.mark.timeout(300)]


def _pixels(png: bytes) -> np.ndarray:
    from PIL import Image

    return np.asarray(Image.open(io.BytesIO(png)).convert("RGB"), dtype=np.int16)


def _shot(page: Any, name: str) -> None:
    ARTIFACTS.mkdir(exist_ok=True)
    page.screenshot(path=str(ARTIFACTS / f"kiosk-{name}.png"))


def _canvas_changes(page: Any, seconds: float = 20.0) -> float:
    """Fraction of the live canvas's pixels that changed while waiting (up to ``seconds``)."""
    box = page.locator(".pmk-home-preview-box .pmk-live-canvas")
    before = _pixels(box.screenshot())
    changed = 0.0
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline and changed < 1e-4:
        time.sleep(1.0)
        after = _pixels(box.screenshot())
        changed = float(np.mean(np.any(before != after, axis=2))) if after.shape == before.shape else 1.0
    assert float(np.std(after)) > 5.0, "the live canvas is blank: no map drawn"
    return changed


def _check_home_layout(page: Any, size: dict[str, int]) -> None:
    """The map fits the window without being stretched, and the tool bar floats over it (issue 28:
    the map is the screen; the zoom buttons are in the bar, inside the map's box)."""
    canvas = page.locator(".pmk-home-preview-box .pmk-live-canvas")
    box = canvas.bounding_box()
    toolbar = page.locator(".pmk-home-toolbar").bounding_box()
    zoom_in = page.locator("button.pmk-home-zoom-in").bounding_box()
    assert box is not None and toolbar is not None and zoom_in is not None
    assert box["x"] + box["width"] <= size["width"] + 0.5 and box["y"] + box["height"] <= size["height"] + 0.5
    attr_w, attr_h = (int(canvas.get_attribute(a) or 0) for a in ("width", "height"))
    assert abs(box["width"] / box["height"] - attr_w / attr_h) < 0.02, "the canvas is stretched"
    inside = box["x"] - 0.5 <= toolbar["x"] and toolbar["x"] + toolbar["width"] <= box["x"] + box["width"] + 0.5
    assert inside and box["y"] - 0.5 <= toolbar["y"] < box["y"] + 24, "the tool bar does not float over the map"
    assert box["x"] <= zoom_in["x"] and zoom_in["x"] + zoom_in["width"] <= box["x"] + box["width"] + 0.5


def test_kiosk_flow_in_chromium(kiosk: tuple[str, DemoWorld]) -> None:
    from playwright.sync_api import expect

    url, _world = kiosk
    with chromium_page(url, viewport=VIEWPORT, has_touch=True) as page:  # a tablet: touch events on
        expect(page.locator("button.pmk-nav-home")).to_be_visible(timeout=120_000)
        expect(page.locator(".pmk-home-map")).to_contain_text("clinic_floor")
        # -- a first-time user sees the chair moving without pressing anything (demo autostart)
        expect(page.locator("button.pmk-home-disconnect")).to_be_visible(timeout=30_000)
        expect(page.locator(".pmk-home-info-state")).to_contain_text("Live", timeout=30_000)
        assert _canvas_changes(page) >= 1e-4, "the chair does not move on the first page"
        _shot(page, "1-home")
        _check_home_layout(page, VIEWPORT)
        # -- nothing but the app: no notebook code, no traceback
        assert "build_app" not in page.content()
        assert page.locator(".jp-OutputArea-output pre").count() == 0
        # -- an older 1024 x 768 tablet: the map scales down and still fits
        page.set_viewport_size(SMALL_VIEWPORT)
        time.sleep(1.0)
        _shot(page, "1b-home-1024x768")
        _check_home_layout(page, SMALL_VIEWPORT)
        page.set_viewport_size(VIEWPORT)

        # -- Settings: the demo profile is pre-filled; Test connection -> Connected + map info
        page.locator("button.pmk-nav-settings").click()
        expect(page.locator(".pmk-settings-name input")).to_have_value("Simulated chair")
        page.locator("button.pmk-settings-test").click()
        expect(page.locator(".pmk-settings-status")).to_contain_text("Connected", timeout=30_000)
        expect(page.locator(".pmk-settings-mapinfo")).to_contain_text("Map width")
        _shot(page, "2-settings-connected")

        # -- Maps: select, convert, send (key login: no password asked)
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
        expect(page.locator(".pmk-maps-hostkey")).to_contain_text("SHA256:", timeout=60_000)  # first use: asked
        _shot(page, "4a-maps-host-key")
        page.locator("button.pmk-maps-hostkey-yes").click()
        expect(page.locator(".pmk-maps-status")).to_contain_text("Sent", timeout=90_000)
        _shot(page, "4-maps-sent")
        page.get_by_role("tab", name="Download").click()
        expect(page.locator("button.pmk-maps-download")).to_be_visible()
        _shot(page, "4b-maps-download")

        # -- Home: live again by itself; Disconnect stops it, Preview starts it again
        page.locator("button.pmk-nav-home").click()
        page.locator("button.pmk-home-disconnect").click()
        expect(page.locator("button.pmk-home-preview")).to_be_visible()
        expect(page.locator("button.pmk-home-disconnect")).to_be_hidden()
        expect(page.locator(".pmk-home-preview-box .pmk-live-canvas")).to_be_visible()  # the map stays on screen
        _shot(page, "5-home-stopped")
        page.locator("button.pmk-home-preview").click()
        expect(page.locator(".pmk-home-preview-box .pmk-live-canvas")).to_be_visible()
        time.sleep(3.0)
        assert _canvas_changes(page) >= 1e-4, "the live canvas did not change while the chair moves"
        _shot(page, "6-home-moving")

        # -- zoom: the buttons, the mouse wheel and a two-finger pinch (real touch events)
        zoom = page.locator(".pmk-home-info-zoom")
        page.locator("button.pmk-home-zoom-in").click()
        expect(zoom).to_contain_text("Zoom: 2")
        box = page.locator(".pmk-home-preview-box .pmk-live-canvas").bounding_box()
        assert box is not None
        cx, cy = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
        page.mouse.move(cx, cy)
        page.mouse.wheel(0, -120)  # wheel up zooms in
        expect(zoom).to_contain_text("Zoom: 3")
        time.sleep(1.0)
        _shot(page, "7-home-zoomed")
        cdp = page.context.new_cdp_session(page)

        def touch(kind: str, spread: float | None) -> None:
            points = [] if spread is None else [{"x": cx - spread, "y": cy}, {"x": cx + spread, "y": cy}]
            cdp.send("Input.dispatchTouchEvent", {"type": kind, "touchPoints": points})

        touch("touchStart", 40)
        for spread in (60, 90, 130, 135):  # fingers apart: x3.4 -> three levels in at 1.5 per level
            touch("touchMove", spread)
            time.sleep(0.2)
        touch("touchEnd", None)
        expect(zoom).to_contain_text("Zoom: 6")
        page.locator("button.pmk-home-zoom-out").click()
        expect(zoom).to_contain_text("Zoom: 5")


# --- kiosk mode (`pmk dashboard --kiosk`, `pmk demo`): Home only, big targets, PIN, screen kept on ----


def _pin_prompt_says(page: Any, typed: str, expected: str, *, enter: bool = False) -> None:
    from playwright.sync_api import expect

    box = page.locator(".pmk-kiosk-pin input")
    box.fill(typed)
    if enter:  # Enter in the box submits as Unlock does (kiosk.PIN_ENTER_SCRIPT)
        box.press("Enter")
    else:
        page.locator("button.pmk-kiosk-unlock").click()
    expect(box).to_have_value("", timeout=30_000)  # the kernel took the PIN (it empties the box)
    expect(page.locator(".pmk-kiosk-pin-status")).to_contain_text(expected, timeout=30_000)


def test_kiosk_mode_locks_maps_and_settings_behind_the_pin(tmp_path: Path) -> None:
    from playwright.sync_api import expect

    from pmk_nb.ui.kiosk.pin import KIOSK_ENV, LOCKOUT_S, MAX_TRIES

    with (
        serve_kiosk(tmp_path, label="kiosk-mode", env={KIOSK_ENV: "1"}) as (url, _world),
        chromium_page(url, viewport=VIEWPORT, has_touch=True) as page,
    ):
        expect(page.locator(".pmk-kiosk button.pmk-nav-home")).to_be_visible(timeout=120_000)
        expect(page.locator(".pmk-home-info-state")).to_contain_text("Live", timeout=60_000)
        # -- Home with big targets: every visible button on the page is at least 60 px tall
        heights = page.eval_on_selector_all(
            "button", "bs => bs.filter(b => b.offsetParent !== null).map(b => [b.className, b.offsetHeight])"
        )
        assert heights and all(h >= 60 for _c, h in heights), f"small touch targets: {heights}"
        assert page.locator("button.pmk-nav-home").bounding_box()["height"] >= 90  # type: ignore[index]
        for name in ("maps", "settings"):  # no PIN yet: they open freely, so no lock icon (issue 29 item 9)
            assert page.locator(f"button.pmk-nav-{name} i.fa-lock").count() == 0
        # -- the screen is kept on, or the page says it cannot be (headless Chromium may refuse)
        expect(page.locator(".pmk-wakelock")).to_have_attribute("data-state", re.compile("on|off"))
        assert "screen" in (page.locator(".pmk-wakelock").text_content() or "").lower()
        _shot(page, "mode-1-home")

        # -- no PIN yet: Settings opens and says how to lock it; the PIN is set there
        page.locator("button.pmk-nav-settings").click()
        expect(page.locator(".pmk-kiosk-pin-state")).to_contain_text("No PIN yet")
        page.locator(".pmk-kiosk-pin-new input").fill("12")
        page.locator(".pmk-kiosk-pin-repeat input").fill("12")
        page.locator("button.pmk-kiosk-pin-set").click()
        expect(page.locator(".pmk-kiosk-pin-message")).to_contain_text("4 to 12 digits")
        page.locator(".pmk-kiosk-pin-new input").fill("4711")
        page.locator(".pmk-kiosk-pin-repeat input").fill("4711")
        page.locator("button.pmk-kiosk-pin-set").click()
        expect(page.locator(".pmk-kiosk-pin-message")).to_contain_text("PIN saved")
        expect(page.locator(".pmk-kiosk-pin-state")).to_contain_text("A PIN protects")
        _shot(page, "mode-2-settings-pin-set")

        # -- back Home locks again: Maps asks for the PIN and shows nothing of Maps
        page.locator("button.pmk-nav-home").click()
        for name in ("maps", "settings"):  # locked screens say so on their button, once a PIN is set
            expect(page.locator(f"button.pmk-nav-{name} i.fa-lock")).to_have_count(1, timeout=10_000)
        page.locator("button.pmk-nav-maps").click()
        expect(page.locator(".pmk-kiosk-pin-box")).to_contain_text("Enter the PIN to open Maps", timeout=30_000)
        assert page.locator(".pmk-maps-list").count() == 0 or not page.locator(".pmk-maps-list").is_visible()
        _pin_prompt_says(page, "", "Type the PIN first")
        _pin_prompt_says(page, "abcd", "a PIN has 4 to 12 digits")
        _pin_prompt_says(page, "1234", "Wrong PIN.", enter=True)
        _shot(page, "mode-3-pin-refused")
        page.locator(".pmk-kiosk-pin input").fill("4711")
        page.locator("button.pmk-kiosk-unlock").click()
        expect(page.locator(".pmk-maps-list")).to_be_visible(timeout=30_000)
        _shot(page, "mode-4-maps-unlocked")

        # -- Home -> Settings asks again; too many wrong PINs lock out, even the right one
        page.locator("button.pmk-nav-home").click()
        page.locator("button.pmk-nav-settings").click()
        expect(page.locator(".pmk-kiosk-pin-box")).to_contain_text("Enter the PIN to open Settings")
        for _ in range(MAX_TRIES - 1):
            _pin_prompt_says(page, "0000", "Wrong PIN.")
        _pin_prompt_says(page, "0000", f"try again in {LOCKOUT_S:.0f} s")
        _pin_prompt_says(page, "4711", "Too many wrong PINs")
        assert page.locator(".pmk-settings-name").count() == 0 or not page.locator(".pmk-settings-name").is_visible()
        _shot(page, "mode-5-lockout")


# --- served with a token: the page opens only with it ---------------------------------------------


def test_the_dashboard_refuses_the_network_without_a_token_and_needs_the_printed_url(tmp_path: Path) -> None:
    """`pmk dashboard --ip 0.0.0.0` without a token never starts; with ``--token auto`` (on loopback:
    the tests stay on 127.0.0.1) the page opens only from the printed URL, which carries the token."""
    import os
    import sys

    from playwright.sync_api import expect

    env = {**os.environ, "PMK_MAPS_DIR": str(tmp_path / "maps"), "PMK_CONFIG_DIR": str(tmp_path / "config")}
    port = free_port()
    refused = subprocess.run(
        [sys.executable, "-m", "pmk_nb.cli", "dashboard", "--ip", "0.0.0.0", "--port", str(port), "--no-browser"],
        env=env,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert refused.returncode == 2 and "--token" in refused.stderr and len(refused.stderr.strip().splitlines()) == 1
    served = subprocess.Popen(
        [sys.executable, "-m", "pmk_nb.cli", "dashboard", "--token", "auto", "--port", str(port), "--no-browser"],
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.DEVNULL,
        text=True,
    )
    try:
        assert served.stdout is not None
        line = served.stdout.readline()
        assert line.startswith("PMK dashboard: http://127.0.0.1:") and "?token=" in line, line
        printed = line.split()[2]
        bare = printed.split("?", 1)[0]
        with chromium_page(bare, viewport=VIEWPORT) as page:
            time.sleep(3.0)
            assert page.locator("button.pmk-nav-home").count() == 0, "the page opened without the token"
            assert "build_app" not in page.content()
            page.goto(printed, wait_until="domcontentloaded")
            expect(page.locator("button.pmk-nav-home")).to_be_visible(timeout=120_000)
            _shot(page, "token-opened")
    finally:
        stop_process(served)
