"""Home's live map in a real browser: every thin wall drawn, the map shown without a chair, pan,
Follow and Centre.

The current map is a long building (120 x 40 m at 0.05 m per cell) with 0.1 m walls (two cells)
about every 6 m.  Home's canvas is about 920 px wide, so at zoom level 1 one screen pixel covers more
than two cells: sampling one cell per pixel (the earlier look) loses walls, the screen-resolution
map keeps every one.  The test reads the map layer's pixels back from the page.  The chair is the
demo's simulated chair, driving around near the middle of the map; the page is not set to start
the preview by itself, so the map is first checked with no chair connected.
"""

from __future__ import annotations

import base64
import contextlib
import io
import math
import re
import shutil
import subprocess
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from pmk_nb.cli.demo_setup import prepare_demo
from pmk_nb.grid import OccupancyGrid
from pmk_nb.serve.procs import free_port, stop_process, wait_for_port
from pmk_nb.serve.voila import voila_command, write_dashboard_notebook
from pmk_nb.ui import AUTOSTART_ENV
from pmk_nb.viewport import Viewport
from tests.browser.kiosk_page import ARTIFACTS, VIEWPORT, chromium_page
from tests.page_view import settled_state

pytestmark = [pytest.mark.slow, pytest.mark.browser, pytest.mark.timeout(300)]

RES = 0.05
ORIGIN = (-60.0, -20.0)  # the demo chair drives near (0..20, 0..10) m: the middle of this map
#: left edges of the vertical 0.1 m walls, metres: 6.05 m apart, so they meet the pixel grid at
#: every phase (a regular 6 m spacing could happen to fall on the cells a sampling picks)
WALL_XS = np.round(np.arange(20) * 6.05 - 57.0, 2)
CHAIR_RGB = (31, 111, 235)
ACTIVE = re.compile("mod-active")  # a ToggleButton that is on


def thin_wall_grid() -> OccupancyGrid:
    data = np.zeros((800, 2400), np.int8)  # rows from the bottom
    data[[0, 1, -2, -1], :] = 100
    data[:, [0, 1, -2, -1]] = 100
    for x in WALL_XS:
        c = round((x - ORIGIN[0]) / RES)
        data[40:-40, c : c + 2] = 100  # 0.1 m thick, a 2 m gap at each end for the corridor
    return OccupancyGrid(data, RES, (*ORIGIN, 0.0))


@contextlib.contextmanager
def serve_thin_walls(tmp_path: Path) -> Iterator[str]:
    """The demo chair, the thin-wall map as the current map, Voilà serving the dashboard (no autostart)."""
    from pmk_nb.chair import PROFILES_FILE, ProfileStore
    from pmk_nb.chair.link import ChairLink
    from pmk_nb.library import MapsFolder
    from pmk_nb.rosmap import write_map
    from pmk_nb.ui import AppContext

    world = prepare_demo(tmp_path / "demo")
    log = (tmp_path / "voila.log").open("wb")
    voila = None
    try:
        files = write_map(thin_wall_grid(), world.maps_dir, "thin_walls")
        ctx = AppContext(
            MapsFolder(world.maps_dir),
            ProfileStore(world.config_dir / PROFILES_FILE, secrets=False),
            config_dir=world.config_dir,
        )
        ctx.set_current_map("thin_walls", files.yaml, files.preview)
        ctx.close()
        # sent to the chair too: Home shows the chair's own /map once live (issue 29), so the chair
        # must publish the map this test draws
        write_map(thin_wall_grid(), world.chair_dir, "thin_walls", preview=False)
        link = ChairLink("127.0.0.1", world.ros_port)
        try:
            link.connect(timeout=30.0)
            link.reload_map("/home/pmk/ALMA_MAPS/thin_walls.yaml", timeout=60.0)
        finally:
            link.close()
        env = {k: v for k, v in world.env.items() if k != AUTOSTART_ENV}
        port = free_port()
        notebook = write_dashboard_notebook(tmp_path / "kiosk")
        voila = subprocess.Popen(
            voila_command(notebook, port=port), env=env, cwd=notebook.parent, stdout=log, stderr=subprocess.STDOUT
        )
        wait_for_port("127.0.0.1", port, voila, "Voilà", 120.0)
        yield f"http://127.0.0.1:{port}/"
    finally:
        stop_process(voila)
        world.stop()
        log.close()
        ARTIFACTS.mkdir(exist_ok=True)
        shutil.copy(tmp_path / "voila.log", ARTIFACTS / "live-voila.log")


