"""Maps screen driven like a user: import, select, convert, send to the simulated chair, download."""

from __future__ import annotations

import base64
import datetime as dt
import http.server
import re
import socket
import threading
from collections.abc import Iterator
from pathlib import Path
from typing import Any, ClassVar

import pytest

from pmk_nb.chair import ChairProfile
from pmk_nb.ui.common.context import AppContext
from pmk_nb.ui.maps.screen import MapsScreen, parse_resolution
from tests.fixtures_sim import sim_profile
from tests.helpers import wait_until
from tests.indoorgml_samples import HTML_PAGE, two_rooms

SAMPLE_MAPS = Path(__file__).resolve().parents[3] / "sample_maps"
NOW = dt.datetime(2026, 1, 1, tzinfo=dt.UTC)  # FileUpload's kernel-side value format


def errors(ctx: AppContext) -> list[str]:
    return [n.message for n in ctx.notifications if n.level == "error"]


def send_buttons(screen: MapsScreen) -> list[Any]:
    return screen._send_buttons()


def trust_sim_key(sim: Any, known_hosts: Path) -> None:
    """Record the simulator's SSH host key, as a user confirming it once would (tests/ui/maps/test_host_key.py)."""
    kind, blob = sim.sftp_host_key.split()[:2]
    known_hosts.write_text(f"[127.0.0.1]:{sim.sftp_port} {kind} {blob}\n")


@pytest.mark.parametrize("raw", ["0.05", " 0.1 ", "1", "0,05"])
def test_resolution_accepts(raw: str) -> None:
    assert 0 < parse_resolution(raw) <= 1


@pytest.mark.parametrize("raw", ["", "abc", "0", "-0.05", "1.5", "nan", "inf", "1e9"])
def test_resolution_rejects(raw: str) -> None:
    with pytest.raises(ValueError):
        parse_resolution(raw)


def test_upload_lists_and_selects_the_map(screen: MapsScreen, ctx: AppContext) -> None:
    data = two_rooms(("F1", "F2"))
    screen.upload.value = (
        {
            "name": "house.gml",
            "type": "application/gml+xml",
            "size": len(data),
            "content": memoryview(data),
            "last_modified": NOW,
        },
    )
    assert screen.upload.value == ()  # reset so the same file can be chosen again
    assert (ctx.maps.root / "house.gml").read_bytes() == data
    assert screen.map_list.value == "house"
    assert "not converted" in screen.map_list.options[0][0]
    assert "house" in screen.title.value and screen.convert_row.layout.display == "flex"
    assert send_buttons(screen) == []  # nothing to send before converting
    # importing the same name again asks first, and only the confirm button replaces it
    screen.import_bytes("house.gml", two_rooms(("F1",), width=9.0))
    assert screen.import_confirm.visible
    assert (ctx.maps.root / "house.gml").read_bytes() == data
    screen.import_confirm.no.click()
    assert not screen.import_confirm.visible and (ctx.maps.root / "house.gml").read_bytes() == data
    screen.import_bytes("house.gml", two_rooms(("F1",), width=9.0))
    screen.import_confirm.yes.click()
    assert (ctx.maps.root / "house.gml").read_bytes() != data


def test_import_of_a_non_indoorgml_file_is_reported(screen: MapsScreen, ctx: AppContext) -> None:
    screen.upload.value = (
        {
            "name": "page.gml",
            "type": "",
            "size": len(HTML_PAGE),
            "content": memoryview(HTML_PAGE),
            "last_modified": NOW,
        },
    )
    assert errors(ctx), "an HTML page must not be imported silently"
    assert not (ctx.maps.root / "page.gml").exists()
    said = screen.importer.status.value
    # in the page's words: the file's own name, no temporary path, no advice about URLs
    assert "page.gml" in said and "pmk-msg-error" in said
    assert "pmk-upload" not in said and "/tmp" not in said and "URL" not in said


