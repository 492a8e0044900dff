"""The Fleet panel with three chairs in a real browser (issue 26): Voilà, headless Chromium, three
simulated chairs in this process (their poses are read from the simulators themselves).

Home opens on chair A (the last used profile); Fleet -> Add all saved chairs lists A, B and C with
connection, map, pose and goal; the map shows three markers, one colour each (none of them before);
C's Control
moves control to C, and the joystick then drives C while A and B stay where they are.
Screenshots: ``test-artifacts/fleet-*.png``.
"""

from __future__ import annotations

import os
import subprocess
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from pmk_nb.chair import Fleet
from pmk_nb.serve.procs import free_port, stop_process, wait_for_port
from pmk_nb.serve.voila import voila_command, write_dashboard_notebook
from pmk_nb.ui import AUTOSTART_ENV
from tests.browser.kiosk_page import ARTIFACTS, VIEWPORT, chromium_page
from tests.browser.test_browser_kiosk import _pixels

pytestmark = [pytest.mark.slow, pytest.mark.browser, pytest.mark.timeout(300)]

STARTS = [(3.0, 6.0, 0.0), (8.0, 6.0, 0.0), (13.0, 6.0, 0.0)]  # along the demo floor's corridor
NAMES = ["chair A", "chair B", "chair C"]


@pytest.fixture
def lab(tmp_path: Path, sim_factory: Callable[..., Any]) -> Iterator[tuple[str, list[Any]]]:
    """Three simulated chairs (classroom rates), their profiles, the demo floor current, Voilà."""
    from pmk_nb.chair import PROFILES_FILE, ChairProfile, ProfileStore
    from pmk_nb.library import MapsFolder
    from pmk_nb.rosmap import write_map
    from pmk_nb.sim import demo_grid
    from pmk_nb.ui import AppContext

    maps_dir, config_dir = tmp_path / "maps", tmp_path / "config"
    files = write_map(demo_grid(), maps_dir, "demo_floor")
    sims = [
        sim_factory(grid=demo_grid(), start_pose=p, odom_rate=20.0, scan_rate=5.0, rays=180, patrol=False)
        for p in STARTS
    ]
    store = ProfileStore(config_dir / PROFILES_FILE, secrets=False)
    for name, sim in zip(NAMES, sims, strict=True):
        store.save(ChairProfile(name=name, host="127.0.0.1", port=sim.port))
    store.mark_used("chair A")
    ctx = AppContext(MapsFolder(maps_dir), store, config_dir=config_dir)
    ctx.set_current_map("demo_floor", files.yaml, files.preview)
    ctx.close()
    env = {**os.environ, "PMK_MAPS_DIR": str(maps_dir), "PMK_CONFIG_DIR": str(config_dir), AUTOSTART_ENV: "1"}
    env["PYTHONPATH"] = os.pathsep.join([str(Path(__file__).resolve().parents[2]), env.get("PYTHONPATH", "")])
    port = free_port()
    notebook = write_dashboard_notebook(tmp_path / "kiosk")
    log = (tmp_path / "voila.log").open("wb")
    voila = subprocess.Popen(voila_command(notebook, port=port), env=env, cwd=notebook.parent, stdout=log, stderr=log)
    try:
        wait_for_port("127.0.0.1", port, voila, "Voilà", 120.0)
        yield f"http://127.0.0.1:{port}/", sims
    finally:
        stop_process(voila)
        log.close()
        ARTIFACTS.mkdir(exist_ok=True)
        (ARTIFACTS / "fleet-voila.log").write_bytes((tmp_path / "voila.log").read_bytes())


def _colour_pixels(png: bytes, colour: str, tolerance: int = 30) -> int:
    """How many pixels of the screenshot are near ``colour`` (CSS hex)."""
    rgb = np.array([int(colour[i : i + 2], 16) for i in (1, 3, 5)], dtype=np.int16)
    return int(np.sum(np.all(np.abs(_pixels(png) - rgb) <= tolerance, axis=2)))