#: the live canvas with the page's chair layer over it (issue 41: the page draws the chair)
PIXELS_JS = """(() => {
  const c = document.querySelector('canvas.pmk-live-canvas'), o = document.querySelector('canvas.pmk-live-page');
  const out = document.createElement('canvas');
  out.width = c.width; out.height = c.height;
  const g = out.getContext('2d');
  g.drawImage(c, 0, 0);
  if (o && o.width === c.width && o.height === c.height) g.drawImage(o, 0, 0);
  return out.toDataURL('image/png');
})()"""


def pixels(page: Any) -> np.ndarray:
    """RGBA pixels of the live canvas as the page shows them (the layers composited: map, laser, then
    the page's chair)."""
    from PIL import Image

    url = page.evaluate(PIXELS_JS)
    return np.asarray(Image.open(io.BytesIO(base64.b64decode(url.split(",", 1)[1]))).convert("RGBA"))


def wall_columns(rgba: np.ndarray) -> np.ndarray:
    """Canvas columns that are dark over most of the map's height: the vertical walls drawn."""
    dark = (rgba[..., 3] > 0) & np.all(rgba[..., :3] < 80, axis=2)
    # over the rows the map is drawn in: the canvas takes the page's room (issue 28), so a wide map
    # leaves bands above and below it
    rows = dark.any(axis=1)
    return np.flatnonzero(dark[rows].mean(axis=0) > 0.6) if rows.any() else np.zeros(0, dtype=np.int64)


def chair_centre(rgba: np.ndarray) -> tuple[float, float] | None:
    blue = np.all(np.abs(rgba[..., :3].astype(int) - CHAIR_RGB) < 30, axis=2) & (rgba[..., 3] > 200)
    ys, xs = np.nonzero(blue)
    return (float(xs.mean()), float(ys.mean())) if xs.size > 10 else None


def expected_wall_px(width: int, height: int) -> np.ndarray:
    view = Viewport(2400, 800, RES, ORIGIN, width, height)
    px, _ = view.world_to_pixel(WALL_XS, 0.0)
    return np.asarray(px)


def old_look_walls(width: int, height: int) -> np.ndarray:
    """The walls the earlier one-cell-per-pixel sampling kept at this canvas size."""
    grid = thin_wall_grid()
    gray = np.where(grid.data[::-1] == 100, 0, 254).astype(np.uint8)
    img, inside = Viewport.for_grid(grid, width, height).image_window(gray)
    rows = inside.any(axis=1)  # the map's rows (bands above and below a wide map: issue 28)
    return np.flatnonzero((img[rows] == 0).mean(axis=0) > 0.6)


def wait_until(page: Any, cond: Any, seconds: float = 20.0) -> Any:
    for _ in range(int(seconds * 4)):
        got = cond()
        if got:
            return got
        page.wait_for_timeout(250)
    return cond()


