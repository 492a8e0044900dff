"""Home's Record panel (issue 29), kernel side against the simulated chair: record, stop, the download
link carries the MCAP file; the current map as a zip; a locked kiosk page cannot start a recording."""

from __future__ import annotations

import base64
import io
import re
import zipfile
from pathlib import Path

from pmk_nb.chair import ChairProfile
from pmk_nb.rosmap import write_map
from pmk_nb.ui.kiosk.pin import KioskLock, PinStore
from pmk_nb.ui.record.panel import RecordPanel, recordings_dir
from tests.fixtures_sim import room_grid, wait_until
from tests.helpers import app_context

MCAP_MAGIC = b"\x89MCAP0\r\n"


def _link_bytes(html: str) -> tuple[str, bytes]:
    found = re.search(r'download="([^"]+)" href="data:[^;]+;base64,([^"]+)"', html)
    assert found, html
    return found.group(1), base64.b64decode(found.group(2))


def test_record_stop_and_download_the_file(sim_factory, tmp_path: Path) -> None:
    sim = sim_factory()
    with app_context(tmp_path) as ctx:
        ctx.profiles.save(ChairProfile(name="sim", host="127.0.0.1", port=sim.port))
        panel = RecordPanel(ctx)
        try:
            thread = panel.start()
            assert thread is not None
            thread.join(30)
            assert panel.recording is not None, panel.status.value
            assert panel.stop_button.layout.display == "" and panel.record_button.layout.display == "none"
            assert wait_until(lambda: panel.recording is not None and panel.recording.stats.total > 20, timeout=20)
            panel.refresh()
            assert re.search(r"Recording 0:\d\d · \d+ messages · rec-\d{8}-\d{6}\.mcap", panel.status.value)
            panel.stop().join(30)
            assert panel.recording is None and panel.record_button.layout.display == ""
            name, data = _link_bytes(panel.downloads.value)
            files = list(recordings_dir(ctx).iterdir())
            assert [f.name for f in files] == [name] and recordings_dir(ctx).parent == ctx.maps.root.parent
            assert data == files[0].read_bytes() and data.startswith(MCAP_MAGIC)
        finally:
            panel.close()


def test_the_current_map_downloads_as_a_zip_of_yaml_and_image(tmp_path: Path) -> None:
    with app_context(tmp_path) as ctx:
        panel = RecordPanel(ctx)
        panel.offer_map()
        assert "No current map" in panel.map_link.value
        files = write_map(room_grid(), tmp_path / "maps", "lab", preview=False)
        ctx.set_current_map("lab", files.yaml, None)
        panel.offer_map()
        name, data = _link_bytes(panel.map_link.value)
        assert name == "lab.zip"
        with zipfile.ZipFile(io.BytesIO(data)) as zf:
            assert sorted(zf.namelist()) == ["lab.pgm", "lab.yaml"]
            assert zf.read("lab.pgm") == (tmp_path / "maps" / "lab.pgm").read_bytes()


def test_a_locked_kiosk_page_cannot_start_a_recording(tmp_path: Path) -> None:
    PinStore(tmp_path / "cfg").set_pin("2468", "2468")
    with app_context(tmp_path) as ctx:
        ctx.kiosk = KioskLock(PinStore(ctx.config_dir))
        ctx.profiles.save(ChairProfile(name="sim", host="127.0.0.1", port=9))
        panel = RecordPanel(ctx)
        panel.record_button.click()
        assert panel.recording is None and not recordings_dir(ctx).exists()
        assert any("locked" in n.message for n in ctx.notifications)
