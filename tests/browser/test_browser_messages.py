"""Messages in a real browser: one place each, cleared by the next action, in the user's words.

Against the demo world (simulated chair, Voilà, Chromium): a failed connection test then a good
one leaves "Connected" alone on the page; Test connection never says "Not saved"; a long address
wraps in the panel instead of being clipped; "too large" goes when the next attempt says "too
coarse"; an imported non-XML file is named by its own name without URL advice; finished progress
bars leave; during a stall the panel shows no speed; and every button has an accessible name, the
preview's stop button being neither red nor called Disconnect.
"""

from __future__ import annotations

import os
import signal
import socket
import time
from pathlib import Path
from typing import Any

import pytest

from tests.browser.kiosk_page import ARTIFACTS, VIEWPORT, chromium_page, serve_kiosk

pytestmark = [pytest.mark.slow, pytest.mark.browser, pytest.mark.timeout(600)]


def _closed_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def _page_text(page: Any) -> str:
    return str(page.locator(".pmk-app").inner_text())


def _shot(page: Any, name: str) -> None:
    ARTIFACTS.mkdir(exist_ok=True)
    page.screenshot(path=str(ARTIFACTS / f"messages-{name}.png"))


def _settings_messages(page: Any, ros_port: int) -> None:
    from playwright.sync_api import expect

    page.locator("button.pmk-nav-settings").click()
    port = page.locator(".pmk-settings-port input")
    host = page.locator(".pmk-settings-host input")
    # Test connection with a bad field: the field says why, and nothing says "Not saved"
    port.fill("ninety")
    page.locator("button.pmk-settings-test").click()
    expect(page.locator(".pmk-settings-message")).to_contain_text("Not tested")
    assert "Not saved" not in _page_text(page)
    # a failure: once, in the status (not again in the app's message line)
    port.fill(str(_closed_port()))
    host.fill("127.0.0.1")
    page.locator("button.pmk-settings-test").click()
    status = page.locator(".pmk-settings-status")
    expect(status).to_contain_text("Disconnected", timeout=30_000)
    reason = page.locator(".pmk-status-reason").inner_text().strip()
    assert reason and _page_text(page).count(reason) == 1, "the reason is shown more than once"
    assert page.locator(".pmk-message").inner_text().strip() == ""
    _shot(page, "1-connection-failed")
    # the next test succeeds: "Connected" and no trace of the older failure anywhere
    port.fill(str(ros_port))
    page.locator("button.pmk-settings-test").click()
    expect(status).to_contain_text("Connected", timeout=30_000)
    assert "failed" not in _page_text(page).lower() and reason not in _page_text(page)
    _shot(page, "2-connected")


def _long_address_wraps(page: Any) -> None:
    from playwright.sync_api import expect

    page.locator(".pmk-settings-host input").fill("chair-" + "very-long-ward-name-" * 6 + "example.invalid")
    page.locator("button.pmk-settings-test").click()
    expect(page.locator(".pmk-settings-status")).to_contain_text("Disconnected", timeout=30_000)
    clipped = page.evaluate(
        """() => [...document.querySelectorAll('.pmk-info *')]
              .filter((e) => e.scrollWidth > e.clientWidth + 1 && getComputedStyle(e).overflowX !== 'visible')
              .map((e) => e.className)"""
    )
    panel = page.locator(".pmk-info").bounding_box()
    reason = page.locator(".pmk-status-reason").bounding_box()
    assert not clipped, f"clipped in the panel: {clipped}"
    assert panel is not None and reason is not None and reason["x"] + reason["width"] <= panel["x"] + panel["width"] + 1
    _shot(page, "3-long-address")


