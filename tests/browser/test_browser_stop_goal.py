"""Issue 38 in a real browser, as the attacker did it: page B's Stop must stop page A's goal.

Item 1: page A taps a destination far down the corridor (Nav2 NavigateToPose over the official bridge,
which holds a connection's ops behind its goal); page B (its own Voilà kernel) presses Stop. Before the
fix A's page said "Stopped from another page" while its goal drove the chair on (the simulator used
to cancel a goal on any /cmd_vel; now, like Nav2, it does not). Now the chair stops and stays
stopped, A's goal says cancelled, and A's Set destination is greyed and refused until B releases.
Item 4: B's profile spells the chair ``localhost`` where A's says ``127.0.0.1``: one chair, one key,
so B's Stop reaches A, and when A drives B sees "Driven from another page".
Screenshots: ``test-artifacts/drive-stop-goal-*.png``.
"""

from __future__ import annotations

import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from pmk_nb.sim import World, demo_grid
from tests.browser.kiosk_page import VIEWPORT, chromium_page
from tests.browser.test_browser_drive import press_forward, ready, shot
from tests.browser.test_browser_goal import _goal_near, _press
from tests.drive_world import ChairWatch, DriveWorld, drive_world
from tests.page_view import page_view

pytestmark = [pytest.mark.slow, pytest.mark.browser, pytest.mark.timeout(420)]


@pytest.fixture
def world(tmp_path: Path) -> Iterator[DriveWorld]:
    with drive_world(tmp_path) as served:
        yield served


def _use_profile(world: DriveWorld, host: str) -> None:
    """Make a profile for the same chair, spelled ``host``, the last used (the next page opens with it)."""
    from pmk_nb.chair import PROFILES_FILE, ChairProfile, ProfileStore

    store = ProfileStore(world.root / "config" / PROFILES_FILE, secrets=False)
    store.save(ChairProfile(name=f"Chair as {host}", host=host, port=world.ros_port))


def _still_for(watch: ChairWatch, seconds: float) -> bool:
    start = time.monotonic()
    time.sleep(seconds)
    return all(watch.still(v, w) for t, v, w in watch.odom if t > start)


def test_page_b_stop_stops_page_a_goal_across_two_spellings(world: DriveWorld) -> None:
    from playwright.sync_api import expect

    watch = ChairWatch(world.ros_port)
    try:
        with chromium_page(world.url, viewport=VIEWPORT) as page_a:
            expect(page_a.locator(".pmk-home-info-state")).to_contain_text("Live", timeout=120_000)
            _use_profile(world, "localhost")  # page B (opened next) spells the chair otherwise
            page_b: Any = page_a.context.browser.new_page(viewport=VIEWPORT)
            page_b.set_default_timeout(60_000)
            page_b.goto(world.url, wait_until="domcontentloaded")
            expect(page_b.locator(".pmk-home-info-state")).to_contain_text("Live", timeout=120_000)

            # -- A: a destination far along the corridor
            grid = demo_grid()
            view = page_view(page_a, grid)
            canvas = page_a.locator(".pmk-live-canvas").first
            toggle_a = page_a.locator(".pmk-goal-set")
            expect(toggle_a).to_be_enabled(timeout=30_000)
            toggle_a.click()
            goal = _goal_near(page_a, canvas, view, World(grid, 0.35), (1.0, 6.0), 6.0, 30.0)
            _press(page_a, canvas, view, goal)
            expect(page_a.locator(".pmk-goal-word")).to_have_text("moving", timeout=30_000)
            assert watch.first(time.monotonic(), watch.moving, 10.0) is not None, "A's goal never moved the chair"

            # -- B: Drive, then Stop
            ready(page_b)
            pressed = time.monotonic()
            page_b.locator("button.pmk-drive-stop").click()
            stopped = watch.first(pressed, watch.still, 5.0)
            assert stopped is not None and stopped < 3.0, f"the chair drove on {stopped} s after B's Stop"
            assert _still_for(watch, 2.0), "A's goal drove the chair again after B's Stop"
            expect(page_a.locator(".pmk-goal-word")).to_have_text("cancelled", timeout=10_000)
            expect(toggle_a).to_be_disabled(timeout=5_000)
            expect(page_a.locator(".pmk-goal-stopped")).to_contain_text("released on the page where it was pressed")
            expect(page_a.locator(".pmk-home-goto")).to_be_disabled()
            toggle_a.click(force=True)  # a page can click a greyed button: the kernel refuses
            _press(page_a, canvas, view, goal)
            assert _still_for(watch, 2.0), "a goal left page A under B's Stop"
            shot(page_a, "stop-goal-a")
            print(f"B's Stop -> A's goal stopped (odometry): {stopped:.2f} s")

            # -- B releases where it was pressed; A's destination comes back; A drives, B is refused
            release = page_b.locator("button.pmk-drive-claim")
            expect(release).to_contain_text("Release the Stop", timeout=10_000)
            release.click()
            expect(toggle_a).to_be_enabled(timeout=10_000)
            centre = ready(page_a)
            press_forward(page_a, watch, centre)
            expect(page_b.locator(".pmk-drive-status")).to_contain_text("Driven from another page", timeout=10_000)
            shot(page_b, "stop-goal-b")
            page_a.mouse.up()
    finally:
        watch.close()
