"""Tap-to-go in a real browser: Set destination, a tap and a drag on the live map send a goal that
the simulated chair reaches with the dragged heading; Cancel stops the chair (status cancelled).

The dashboard is the demo kiosk (the converted clinic sample, the patrolling simulated chair,
preview started by itself). The test reads the chair's true pose with its own chair link, picks
a reachable goal a few metres away with the simulator's planner, and works out where to press with
the same pure view maths the page uses (at zoom level 1 the whole map is shown, so following does
not move it; the canvas size and the insets the view keeps clear come from the page: tests/page_view.py).
"""

from __future__ import annotations

import math
import time
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from pmk_nb.chair.link import ChairLink
from pmk_nb.rosmap import read_map
from pmk_nb.sim import World
from pmk_nb.viewport import Viewport
from tests.browser.kiosk_page import ARTIFACTS, VIEWPORT, chromium_page, serve_kiosk
from tests.browser.test_browser_live import pixels, wait_until
from tests.page_view import page_view

pytestmark = [pytest.mark.slow, pytest.mark.browser, pytest.mark.timeout(300)]

GOAL_RGB = (200, 0, 160)  # pmk_nb.ui.goals.picker.GOAL_RGB


def _page_xy(canvas: Any, view: Viewport, point: tuple[float, float]) -> tuple[float, float, float]:
    """Page (CSS) position of a world point on the canvas, and CSS pixels per canvas pixel."""
    box = canvas.bounding_box()
    assert box is not None
    css = box["width"] / view.canvas_width  # the page may scale the canvas down
    px, py = (float(v) for v in view.world_to_pixel(point[0], point[1]))
    return box["x"] + px * css, box["y"] + py * css, css


def _goal_near(
    page: Any, canvas: Any, view: Viewport, world: World, start: tuple[float, float], lo: float, hi: float
) -> tuple[float, float]:
    """A reachable free point ``lo``..``hi`` m from ``start`` where the map is not covered (the joystick
    panel floats over part of it)."""
    rng = np.random.default_rng(7)
    for point in world.reachable_points(start, rng, k=300):
        if not lo <= math.dist(point, start) <= hi or len(world.plan(start, point)) < 2:
            continue
        x, y, _ = _page_xy(canvas, view, point)
        top = page.evaluate(f"(() => {{ const e = document.elementFromPoint({x}, {y}); return e && e.tagName; }})()")
        if top == "CANVAS":
            return point
    raise AssertionError(f"no reachable, uncovered goal {lo}-{hi} m from {start}")


def _press(page: Any, canvas: Any, view: Viewport, goal: tuple[float, float], drag_px: float = 0.0) -> None:
    """Press at ``goal`` (world), drag ``drag_px`` canvas pixels to the right (heading +x), release."""
    x, y, css = _page_xy(canvas, view, goal)
    page.mouse.move(x, y)
    page.mouse.down()
    if drag_px:
        page.mouse.move(x + drag_px * css, y, steps=6)
    page.mouse.up()


def _goal_drawn(page: Any, view: Viewport, goal: tuple[float, float]) -> bool:
    rgba = pixels(page)
    px, py = (round(float(v)) for v in view.world_to_pixel(goal[0], goal[1]))
    patch = rgba[max(py - 40, 0) : py + 40, max(px - 40, 0) : px + 40, :3].astype(int)
    return bool((np.abs(patch - GOAL_RGB).sum(axis=2) < 60).sum() > 20)


