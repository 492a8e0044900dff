"""The Maps screen's witness panel in Chromium: a leak painted into a map, found by "Check against the plan"."""

from __future__ import annotations

import json
from pathlib import Path

from pmk_nb.access import sidecar_path
from pmk_nb.library import MapsFolder
from tests.browser.kiosk_page import ARTIFACTS, VIEWPORT, chromium_page, serve_kiosk
from tests.browser.test_browser_access import _access_panel
from tests.witness.test_witness_cli import SAMPLE, _open_wall


def test_maps_screen_shows_the_witness_disagreeing_with_its_picture(tmp_path: Path) -> None:
    from playwright.sync_api import expect

    with serve_kiosk(tmp_path, label="witness") as (url, world):
        maps = MapsFolder(world.maps_dir)
        maps.convert(maps.import_file(SAMPLE, "clinic").name, 0.05)
        [gm] = maps.entry("clinic").generated
        rooms = sidecar_path(gm.yaml)
        doc = json.loads(rooms.read_text(encoding="utf-8"))
        del doc["witness"]  # a map converted before the witness ...
        rooms.write_text(json.dumps(doc), encoding="utf-8")
        _open_wall(gm.yaml)  # ... whose image was edited since: a wall opened between two rooms
        with chromium_page(url, viewport=VIEWPORT) as page:
            _access_panel(page, "clinic")
            panel = page.locator(".pmk-witness")
            expect(panel).to_contain_text("This map has not been witnessed")
            page.locator("button.pmk-witness-check").click()
            expect(panel).to_contain_text("The map DISAGREES with the plan: 1 finding", timeout=60_000)
            expect(panel.locator(".pmk-witness-list li")).to_have_count(1)
            expect(panel.locator(".pmk-witness-list li").first).to_contain_text("leak: ")
            expect(panel).to_contain_text("Waiting room")
            picture = page.locator("img.pmk-witness-picture")
            expect(picture).to_be_visible(timeout=30_000)
            size = picture.evaluate("img => [img.complete, img.naturalWidth, img.naturalHeight]")
            assert size == [True, 607, 307], f"the witness's picture did not load: {size}"
            picture.scroll_into_view_if_needed()
            ARTIFACTS.mkdir(exist_ok=True)
            page.screenshot(path=str(ARTIFACTS / "maps-witness.png"), full_page=True)