def test_the_fleet_panel_with_three_chairs(lab: tuple[str, list[Any]]) -> None:
    from playwright.sync_api import expect

    url, sims = lab
    colours = {m.name: m.colour for m in (Fleet().add(s) for s in _profiles(sims))}  # the colours are per name
    t0 = time.monotonic()
    with chromium_page(url, viewport=VIEWPORT) as page:
        expect(page.locator(".pmk-home-info-state")).to_contain_text("Live", timeout=120_000)
        print(f"\nlive after {time.monotonic() - t0:.1f} s")
        canvas = page.locator(".pmk-home-preview-box .pmk-live-canvas")
        page.wait_for_timeout(1000)
        png = canvas.screenshot()
        alone = {name: _colour_pixels(png, colours[name]) for name in NAMES}  # before the fleet: none
        assert all(n < 40 for n in alone.values()), f"the fleet's colours on a page without a fleet: {alone}"
        page.locator(".pmk-fleet-toggle").click()
        page.locator("button.pmk-fleet-add-all").click()
        rows = page.locator(".pmk-fleet-row")
        expect(rows).to_have_count(3, timeout=30_000)
        for i, name in enumerate(NAMES):
            row = rows.nth(i)
            expect(row.locator(".pmk-fleet-name")).to_have_text(name)
            expect(row.locator(".pmk-fleet-connection")).to_have_attribute("data-state", "live", timeout=30_000)
            expect(row.locator(".pmk-fleet-map")).to_contain_text("22.0 × 14.0 m map", timeout=30_000)
            expect(row.locator(".pmk-fleet-pose")).to_contain_text(f"x {STARTS[i][0]:.2f} m, y 6.00 m", timeout=30_000)
            expect(row.locator(".pmk-fleet-goal")).to_have_text("no goal")
        expect(rows.nth(0)).to_contain_text("(in control)")
        print(f"rows after {time.monotonic() - t0:.1f} s")
        page.screenshot(path=str(ARTIFACTS / "fleet-1-rows.png"))
        page.locator(".pmk-fleet-toggle").click()  # the card closed: the whole map in sight
        counts: dict[str, int] = {}
        deadline = time.monotonic() + 20
        while time.monotonic() < deadline:
            png = canvas.screenshot()
            counts = {name: _colour_pixels(png, colours[name]) for name in NAMES}
            if all(n >= 40 for n in counts.values()):
                break
            page.wait_for_timeout(500)
        assert all(n >= 40 for n in counts.values()), f"markers' pixels per chair: {counts}"
        page.screenshot(path=str(ARTIFACTS / "fleet-2-markers.png"))
        print(f"markers after {time.monotonic() - t0:.1f} s")
        # control to C, then drive: only C moves
        page.locator(".pmk-fleet-toggle").click()
        rows.nth(2).locator("button.pmk-fleet-control").click()
        expect(rows.nth(2)).to_contain_text("(in control)", timeout=20_000)
        expect(page.locator(".pmk-fleet-note")).to_contain_text("chair C is in control")
        expect(rows.nth(0).locator("button.pmk-fleet-control")).to_be_enabled()
        page.locator(".pmk-fleet-toggle").click()
        print(f"control after {time.monotonic() - t0:.1f} s")
        before = [s.pose for s in sims]
        _drive_forward(page, sims[2], before[2])
        page.screenshot(path=str(ARTIFACTS / "fleet-3-driving-c.png"))
        for sim, was in zip(sims[:2], before[:2], strict=True):
            assert np.hypot(sim.pose[0] - was[0], sim.pose[1] - was[1]) < 0.01, f"{sim.pose} moved from {was}"
    print(f"\nfleet markers' pixels: {counts}; C drove from {before[2][0]:.2f} to {sims[2].pose[0]:.2f} m")


def _profiles(sims: list[Any]) -> list[Any]:
    from pmk_nb.chair import ChairProfile

    return [ChairProfile(name=n, host="127.0.0.1", port=s.port) for n, s in zip(NAMES, sims, strict=True)]


def _drive_forward(page: Any, sim: Any, was: tuple[float, float, float]) -> None:
    """Drive on, hold the stick up until ``sim`` has moved 10 cm (a few tries: a loaded kernel may
    fall behind the deadman, which then stops the chair, as it must)."""
    from playwright.sync_api import expect

    page.locator(".pmk-drive-toggle").click()
    pad = page.locator(".pmk-drive-pad")
    expect(pad).to_be_visible(timeout=30_000)
    page.wait_for_function("() => document.querySelector('.pmk-drive-pad[data-pmk-bound]') !== null")
    box = pad.bounding_box()
    assert box is not None
    cx, cy, r = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2, box["width"] / 2
    for _ in range(4):
        page.mouse.move(cx, cy)
        page.mouse.down()
        page.mouse.move(cx, cy - 1.3 * r, steps=3)
        end = time.monotonic() + 4.0
        while time.monotonic() < end and sim.pose[0] - was[0] < 0.1:
            page.wait_for_timeout(100)
        page.mouse.up()
        if sim.pose[0] - was[0] >= 0.1:
            return
        page.wait_for_timeout(500)
    pytest.fail(
        f"chair C did not drive: {sim.pose} from {was}; the page says {page.locator('.pmk-drive-status').inner_text()}"
    )