def _maps_messages(page: Any) -> None:
    from playwright.sync_api import expect

    page.locator("button.pmk-nav-maps").click()
    page.locator(".pmk-maps-list select").select_option(index=0)
    resolution = page.locator(".pmk-maps-resolution input")
    resolution.fill("0.0001")
    resolution.press("Enter")
    page.locator("button.pmk-maps-convert").click()
    field = page.locator(".pmk-maps-resolution + .pmk-field-error, .pmk-field-error").filter(has_text="too large")
    expect(field.first).to_be_visible(timeout=60_000)
    text = _page_text(page)
    assert text.count("too large") == 1 and "--" not in text  # once, and no command-line options
    resolution.fill("5")
    resolution.press("Enter")
    page.locator("button.pmk-maps-convert").click()
    expect(page.locator(".pmk-field-error").filter(has_text="too coarse").first).to_be_visible()
    assert "too large" not in _page_text(page), "the older budget error is still shown"
    _shot(page, "4-too-coarse")
    resolution.fill("0.2")
    resolution.press("Enter")
    page.locator("button.pmk-maps-convert").click()
    expect(page.locator(".pmk-maps-status")).to_contain_text("Converted", timeout=90_000)
    time.sleep(0.5)
    assert page.locator(".widget-progress:visible").count() == 0, "a finished progress bar stays on screen"
    assert "too coarse" not in _page_text(page)


def _import_message(page: Any, tmp_path: Path) -> None:
    from playwright.sync_api import expect

    bad = tmp_path / "ward_plan.gml"
    bad.write_bytes(b"<IndoorFeatures>\n  <unclosed>\n")
    with page.expect_file_chooser() as chooser:
        page.locator(".pmk-maps-import").first.click()
    chooser.value.set_files(str(bad))
    said = page.locator(".pmk-maps-import-status")
    expect(said).to_contain_text("ward_plan.gml", timeout=30_000)
    text = said.inner_text()
    assert "/tmp" not in text and "pmk-upload" not in text and "URL" not in text, text
    _shot(page, "5-import-error")


def _stall_hides_speed(page: Any, sim_pid: int) -> None:
    from playwright.sync_api import expect

    page.locator("button.pmk-nav-home").click()
    expect(page.locator(".pmk-home-info-speed")).to_contain_text("m/s", timeout=30_000)
    os.kill(sim_pid, signal.SIGSTOP)  # the chair goes silent: no odometry
    try:
        expect(page.locator(".pmk-home-info-state")).to_contain_text("No data", timeout=30_000)
        time.sleep(0.6)  # one more refresh of the panel
        speed = page.locator(".pmk-home-info-speed").inner_text()
        assert "m/s" not in speed and "—" in speed, f"a stale speed is shown as current: {speed}"
        _shot(page, "6-stall")
    finally:
        os.kill(sim_pid, signal.SIGCONT)


def _accessible_names(page: Any) -> None:
    cdp = page.context.new_cdp_session(page)
    nodes = cdp.send("Accessibility.getFullAXTree")["nodes"]
    buttons = [
        n for n in nodes if not n.get("ignored") and n.get("role", {}).get("value") in ("button", "ToggleButton")
    ]
    nameless = [n.get("nodeId") for n in buttons if not str(n.get("name", {}).get("value", "")).strip()]
    assert buttons and not nameless, f"{len(nameless)} of {len(buttons)} buttons have no accessible name"
    names = {str(n.get("name", {}).get("value", "")) for n in buttons}
    assert {"Zoom in", "Zoom out"} <= names, names
    stop = page.locator("button.pmk-home-disconnect")
    assert stop.inner_text().strip() == "Stop preview"
    red, green, blue = (int(v) for v in stop.evaluate("e => getComputedStyle(e).backgroundColor")[4:-1].split(",")[:3])
    assert not (red > 150 and green < 100 and blue < 100), "the stop-preview button looks like an emergency stop"


def test_messages_in_one_place_in_chromium(tmp_path: Path) -> None:
    from playwright.sync_api import expect

    with serve_kiosk(tmp_path, label="messages") as (url, world):
        assert world.sim is not None
        with chromium_page(url, viewport=VIEWPORT, has_touch=True) as page:
            expect(page.locator("button.pmk-home-disconnect")).to_be_visible(timeout=120_000)
            _accessible_names(page)
            _stall_hides_speed(page, world.sim.pid)
            _settings_messages(page, world.ros_port)
            _long_address_wraps(page)
            _maps_messages(page)
            _import_message(page, tmp_path)