def test_import_of_non_xml_names_the_file_and_the_line(screen: MapsScreen, ctx: AppContext) -> None:
    screen.import_bytes("plan.xml", b"<IndoorFeatures>\n<unclosed>\n")
    said = screen.importer.status.value
    assert "plan.xml is not an IndoorGML map" in said and "line" in said
    assert "pmk-upload" not in said and "URL" not in said
    screen.import_bytes("house.gml", two_rooms())  # the next import that works clears the failure
    assert "Imported house.gml" in screen.importer.status.value and "plan.xml" not in screen.importer.status.value


def test_bad_resolution_blocks_convert(screen: MapsScreen, ctx: AppContext) -> None:
    screen.import_bytes("house.gml", two_rooms())
    screen.resolution.value = "lots"
    screen.convert_button.click()
    assert "not a number" in screen.resolution_error.value
    assert screen.convert() is None, "refused before a conversion thread starts: nothing can write a map later"
    assert not list(ctx.maps.root.glob("*.yaml"))


def test_too_fine_resolution_suggests_one_that_fits(screen: MapsScreen, ctx: AppContext) -> None:
    screen.import_bytes("house.gml", two_rooms())
    screen.resolution.value = "0.0001"  # a valid number, but billions of cells for a house
    thread = screen.convert()
    assert thread is not None
    thread.join(60)
    suggestion = screen.resolution_error.value
    assert "too large" in suggestion and "--" not in suggestion  # the page's words, no CLI options
    suggested = float(suggestion.split("Use ")[1].split(" m")[0])
    assert 0.0001 < suggested <= 0.05  # the finest resolution that fits the budget, not any
    # one place: under the field only; the finished bar is gone
    assert screen.status.value == "" and screen.convert_progress.layout.display == "none" and errors(ctx)
    assert not list(ctx.maps.root.glob("*.yaml"))
    screen.resolution.value = "5"  # the next attempt's message replaces the budget error
    screen.convert_button.click()
    assert "too coarse" in screen.resolution_error.value and "too large" not in screen.resolution_error.value
    assert screen.status.value == ""


def test_convert_requires_a_selection(screen: MapsScreen, ctx: AppContext) -> None:
    screen.convert_button.click()
    assert any("Select a map" in e for e in errors(ctx))


@pytest.mark.slow
def test_convert_and_send_to_the_simulator(
    screen: MapsScreen, ctx: AppContext, sim_factory: Any, tmp_path: Path
) -> None:
    screen.import_bytes("house.gml", two_rooms(("F1", "F2")))
    screen.resolution.value = "0.1"
    screen.convert_button.click()
    wait_until(lambda: len(send_buttons(screen)) == 2, what="two storeys converted")
    assert screen.convert_progress.value == 1.0 and not errors(ctx)
    assert "2 storeys" in screen.map_list.options[0][0]
    previews = [c for c in screen.generated_box.children if "pmk-maps-preview" in c.children[0]._dom_classes]
    # the preview is an <img> with a text alternative (WCAG 1.1.1), its PNG inline
    img = re.search(r'src="data:image/png;base64,([^"]+)" alt="([^"]+)"', previews[0].children[0].value)
    assert len(previews) == 2 and img is not None and base64.b64decode(img.group(1))[:4] == b"\x89PNG"
    assert img.group(2).startswith("Preview of the map")

    chair_dir = tmp_path / "chair"
    sim = sim_factory(sftp_port=0, maps_dir=chair_dir)
    ctx.profiles.save(
        ChairProfile(
            name="sim",
            host="127.0.0.1",
            port=sim.port,
            ssh_user=sim.config.sftp_user,
            ssh_port=sim.sftp_port,
            known_hosts=str(tmp_path / "known_hosts"),
        )
    )
    trust_sim_key(sim, tmp_path / "known_hosts")
    # password auth with no stored password: Send asks for it in the page
    send_buttons(screen)[1].click()
    assert screen.password_box.layout.display == "flex"
    screen.password.value = sim.sftp_password
    screen.password_ok.click()
    wait_until(lambda: ctx.current_map or errors(ctx), what="the map to be sent")
    assert not errors(ctx)
    current = ctx.current_map
    entry = ctx.maps.entry("house")
    sent = entry.generated[1]
    assert current.yaml == sent.yaml and current.preview == sent.preview
    assert (chair_dir / sent.yaml.name).is_file()
    wait_until(lambda: sim.grid is not None and sim.grid.width == sent.width, what="the chair to load the map")
    assert sim.grid.height == sent.height
    assert "current map" in screen.status.value and not errors(ctx)
    assert ctx.ssh_password(ctx.profile()) == sim.sftp_password  # asked once per session