def test_home_map_keeps_thin_walls_without_a_chair_and_pans_follows_centres(tmp_path: Path) -> None:
    from playwright.sync_api import expect

    with serve_thin_walls(tmp_path) as url, chromium_page(url, viewport=VIEWPORT) as page:
        expect(page.locator(".pmk-home-map")).to_contain_text("thin_walls", timeout=120_000)
        # -- no chair connected (no preview yet): the map is there, every wall a line
        expect(page.locator("button.pmk-home-preview")).to_be_visible(timeout=30_000)
        canvas = page.locator(".pmk-live-canvas").first
        expect(canvas).to_be_visible()
        settled_state(page)  # the canvas has taken the page's room (issue 28: the map is the screen)
        rgba = pixels(page)
        for _ in range(80):  # the map arrives with the first frames
            if wall_columns(rgba).size:
                break
            page.wait_for_timeout(250)
            rgba = pixels(page)
        h, w = rgba.shape[:2]
        assert w > 600, f"Home's canvas is {w} px wide"
        expected = expected_wall_px(w, h)
        drawn = wall_columns(rgba)
        missing = [float(x) for x in expected if not np.any(np.abs(drawn - x) <= 1.5)]
        assert not missing, f"walls at canvas x {missing} are not drawn (drawn columns {drawn.tolist()})"
        old = old_look_walls(w, h)
        lost_before = [float(x) for x in expected if not np.any(np.abs(old - x) <= 1.5)]
        assert lost_before, "this zoom should be one where sampling one cell per pixel loses walls"
        ARTIFACTS.mkdir(exist_ok=True)
        page.screenshot(path=str(ARTIFACTS / "live-thin-walls-no-chair.png"))
        # no preview running: no update is promised, so the page does not call it a slow link
        page.wait_for_timeout(1000)
        expect(page.locator(".pmk-live-link")).to_have_text("")
        # -- the zoom buttons and the view's own buttons have accessible names
        # (Chromium's own accessibility tree: an icon glyph must not be, or be part of, the name)
        tree = page.context.new_cdp_session(page).send("Accessibility.getFullAXTree")
        names = {n.get("name", {}).get("value") for n in tree["nodes"] if n.get("role", {}).get("value") == "button"}
        assert {"Zoom in", "Zoom out", "Follow", "Centre"} <= names, f"button names: {sorted(map(str, names))}"

        # -- zoomed in, a mouse drag pans the map (and turns Follow off)
        for _ in range(4):
            page.locator("button.pmk-home-zoom-in").click()
        expect(page.locator(".pmk-home-info-zoom")).to_contain_text("Zoom: 5")
        # no chair seen yet: the view is on the map's middle, where the pure view maths puts the walls
        view = Viewport(2400, 800, RES, ORIGIN, w, h)
        view.set_zoom(5)
        want = [float(x) for x in view.world_to_pixel(WALL_XS, 0.0)[0] if 2 < x < w - 2]

        def walls_at(xs: list[float]) -> bool:
            cols = wall_columns(pixels(page))
            return cols.size > 0 and all(np.any(np.abs(cols - x) <= 2.0) for x in xs)

        assert want and wait_until(page, lambda: walls_at(want)), f"zoom 5: walls not at {want}"
        box = canvas.bounding_box()
        assert box is not None
        sx = w / box["width"]  # canvas pixels per CSS pixel (the page may scale the canvas down)
        cx, cy = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
        page.mouse.move(cx, cy)
        page.mouse.down()
        for step in range(1, 6):
            page.mouse.move(cx + 16 * step, cy + 4 * step)
            page.wait_for_timeout(50)
        page.mouse.up()
        moved = [x + 80 * sx for x in want if x + 80 * sx < w - 2]
        assert wait_until(page, lambda: walls_at(moved)), f"the map did not follow the drag: walls not at {moved}"
        follow = page.locator(".pmk-live-follow")
        expect(follow).not_to_have_class(ACTIVE)
        # -- Centre with no chair: back to the middle of the map
        page.locator("button.pmk-live-centre").click()
        assert wait_until(page, lambda: walls_at(want)), f"Centre: walls not at {want}"

        # -- the chair live: Follow keeps it in the middle, a drag lets it go, Centre brings it back
        page.locator("button.pmk-home-preview").click()
        expect(page.locator(".pmk-home-info-state")).to_contain_text("Live", timeout=60_000)
        follow.click()  # Follow on again
        expect(follow).to_have_class(ACTIVE)

        # the middle of the part of the map no panel covers (the tool bar, the status line: issue 28)
        left, top, right, bottom = settled_state(page)["insets"]
        mid = (left + (w - left - right) / 2, top + (h - top - bottom) / 2)

        def near_middle(tolerance: float) -> bool:
            c = chair_centre(pixels(page))
            return c is not None and math.dist(c, mid) < tolerance

        assert wait_until(page, lambda: near_middle(12)), f"following: the chair is off ({chair_centre(pixels(page))})"
        page.mouse.move(cx, cy)
        page.mouse.down()
        page.mouse.move(cx - 150, cy, steps=5)
        page.mouse.up()
        expect(follow).not_to_have_class(ACTIVE)
        page.wait_for_timeout(300)  # (the chair drives at under 40 px/s here: it cannot be back yet)
        away = chair_centre(pixels(page))
        assert away is not None and math.dist(away, mid) > 80 * sx, "a drag must stop following"
        page.locator("button.pmk-live-centre").click()
        assert wait_until(page, lambda: near_middle(40)), "Centre did not bring the chair back to the middle"
        page.screenshot(path=str(ARTIFACTS / "live-following.png"))
