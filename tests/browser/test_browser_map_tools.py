"""Map tools in a real browser (issue 29): the scale bar is drawn on the live canvas at the length it
names, and Measure with two taps shows the distance between them.

The dashboard is the demo kiosk (Voilà, the simulated chair, preview started by itself). Where to tap
comes from the same pure view maths the page uses, built from what the kernel publishes
(tests/page_view.py: the canvas fitted to the page, zoom, insets): at zoom level 1 the whole map is
shown, so following the chair does not move it.
"""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from pmk_nb.rosmap import read_map
from pmk_nb.viewport import Viewport, scale_bar
from tests.browser.kiosk_page import ARTIFACTS, VIEWPORT, chromium_page, serve_kiosk
from tests.browser.test_browser_live import pixels, wait_until
from tests.page_view import page_view

pytestmark = [pytest.mark.slow, pytest.mark.browser, pytest.mark.timeout(300)]


def _tap(page: Any, canvas: Any, view: Viewport, point: tuple[float, float]) -> tuple[float, float]:
    """Click the canvas where the world ``point`` is; returns the canvas pixel actually clicked."""
    box = canvas.bounding_box()
    assert box is not None
    css = box["width"] / view.canvas_width  # the page may scale the canvas down
    px, py = (float(v) for v in view.world_to_pixel(*point))
    x, y = box["x"] + px * css, box["y"] + py * css
    page.mouse.click(x, y)
    return (x - box["x"]) / css, (y - box["y"]) / css


def _visible_middle(view: Viewport, grid: Any, box: dict[str, float], window_h: float) -> tuple[float, float]:
    """The map point in the middle of the part of the map shown in the window (above the status
    line), checked to leave room for taps 2 m above and below it."""
    top = max(-box["y"] * view.canvas_width / box["width"], 0.0)
    bottom = min((window_h - box["y"]) * view.canvas_width / box["width"], view.canvas_height - view.insets.bottom)
    x0, y0 = grid.origin[0], grid.origin[1]
    _px, (map_top, map_bottom) = view.world_to_pixel([x0, x0], [y0 + grid.height * grid.resolution, y0])
    lo, hi = max(top, float(map_top)), min(bottom, float(map_bottom))
    assert hi - lo > 4.5 * view.px_per_m, f"too little map in the window for a 4 m tap: rows {lo:.0f}..{hi:.0f}"
    _x, y = view.pixel_to_world(0.0, (lo + hi) / 2)
    return x0 + grid.width * grid.resolution / 2, float(y)


def _bar_drawn(rgba: np.ndarray, bar_px: float) -> bool:
    """The scale bar's dark line at the lower left: row height - 14 from x = 12, ``bar_px`` long."""
    row = rgba.shape[0] - 14
    band = rgba[row - 1 : row + 2, 12 : 12 + int(bar_px) - 1, :3].astype(int)
    dark = (band.max(axis=2) < 60).any(axis=0)  # per column: the 3 px line in one of three rows
    return bool(dark.mean() > 0.9)


def test_scale_bar_is_drawn_at_the_length_it_names(tmp_path: Path) -> None:
    from playwright.sync_api import expect

    with serve_kiosk(tmp_path, label="map-tools") as (url, world), chromium_page(url, viewport=VIEWPORT) as page:
        expect(page.locator(".pmk-home-info-state")).to_contain_text("Live", timeout=120_000)
        grid = read_map(world.map_yaml)
        view = page_view(page, grid)  # the canvas the kernel fitted to the page, its zoom and insets
        bar = scale_bar(view.px_per_m, min(120.0, 0.4 * view.canvas_width))
        expect(page.locator(".pmk-tools-scale")).to_contain_text(bar.label, timeout=10_000)
        assert wait_until(page, lambda: _bar_drawn(pixels(page), bar.pixels), 10.0), f"no {bar.label} bar drawn"

        ARTIFACTS.mkdir(exist_ok=True)
        page.screenshot(path=str(ARTIFACTS / "map-tools.png"))


def test_measure_two_taps_in_the_browser(tmp_path: Path) -> None:
    from playwright.sync_api import expect

    with serve_kiosk(tmp_path, label="map-measure") as (url, world), chromium_page(url, viewport=VIEWPORT) as page:
        expect(page.locator(".pmk-home-info-state")).to_contain_text("Live", timeout=120_000)
        grid = read_map(world.map_yaml)
        view = page_view(page, grid)
        # Measure: two taps 5 m apart (3 m across, 4 m up) around the map's middle. Follow off first:
        # the demo chair patrols, and a view that follows it between the taps would move under them
        follow = page.locator(".pmk-live-follow")
        follow.click()
        expect(follow).not_to_have_class(re.compile(r"mod-active"))
        page.locator(".pmk-tools-mode button", has_text="Measure").click()
        expect(page.locator(".pmk-tools-readout")).to_contain_text("Tap two points")
        # the researcher has scrolled down to the tools: the map's top is above the window (a press
        # then focused the canvas, which scrolled it into view between ipycanvas's two reads: the
        # press's pixel was off by the scroll, 10.33 m for 5 m; pmk_nb/ui/live/canvas_focus.py)
        page.locator(".pmk-tools-readout").scroll_into_view_if_needed()
        canvas = page.locator(".pmk-live-canvas").first
        box = canvas.bounding_box()
        assert box is not None and box["y"] < -100, f"the map's top should be scrolled away: {box}"
        cx, cy = _visible_middle(view, grid, box, VIEWPORT["height"])
        a = _tap(page, canvas, view, (cx - 1.5, cy - 2.0))
        expect(page.locator(".pmk-tools-readout")).to_contain_text("second point", timeout=10_000)
        assert canvas.bounding_box() == box, "a press on the map scrolled the page"
        b = _tap(page, canvas, view, (cx + 1.5, cy + 2.0))
        distance = page.locator(".pmk-tools-distance")
        expect(distance).to_contain_text(" m", timeout=10_000)
        shown = float(re.sub(r"[^0-9.]", "", distance.inner_text()))
        clicked = math.dist(a, b) / view.px_per_m  # the pixels Chromium really clicked, in metres
        assert abs(shown - clicked) < 0.011 and abs(shown - 5.0) < 2.5 / view.px_per_m + 0.01, (shown, clicked)
        expect(page.locator(".pmk-tools-pointer")).to_contain_text("x ")  # the pointer's map coordinates
        ARTIFACTS.mkdir(exist_ok=True)
        page.screenshot(path=str(ARTIFACTS / "map-measure.png"))