@pytest.mark.parametrize("ros", ["ros1", "ros2"])  # move_base over actionlib; Nav2 NavigateToPose
def test_tap_to_go_reaches_the_goal_and_cancel_stops_the_chair(tmp_path: Path, ros: str) -> None:
    from playwright.sync_api import expect

    # rs: a cancel acts at once; the official bridge's held cancel is tests/ui/goals/test_goals.py's (issue 24)
    served = serve_kiosk(tmp_path, sim_args=("--ros", ros, "--bridge", "rs"), label=f"goal-{ros}")
    with served as (url, world), chromium_page(url, viewport=VIEWPORT) as page:
        grid = read_map(world.map_yaml)
        planner = World(grid, 0.35)
        link = ChairLink("127.0.0.1", world.ros_port)
        link.connect(timeout=30.0)
        link.start_streams()
        try:
            expect(page.locator(".pmk-home-info-state")).to_contain_text("Live", timeout=120_000)
            canvas = page.locator(".pmk-live-canvas").first
            # the canvas takes the page's room and the view keeps clear of the panels over it (issue 28)
            view = page_view(page, grid)
            toggle = page.locator(".pmk-goal-set")
            status = page.locator(".pmk-goal-status")
            expect(toggle).to_be_enabled(timeout=30_000)

            # -- tap + drag to the right: the chair drives there and faces +x
            assert wait_until(page, lambda: link.latest_pose() is not None)
            pose = link.latest_pose()
            toggle.click()  # first: its heading card floats over part of the map
            goal = _goal_near(page, canvas, view, planner, (pose.x, pose.y), 3.0, 7.0)
            _press(page, canvas, view, goal, drag_px=40.0)
            expect(status).to_contain_text("Destination", timeout=10_000)
            expect(page.locator(".pmk-goal-word")).to_have_text("moving", timeout=20_000)
            assert wait_until(page, lambda: _goal_drawn(page, view, goal), 10.0), "no goal arrow at the goal"
            ARTIFACTS.mkdir(exist_ok=True)
            page.screenshot(path=str(ARTIFACTS / f"goal-{ros}-moving.png"))
            route = "Nav2 NavigateToPose" if ros == "ros2" else "move_base actionlib"
            expect(status).to_contain_text(route)
            expect(page.locator(".pmk-goal-word")).to_have_text("arrived", timeout=90_000)
            page.screenshot(path=str(ARTIFACTS / f"goal-{ros}-arrived.png"))
            end = link.latest_pose()
            assert end is not None
            tol = 2 * grid.resolution / view.scale + 0.2  # a press lands on a screen pixel
            assert math.dist((end.x, end.y), goal) < tol, f"chair at ({end.x:.2f}, {end.y:.2f}), goal {goal}"
            assert abs(math.remainder(end.theta, 2 * math.pi)) < 0.3, f"heading {end.theta:.2f}: dragged to +x"
            expect(page.locator(".pmk-goal-cancel")).to_be_hidden()

            # -- a farther goal, then Cancel: the chair stops and the status says cancelled
            toggle.click()
            far = _goal_near(page, canvas, view, planner, (end.x, end.y), 6.0, 30.0)
            _press(page, canvas, view, far)
            expect(page.locator(".pmk-goal-word")).to_have_text("moving", timeout=20_000)
            assert wait_until(page, lambda: (o := link.latest_odom()) is not None and abs(o.v) > 0.1, 10.0)
            clicked = time.monotonic()
            page.locator(".pmk-goal-cancel").click()
            for _ in range(100):  # the chair's own odometry says when it stopped
                odom = link.latest_odom()
                if odom is not None and abs(odom.v) < 0.01 and odom.received > clicked:
                    break
                time.sleep(0.02)
            stopped_after = time.monotonic() - clicked
            assert stopped_after < 2.5, f"the chair still moved {stopped_after:.2f} s after Cancel"
            expect(page.locator(".pmk-goal-word")).to_have_text("cancelled", timeout=5_000)
            here = link.latest_pose()
            page.wait_for_timeout(1500)
            later = link.latest_pose()
            assert here is not None and later is not None
            assert math.dist((here.x, here.y), (later.x, later.y)) < 0.05, "the chair moved on after Cancel"
            assert math.dist((later.x, later.y), far) > 1.0
            page.screenshot(path=str(ARTIFACTS / f"goal-{ros}-cancelled.png"))
            print(f"Cancel click -> chair stopped (odometry): {stopped_after:.2f} s")
        finally:
            link.close()