@pytest.mark.slow
def test_send_with_key_login_to_a_key_only_chair(
    screen: MapsScreen, ctx: AppContext, sim_factory: Any, tmp_path: Path
) -> None:
    """The demo's set-up: the chair refuses passwords; Send logs in with the profile's key, asks nothing."""
    from pmk_nb.cli.demo_setup import make_key_pair

    private, public = make_key_pair(tmp_path / "keys")
    screen.import_bytes("house.gml", two_rooms())
    screen.resolution.value = "0.2"
    screen.convert_button.click()
    wait_until(lambda: send_buttons(screen), what="conversion")
    chair_dir = tmp_path / "chair"
    sim = sim_factory(sftp_port=0, maps_dir=chair_dir, sftp_authorized_key=public, sftp_password_login=False)
    assert sim.sftp_password is None
    profile = sim_profile(sim, tmp_path, name="keyed", auth="key", key_file=str(private))
    ctx.profiles.save(profile)
    trust_sim_key(sim, Path(profile.known_hosts))
    send_buttons(screen)[0].click()
    assert screen.password_box.layout.display == "none"  # no password asked for
    wait_until(lambda: ctx.current_map or errors(ctx), what="the map to be sent")
    assert not errors(ctx)
    assert (chair_dir / ctx.current_map.yaml.name).is_file()
    # the same chair with a key it does not know: refused, and said so in the page
    other, _ = make_key_pair(tmp_path / "other")
    ctx.profiles.save(ChairProfile(**{**profile.to_dict(), "key_file": str(other)}))
    send_buttons(screen)[0].click()
    wait_until(lambda: errors(ctx), what="the refusal")
    assert "key" in errors(ctx)[-1].lower() and "Traceback" not in screen.status.value


def test_send_without_profile_says_what_to_do(screen: MapsScreen, ctx: AppContext) -> None:
    screen.import_bytes("house.gml", two_rooms())
    screen.resolution.value = "0.2"
    screen.convert_button.click()
    wait_until(lambda: send_buttons(screen), what="conversion")
    send_buttons(screen)[0].click()
    assert any("Settings" in e for e in errors(ctx))
    assert ctx.current_map is None


def test_send_to_a_closed_port_reports_failure(screen: MapsScreen, ctx: AppContext, tmp_path: Path) -> None:
    screen.import_bytes("house.gml", two_rooms())
    screen.resolution.value = "0.2"
    screen.convert_button.click()
    wait_until(lambda: send_buttons(screen), what="conversion")
    port = _closed_port()
    ctx.profiles.save(gone := ChairProfile(name="gone", host="127.0.0.1", port=port, ssh_port=port, ssh_user="pmk"))
    ctx.profiles.set_password(gone, "x")
    send_buttons(screen)[0].click()
    wait_until(lambda: errors(ctx), timeout=60, what="the failure message")
    assert "pmk-msg-error" in screen.status.value and ctx.current_map is None
    assert screen.send_progress.layout.display == "none"  # the message says it: no red bar left behind


# -- download -------------------------------------------------------------------------------------
class _Handler(http.server.BaseHTTPRequestHandler):
    routes: ClassVar[dict[str, bytes]] = {}

    def do_GET(self) -> None:
        body = self.routes.get(self.path)
        if body is None:
            self.send_error(404)
            return
        self.send_response(200)
        self.send_header("Content-Length", str(len(body)))
        self.end_headers()
        self.wfile.write(body)

    def log_message(self, *_args: Any) -> None:
        return None


@pytest.fixture
def web() -> Iterator[str]:
    _Handler.routes = {"/house.gml": two_rooms(), "/house2.gml": two_rooms(width=9.0), "/page.gml": HTML_PAGE}
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), _Handler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    yield f"http://127.0.0.1:{server.server_address[1]}"
    server.shutdown()
    server.server_close()


