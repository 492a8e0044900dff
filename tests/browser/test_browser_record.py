"""Record on Home in a real browser (issue 29): the demo page records the simulated chair, Stop
finishes the file, and the download links give the MCAP file and the current map's zip; Replay
(issue 40) shows the recording, and moving its slider changes what the picture shows; a ros2 bag of
more than 10 MiB uploaded from the device replays too, its plot's cursor following the slider."""

from __future__ import annotations

import io
import re
import zipfile
from pathlib import Path

import pytest

from tests.browser.kiosk_page import ARTIFACTS, VIEWPORT, chromium_page, serve_kiosk

pytestmark = [pytest.mark.slow, pytest.mark.browser, pytest.mark.timeout(300)]


def test_record_stop_and_download_on_home(tmp_path: Path) -> None:
    from playwright.sync_api import expect

    with serve_kiosk(tmp_path, label="record") as (url, _world), chromium_page(url, viewport=VIEWPORT) as page:
        expect(page.locator(".pmk-record-start")).to_be_visible(timeout=120_000)  # the page is up
        page.locator(".pmk-record-start").click()
        status = page.locator(".pmk-record-status")
        expect(status).to_contain_text(re.compile(r"Recording 0:\d\d · [1-9]\d* messages"), timeout=30_000)
        expect(page.locator(".pmk-record-stop")).to_be_visible()
        page.wait_for_timeout(1500)
        page.locator(".pmk-record-stop").click()
        link = page.locator("a.pmk-record-link")
        expect(link).to_be_visible(timeout=30_000)
        expect(status).to_contain_text("Recorded")
        with page.expect_download() as got:
            link.click()
        saved = Path(got.value.path())
        assert got.value.suggested_filename.endswith(".mcap")
        assert saved.read_bytes().startswith(b"\x89MCAP0\r\n")

        page.locator(".pmk-record-map").click()
        map_link = page.locator("a.pmk-map-link")
        expect(map_link).to_be_visible(timeout=30_000)
        with page.expect_download() as got_map:
            map_link.click()
        with zipfile.ZipFile(io.BytesIO(Path(got_map.value.path()).read_bytes())) as zf:
            names = zf.namelist()
        assert any(n.endswith(".yaml") for n in names) and len(names) == 2, names
        ARTIFACTS.mkdir(exist_ok=True)
        page.screenshot(path=str(ARTIFACTS / "record-home.png"))

        page.locator(".pmk-record-replay").click()
        picture = page.locator(".pmk-replay-picture img")
        expect(picture).to_be_visible(timeout=30_000)
        caption = page.locator(".pmk-replay-caption")
        expect(caption).to_contain_text("chair at x")
        expect(caption).not_to_contain_text(re.compile(r"^(\d+\.\d) s of \1 s"))  # it opens on the first pose
        page.locator(".pmk-replay-slider .noUi-handle").press("End")  # to the recording's end, by keyboard
        expect(caption).to_contain_text(re.compile(r"^(\d+\.\d) s of \1 s · chair at x"), timeout=30_000)
        page.screenshot(path=str(ARTIFACTS / "record-replay.png"))

        # another tool's recording (a ros2 bag's MCAP), uploaded from this device: kept and replayed
        from tests.ros2_bags import SPEED, write_drive_bag

        # over tornado's default 10 MiB websocket message: the page's socket must carry it (voila.json)
        bag = write_drive_bag(tmp_path / "device", seconds=4.0, name="corridor", rays=70_000, scan_every=1)
        assert bag.stat().st_size > 10 * 2**20
        with page.expect_file_chooser() as chooser:
            page.locator(".pmk-record-upload").first.click()
        chooser.value.set_files(str(bag))
        opened = page.locator(".pmk-record-open-status")
        expect(opened).to_contain_text("Replaying corridor.mcap: 4.0 s", timeout=30_000)
        expect(caption).to_contain_text("chair at x 0.00 m, y 1.00 m")
        value = page.locator(".pmk-replay-value")
        expect(value).to_contain_text(f"/odom · twist.twist.linear.x = {SPEED:.4g} at 0.0 s")
        cursor = page.locator(".pmk-replay-cursor")
        start_left = cursor.evaluate("el => el.getBoundingClientRect().left")
        page.locator(".pmk-replay-slider .noUi-handle").press("End")
        expect(caption).to_contain_text("4.0 s of 4.0 s · chair at x 2.00 m, y 1.00 m", timeout=30_000)
        expect(value).to_contain_text("at 4.0 s")
        assert cursor.evaluate("el => el.getBoundingClientRect().left") > start_left + 100  # it crossed the plot
        files = page.locator(".pmk-record-files select")
        # kept in the recordings folder, chosen in the list
        expect(files).to_have_value(re.compile(r"^corridor\.mcap \("))
        page.screenshot(path=str(ARTIFACTS / "record-replay-bag.png"))
