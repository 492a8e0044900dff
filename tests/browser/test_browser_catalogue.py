"""The Maps screen's Catalogue tab in Chromium (issue 27): add a catalogue served by a real static web
server, see the building with its thumbnail and "New", search by name, Get it, see it installed."""

from __future__ import annotations

import time
from pathlib import Path

from pmk_nb.catalogue.publish import publish
from pmk_nb.library import ALLOW_LOCAL_ENV, MapsFolder
from tests.browser.kiosk_page import ARTIFACTS, VIEWPORT, chromium_page, serve_kiosk
from tests.stac_site import serve_static

SAMPLE = Path(__file__).resolve().parents[2] / "sample_maps" / "clinic_two_storeys.gml"


def test_catalogue_tab_lists_searches_and_installs_a_building(tmp_path: Path) -> None:
    from playwright.sync_api import expect

    lab = MapsFolder(tmp_path / "lab-maps")
    lab.import_file(SAMPLE, "clinic")
    lab.convert("clinic", 0.1)
    publish(lab, tmp_path / "www" / "site", title="Lab maps")
    started = time.monotonic()
    with (
        serve_static(tmp_path / "www") as site,
        serve_kiosk(tmp_path, label="catalogue", env={ALLOW_LOCAL_ENV: "1"}) as (url, world),
    ):
        catalogue_url = site.url + "site/catalog.json"
        with chromium_page(url, viewport=VIEWPORT) as page:
            expect(page.locator("button.pmk-nav-maps")).to_be_visible(timeout=120_000)
            page.locator("button.pmk-nav-maps").click()
            page.get_by_role("tab", name="Catalogue").click()
            page.locator(".pmk-cat-url input").fill(catalogue_url)
            page.locator("button.pmk-cat-add").click()
            card = page.locator(".pmk-cat-card")
            expect(card).to_have_count(1, timeout=30_000)
            expect(card).to_contain_text("clinic")
            expect(card).to_contain_text("2 storeys: F1 (304×154 at 0.1 m), F2 (304×154 at 0.1 m)")
            expect(card.locator(".pmk-cat-new")).to_have_text("New")
            thumb = card.locator(".pmk-cat-thumb")
            expect(thumb).to_be_visible()
            assert thumb.evaluate("img => img.naturalWidth") > 50  # the thumbnail really decoded
            search = page.locator(".pmk-cat-search input")
            search.fill("ward")
            expect(page.locator(".pmk-cat-results")).to_contain_text("No building matches", timeout=10_000)
            search.fill("CLIN")
            expect(card).to_have_count(1, timeout=10_000)
            card.locator("button.pmk-cat-get").click()
            expect(page.locator(".pmk-cat-status")).to_contain_text("Installed clinic", timeout=30_000)
            expect(card.locator(".pmk-cat-installed")).to_have_text("Installed")
            ARTIFACTS.mkdir(exist_ok=True)
            page.screenshot(path=str(ARTIFACTS / "maps-catalogue.png"), full_page=True)
            page.get_by_role("tab", name="Maps").click()
            expect(page.locator(".pmk-maps-list select")).to_contain_text("clinic", timeout=10_000)
        assert (world.config_dir / "catalogues.json").read_text().count(catalogue_url) == 1
    for source in lab.root.iterdir():  # every file, byte for byte (the demo's own clinic_floor stays beside)
        assert (world.maps_dir / source.name).read_bytes() == source.read_bytes()
    print(f"catalogue browser test: {time.monotonic() - started:.1f} s")