def _closed_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.mark.slow
def test_download_then_confirm_overwrite(screen: MapsScreen, ctx: AppContext, web: str) -> None:
    ctx.maps.allow_local = True  # the test server is on 127.0.0.1 (pmk dashboard --allow-local)
    screen.tabs.selected_index = 1
    screen.downloader.url.value, screen.downloader.name.value = f"{web}/house.gml", "clinic"
    screen.downloader.button.click()
    wait_until(lambda: ctx.maps.exists("clinic") and "Downloaded" in screen.downloader.status.value, what="download")
    assert screen.downloader.progress.value == 1.0
    assert "clinic" in [v for _label, v in screen.map_list.options]
    first = (ctx.maps.root / "clinic.gml").read_bytes()
    screen.downloader.url.value = f"{web}/house2.gml"
    screen.downloader.button.click()
    assert screen.downloader.confirm.visible  # explicit confirm step before overwriting
    assert (ctx.maps.root / "clinic.gml").read_bytes() == first
    screen.downloader.confirm.yes.click()
    wait_until(lambda: (ctx.maps.root / "clinic.gml").read_bytes() != first, what="overwrite")


@pytest.mark.slow
@pytest.mark.parametrize(
    ("path", "expect"),
    [("/page.gml", "IndoorGML"), ("/missing.gml", "404"), (None, "")],
)
def test_download_failures_are_explained(
    screen: MapsScreen, ctx: AppContext, web: str, path: str | None, expect: str
) -> None:
    ctx.maps.allow_local = True  # the test server is on 127.0.0.1 (pmk dashboard --allow-local)
    url = f"{web}{path}" if path else f"http://127.0.0.1:{_closed_port()}/x.gml"
    screen.downloader.url.value, screen.downloader.name.value = url, "bad"
    screen.downloader.button.click()
    wait_until(lambda: "pmk-msg-error" in screen.downloader.status.value, what="failure message")
    assert expect in screen.downloader.status.value
    assert not ctx.maps.exists("bad")


@pytest.mark.slow
def test_a_loopback_download_is_refused_by_default(screen: MapsScreen, ctx: AppContext, web: str) -> None:
    """Issue 30 (SSRF): the page could make the kernel fetch a loopback or LAN address and show it."""
    screen.downloader.url.value, screen.downloader.name.value = f"{web}/house.gml", "inside"
    screen.downloader.button.click()
    wait_until(lambda: "pmk-msg-error" in screen.downloader.status.value, what="refusal")
    assert "loopback address" in screen.downloader.status.value and "--allow-local" in screen.downloader.status.value
    assert not ctx.maps.exists("inside")


def test_download_validates_inputs(screen: MapsScreen, ctx: AppContext) -> None:
    screen.downloader.url.value, screen.downloader.name.value = "ftp://x/y.gml", "n"
    screen.downloader.button.click()
    assert "http" in screen.downloader.error.value
    screen.downloader.url.value, screen.downloader.name.value = "http://127.0.0.1/y.gml", "  "
    screen.downloader.button.click()
    assert "name" in screen.downloader.error.value
    screen.downloader.url.value, screen.downloader.name.value = "http://127.0.0.1/y.gml", "../etc/passwd"
    screen.downloader.button.click()
    wait_until(lambda: errors(ctx), what="name rejected")
    assert not list(ctx.maps.root.parent.glob("etc*"))


def storey_checks(screen: MapsScreen) -> dict[str, Any]:
    return {b.description: b for b in screen.storeys_panel.choices.children}


def test_selecting_an_unconverted_two_storey_map_shows_its_storeys(screen: MapsScreen, ctx: AppContext) -> None:
    data = (SAMPLE_MAPS / "clinic_two_storeys.gml").read_bytes()
    screen.import_bytes("clinic_two_storeys.gml", data)
    assert ctx.maps.storey_reads <= 1  # importing does not parse the whole building
    screen.select("clinic_two_storeys")
    wait_until(lambda: "F2" in screen.storeys_panel.table.value, what="storeys read in the background")
    table = screen.storeys_panel.table.value
    assert "F1" in table and "F2" in table and "30.0 × 15.0 m" in table and "<td>15</td>" in table
    assert set(storey_checks(screen)) == {"F1", "F2"} and all(b.value for b in storey_checks(screen).values())
    assert screen.storeys_panel.choice_box.layout.display == "flex"
    wait_until(lambda: "2 storeys, not converted" in screen.map_list.options[0][0], what="storey count in the list")
    assert screen.map_list.value == "clinic_two_storeys"  # relabelling keeps the selection
    # once known, selecting it again shows the storeys at once (no thread)
    assert screen.storeys_panel.show(screen.entries["clinic_two_storeys"]) is None
    assert "F2" in screen.storeys_panel.table.value
    assert not errors(ctx)


