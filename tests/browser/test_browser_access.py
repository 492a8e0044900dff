"""The Maps screen's accessibility panel in Chromium: blocked doors named, marked in red on the preview."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from pmk_nb.access import sidecar_doc
from pmk_nb.library import MapsFolder
from tests.browser.kiosk_page import ARTIFACTS, VIEWPORT, chromium_page, serve_kiosk
from tests.shared_data import INDOORGML_DATA


def _access_panel(page: Any, name: str) -> Any:
    """Open the Maps screen, select the map ``name`` and return its accessibility panel, once shown."""
    from playwright.sync_api import expect

    expect(page.locator("button.pmk-nav-maps")).to_be_visible(timeout=120_000)
    page.locator("button.pmk-nav-maps").click()
    select = page.locator(".pmk-maps-list select")
    expect(select).to_contain_text(name, timeout=30_000)
    labels = select.locator("option").all_inner_texts()
    select.select_option(index=next(i for i, t in enumerate(labels) if t.startswith(name)))
    panel = page.locator(".pmk-access")
    expect(panel).to_contain_text("Wheelchair access", timeout=30_000)
    return panel


def test_maps_screen_shows_the_accessibility_report(tmp_path: Path) -> None:
    from playwright.sync_api import expect

    with serve_kiosk(tmp_path, label="access") as (url, world):
        maps = MapsFolder(world.maps_dir)
        entry = maps.import_file(INDOORGML_DATA / "pnu_abc_3floors_4layers.gml", "pnu_abc")
        maps.convert(entry.name, 0.1, chair_width=1.2)  # a wide chair: a passage on every storey is too narrow
        with chromium_page(url, viewport=VIEWPORT) as page:
            panel = _access_panel(page, "pnu_abc")
            expect(panel).to_contain_text("fourth Floor South Stair")  # blocked, by its room names
            expect(panel).to_contain_text("narrower than the chair")
            expect(panel).to_contain_text("Size warning")
            previews = page.locator(".pmk-access-preview")
            expect(previews.first).to_be_visible()
            assert previews.count() == 3  # every storey of pnu_abc has a blocked passage
            # the marks are really red on the picture the user sees
            red = min(
                previews.nth(i).evaluate(
                    """img => { const c = document.createElement('canvas'); c.width = img.naturalWidth;
                c.height = img.naturalHeight; const g = c.getContext('2d'); g.drawImage(img, 0, 0);
                const d = g.getImageData(0, 0, c.width, c.height).data; let n = 0;
                for (let i = 0; i < d.length; i += 4) if (d[i] > 200 && d[i+1] < 60 && d[i+2] < 60) n++;
                return n; }"""
                )
                for i in range(3)
            )
            assert red > 20, f"only {red} red pixels on the marked preview"
            previews.first.scroll_into_view_if_needed()
            ARTIFACTS.mkdir(exist_ok=True)
            page.screenshot(path=str(ARTIFACTS / "maps-accessibility.png"), full_page=True)


def test_maps_screen_names_the_transitions_it_could_not_check(tmp_path: Path) -> None:
    """FZK-Haus links its window cells: the panel names those passages as not checked, not as passable."""
    from playwright.sync_api import expect

    with serve_kiosk(tmp_path, label="access-windows") as (url, world):
        maps = MapsFolder(world.maps_dir)
        entry = maps.import_file(INDOORGML_DATA / "fzk_haus_poslist.gml", "fzk")
        maps.convert(entry.name, 0.05)
        with chromium_page(url, viewport=VIEWPORT) as page:
            panel = _access_panel(page, "fzk")
            expect(panel).to_contain_text("Not checked: 9 passages into cells taken for windows or sills")
            expect(panel).to_contain_text("Not checked: 2 passages into cells taken for windows or sills")
            expect(panel).to_contain_text("the window rule misjudged it")
            expect(panel).to_contain_text("9 of 9 passages fit a 0.70 m wheelchair")
            expect(panel).to_contain_text("Not checked: 2 passages into doorways out of the map")
            panel.scroll_into_view_if_needed()
            ARTIFACTS.mkdir(exist_ok=True)
            page.screenshot(path=str(ARTIFACTS / "maps-accessibility-not-checked.png"), full_page=True)


def test_a_window_that_is_a_door_is_kept_navigable_from_the_maps_screen(tmp_path: Path) -> None:
    """The balcony plan's "office window" is a door: ticked under Not windows, the next Convert keeps it navigable
    and checks its passages, and the choice stays ticked for the conversions after."""
    from playwright.sync_api import expect

    from tests.access.test_not_window import _balcony

    with serve_kiosk(tmp_path, label="access-not-window") as (url, world):
        maps = MapsFolder(world.maps_dir)
        entry = maps.import_file(_balcony(tmp_path, True), "balcony")
        maps.convert(entry.name, 0.05)
        with chromium_page(url, viewport=VIEWPORT) as page:
            panel = _access_panel(page, "balcony")
            expect(panel).to_contain_text("Not checked: 2 passages into cells taken for windows or sills")
            unit = page.locator(".pmk-maps-unit select")  # the plan's unit: the sizes it gives show at once
            expect(page.locator(".pmk-maps-storeys")).to_contain_text("13.0 × 4.0 m")
            unit.select_option(label="decimetres")
            expect(page.locator(".pmk-maps-storeys")).to_contain_text("1.3 × 0.4 m")
            unit.select_option(label="auto (from sizes)")
            expect(page.locator(".pmk-maps-storeys")).to_contain_text("13.0 × 4.0 m")
            box = page.locator(".pmk-maps-not-window input[type=checkbox]")
            expect(box).to_have_count(1)
            expect(page.locator(".pmk-maps-not-window")).to_contain_text("office window")
            expect(box).not_to_be_checked()
            box.check()
            page.locator("button.pmk-maps-convert").click()
            expect(page.locator(".pmk-maps-status")).to_contain_text("Converted balcony", timeout=60_000)
            expect(panel).to_contain_text("3 of 3 passages fit a 0.70 m wheelchair", timeout=30_000)
            expect(panel).not_to_contain_text("Not checked")
            expect(page.locator(".pmk-maps-not-window input[type=checkbox]")).to_be_checked()
            page.locator(".pmk-maps-not-window").scroll_into_view_if_needed()
            ARTIFACTS.mkdir(exist_ok=True)
            page.screenshot(path=str(ARTIFACTS / "maps-not-window.png"), full_page=True)
    [gm] = maps.entry("balcony").generated
    assert (sidecar_doc(gm.yaml) or {})["choices"] == {"unit": "auto", "not_windows": ["office window"]}


def test_the_maps_screen_says_a_plans_doubts_before_and_after_converting(tmp_path: Path) -> None:
    """Issue 31: a sensor layer not drawn (and offered to draw), a lost navigation graph ("nothing checked"),
    and a unit that makes every door absurd, named before any door, as a kiosk user sees them."""
    from playwright.sync_api import expect

    from tests.ui.maps.test_plan_doubts import cm_house, lost_graph_plan, zoned_plan

    plans = {name: tmp_path / name for name in ("zoned", "lost", "house")}
    for folder in plans.values():
        folder.mkdir()
    with serve_kiosk(tmp_path, label="access-doubts") as (url, world):
        maps = MapsFolder(world.maps_dir)
        maps.import_file(zoned_plan(plans["zoned"]), "zoned")
        maps.convert(maps.import_file(lost_graph_plan(plans["lost"]), "lost").name, 0.05)
        maps.convert(maps.import_file(cm_house(plans["house"]), "house").name, 0.5, unit="m")
        with chromium_page(url, viewport=VIEWPORT) as page:
            _access_panel(page, "lost")
            panel = page.locator(".pmk-access")
            expect(panel).to_contain_text("nothing checked: 2 of 2 transitions name states that are not in the file")
            expect(page.locator(".pmk-maps-plan-notes")).to_contain_text("the navigation graph was not used")
            _access_panel(page, "house")
            expect(panel).to_contain_text("Suspect the unit first: all doors are 90 m wide in metres")
            select = page.locator(".pmk-maps-list select")
            labels = select.locator("option").all_inner_texts()
            select.select_option(index=next(i for i, t in enumerate(labels) if t.startswith("zoned")))
            notes = page.locator(".pmk-maps-plan-notes")
            expect(notes).to_contain_text("Layer 'L2' (2 cells) not drawn: a thematic layer", timeout=30_000)
            boxes = page.locator(".pmk-maps-layer input[type=checkbox]")
            expect(boxes).to_have_count(2)
            expect(boxes.nth(0)).to_be_checked()
            expect(boxes.nth(1)).not_to_be_checked()
            notes.scroll_into_view_if_needed()
            ARTIFACTS.mkdir(exist_ok=True)
            page.screenshot(path=str(ARTIFACTS / "maps-plan-doubts.png"), full_page=True)
            boxes.nth(1).check()
            page.locator("button.pmk-maps-convert").click()
            expect(page.locator(".pmk-maps-status")).to_contain_text("Converted zoned", timeout=60_000)
    [gm] = maps.entry("zoned").generated
    assert (sidecar_doc(gm.yaml) or {})["choices"]["layers"] == ["TOPO", "L2"]