def test_a_changed_file_has_its_storeys_read_again(screen: MapsScreen, ctx: AppContext) -> None:
    screen.import_bytes("house.gml", two_rooms(("A", "B", "C")))
    wait_until(lambda: "C" in screen.storeys_panel.table.value, what="storeys of the imported map")
    reads = ctx.maps.storey_reads
    (ctx.maps.root / "house.gml").write_bytes(two_rooms(("A",), width=9.0))  # changed behind our back
    screen.refresh()  # shows the selected map again: its cached storeys are stale, so they are read again
    thread = screen.storeys_panel.show(screen.entries["house"])  # None if refresh's read already finished
    if thread is not None:
        thread.join(10)
    wait_until(lambda: "<td>B</td>" not in screen.storeys_panel.table.value, what="the new storeys")
    assert "<td>A</td>" in screen.storeys_panel.table.value
    assert ctx.maps.storey_reads > reads  # read from the changed file, not served from the stale cache
    assert screen.storeys_panel.choice_box.layout.display == "none"  # one storey: nothing to choose


def test_a_broken_file_shows_why_its_storeys_are_unknown(screen: MapsScreen, ctx: AppContext) -> None:
    ctx.maps.root.mkdir(parents=True, exist_ok=True)
    (ctx.maps.root / "broken.gml").write_bytes(HTML_PAGE)  # dropped in by hand, never checked
    screen.refresh()
    thread = screen.storeys_panel.show(screen.entries["broken"])
    assert thread is not None
    thread.join(10)
    assert "Cannot read the storeys" in screen.storeys_panel.table.value
    assert any("broken.gml" in e for e in errors(ctx))


def test_converting_only_f2_writes_only_f2s_files(screen: MapsScreen, ctx: AppContext) -> None:
    screen.import_bytes("clinic_two_storeys.gml", (SAMPLE_MAPS / "clinic_two_storeys.gml").read_bytes())
    wait_until(lambda: len(storey_checks(screen)) == 2, what="storey checkboxes")
    checks = storey_checks(screen)
    checks["F1"].value = False
    checks["F2"].value = False
    assert "at least one storey" in screen.storeys_panel.choice_error.value
    screen.convert_button.click()  # nothing ticked: refused, nothing written
    assert any("at least one storey" in e for e in errors(ctx)) and not list(ctx.maps.root.glob("*.yaml"))
    checks["F2"].value = True
    assert screen.storeys_panel.choice_error.value == ""
    screen.resolution.value = "0.1"
    thread = screen.convert()
    assert thread is not None
    thread.join(60)
    written = sorted(p.name for p in ctx.maps.root.iterdir() if not p.name.endswith(".gml"))
    assert written == [
        "clinic_two_storeys_F2-visualization.png",
        "clinic_two_storeys_F2.pgm",
        "clinic_two_storeys_F2.rooms.json",
        "clinic_two_storeys_F2.yaml",
    ]
    assert "2 storeys, 0.1 m" in screen.map_list.options[0][0]
    assert [g.storey for g in screen.entries["clinic_two_storeys"].generated] == ["F2"]
    assert [b.description for b in send_buttons(screen)] == ["Send F2"]
    # a converted map's storeys show at once, with every storey ticked again
    assert screen.storeys_panel.show(screen.entries["clinic_two_storeys"]) is None
    assert all(b.value for b in storey_checks(screen).values())
    with pytest.raises(Exception, match="No storey F3"):
        screen.storeys_panel.check(["F3"])
    screen.storeys_panel.check(["F1"])
    assert screen.storeys_panel.selected() == ["F1"]
