"""`pmk maps ...`: each action prints what it did; errors print one line and exit with status 2."""

from __future__ import annotations

import functools
import json
import subprocess
import sys
import threading
from collections.abc import Iterator
from http.server import SimpleHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path

import pytest

from pmk_nb.cli import main
from pmk_nb.rosmap import read_map
from tests.indoorgml_samples import HTML_PAGE, two_rooms


@pytest.fixture
def maps(tmp_path: Path) -> Path:
    return tmp_path / "ALMA_MAPS"


@pytest.fixture
def gml(tmp_path: Path) -> Path:
    path = tmp_path / "clinic.gml"
    path.write_bytes(two_rooms(("F1", "F2")))
    return path


class _Quiet(SimpleHTTPRequestHandler):
    def log_message(self, format: str, *args: object) -> None:
        pass


@pytest.fixture
def web(tmp_path: Path) -> Iterator[str]:
    site = tmp_path / "site"
    site.mkdir()
    (site / "map.gml").write_bytes(two_rooms())
    (site / "index.html").write_bytes(HTML_PAGE)
    httpd = ThreadingHTTPServer(("127.0.0.1", 0), functools.partial(_Quiet, directory=str(site)))
    thread = threading.Thread(target=httpd.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{httpd.server_address[1]}"
    finally:
        httpd.shutdown()
        httpd.server_close()
        thread.join(5)


def pmk(capsys: pytest.CaptureFixture[str], maps: Path, *argv: str) -> tuple[int, str, str]:
    code = main(["maps", "--dir", str(maps), *argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_list_empty_folder(capsys: pytest.CaptureFixture[str], maps: Path) -> None:
    maps.mkdir()
    code, out, _ = pmk(capsys, maps, "list")
    assert code == 0
    assert f"maps folder: {maps}" in out
    assert "no maps yet" in out


@pytest.mark.parametrize("action", [["list"], ["delete", "ward"], ["convert", "ward"], ["publish", "--out", "site"]])
def test_a_missing_maps_folder_is_an_error(capsys: pytest.CaptureFixture[str], maps: Path, action: list[str]) -> None:
    """Issue 40, item 3: a mistyped --maps-dir was listed as an empty folder, exit 0."""
    code, out, _ = pmk(capsys, maps, *action, "--json")
    doc = json.loads(out)
    assert code == 2 and doc["ok"] is False and doc["error"] == "MapsFolderMissing"
    assert doc["fields"]["path"] == str(maps)
    assert not maps.exists()  # nothing created on the way


def test_import_creates_a_missing_maps_folder(capsys: pytest.CaptureFixture[str], maps: Path, gml: Path) -> None:
    code, out, _ = pmk(capsys, maps, "import", str(gml), "--json")
    assert code == 0 and json.loads(out)["name"] == "clinic"
    assert (maps / "clinic.gml").is_file()


def test_every_maps_action_answers_json(capsys: pytest.CaptureFixture[str], maps: Path, gml: Path) -> None:
    """Issue 40, item 2: `pmk maps import` and `convert` took no --json (an error, and nothing on stdout)."""
    code, out, _ = pmk(capsys, maps, "import", str(gml), "--name", "ward", "--json")
    imported = json.loads(out)
    assert code == 0 and imported["ok"] is True and imported["action"] == "import"
    assert imported["name"] == "ward" and imported["status"] == "not converted"

    code, out, _ = pmk(capsys, maps, "convert", "ward", "--storey", "F1", "--json")
    converted = json.loads(out)  # stdout is the one document: no progress there
    assert code == 0 and converted["ok"] is True and converted["name"] == "ward"
    assert [m["storey"] for m in converted["maps"]] == ["F1"]
    assert read_map(converted["maps"][0]["yaml"]).width == converted["maps"][0]["width"]

    code, out, _ = pmk(capsys, maps, "import", str(gml), "--name", "ward", "--json")
    refused = json.loads(out)
    assert code == 2 and refused["ok"] is False and refused["command"] == "maps"

    code, out, _ = pmk(capsys, maps, "delete", "ward", "--json")
    assert code == 0 and json.loads(out)["action"] == "delete"


def test_import_list_delete(capsys: pytest.CaptureFixture[str], maps: Path, gml: Path) -> None:
    code, out, _ = pmk(capsys, maps, "import", str(gml), "--name", "ward")
    assert code == 0 and "as map 'ward'" in out
    assert (maps / "ward.gml").read_bytes() == gml.read_bytes()

    code, _, err = pmk(capsys, maps, "import", str(gml), "--name", "ward")
    assert code == 2
    assert err.strip() == "pmk maps: error: map 'ward' already exists. Pass --overwrite to replace it."
    assert pmk(capsys, maps, "import", str(gml), "--name", "ward", "--overwrite")[0] == 0

    code, out, _ = pmk(capsys, maps, "list")
    assert code == 0
    assert f"ward  (ward.gml, {gml.stat().st_size} bytes)  not converted" in out

    code, out, _ = pmk(capsys, maps, "delete", "ward")
    assert code == 0 and "deleted map 'ward'" in out
    assert not (maps / "ward.gml").exists()
    code, _, err = pmk(capsys, maps, "delete", "ward")
    assert code == 2 and "no map named 'ward'" in err


def test_import_refuses_html(capsys: pytest.CaptureFixture[str], maps: Path, tmp_path: Path) -> None:
    page = tmp_path / "page.gml"
    page.write_bytes(HTML_PAGE)
    code, _, err = pmk(capsys, maps, "import", str(page))
    assert code == 2 and "not IndoorGML" in err
    assert not maps.exists() or list(maps.iterdir()) == []


@pytest.mark.slow
def test_download(capsys: pytest.CaptureFixture[str], maps: Path, web: str) -> None:
    code, _, err = pmk(capsys, maps, "download", f"{web}/map.gml", "remote")  # a loopback server: refused
    assert code == 2 and "127.0.0.1 is a loopback address" in err and "--allow-local" in err
    code, out, _ = pmk(capsys, maps, "download", f"{web}/map.gml", "remote", "--allow-local")
    assert code == 0 and "as map 'remote'" in out
    assert (maps / "remote.gml").read_bytes() == two_rooms()

    code, _, err = pmk(capsys, maps, "download", f"{web}/index.html", "page", "--allow-local")
    assert code == 2 and "web page" in err
    code, _, err = pmk(capsys, maps, "download", f"{web}/nothing.gml", "x", "--allow-local")
    assert code == 2 and "HTTP 404" in err
    code, _, err = pmk(capsys, maps, "download", "file:///etc/hostname", "x")
    assert code == 2 and "only http:// and https://" in err
    assert sorted(p.name for p in maps.iterdir()) == ["remote.gml"]


def test_convert_and_list_generated(capsys: pytest.CaptureFixture[str], maps: Path, gml: Path) -> None:
    pmk(capsys, maps, "import", str(gml))
    code, out, _ = pmk(capsys, maps, "convert", "clinic", "-r", "0.1", "--storey", "F2", "--format", "png")
    assert code == 0
    assert "converted map 'clinic' at 0.1 m per cell" in out
    assert "storey F2: clinic_F2.yaml" in out and "clinic_F2.png" in out
    assert read_map(maps / "clinic_F2.yaml").resolution == 0.1
    assert not (maps / "clinic_F1.yaml").exists()

    code, out, _ = pmk(capsys, maps, "list")
    assert "clinic  (clinic.gml" in out and "converted" in out
    assert "storey F2: clinic_F2.yaml" in out and "at 0.1 m" in out

    code, _, err = pmk(capsys, maps, "convert", "clinic", "-r", "0")
    assert code == 2 and "resolution must be a positive number" in err
    code, _, err = pmk(capsys, maps, "convert", "clinic", "--storey", "B9")
    assert code == 2 and "no storey named 'B9'" in err
    code, _, err = pmk(capsys, maps, "convert", "clinic", "-r", "0.00001")
    assert code == 2 and "grid would be" in err
    suggested = float(err.split("Use --resolution ")[1].split()[0])
    assert 0.00001 < suggested < 1


def test_dir_accepted_after_the_action(capsys: pytest.CaptureFixture[str], maps: Path, gml: Path) -> None:
    assert main(["maps", "import", str(gml), "--dir", str(maps)]) == 0
    assert (maps / "clinic.gml").is_file()
    assert main(["maps", "list", "--dir", str(maps)]) == 0
    assert "clinic  (clinic.gml" in capsys.readouterr().out


def test_list_marks_broken_maps(capsys: pytest.CaptureFixture[str], maps: Path, gml: Path) -> None:
    pmk(capsys, maps, "import", str(gml))
    (maps / "clinic_F1.yaml").write_text("resolution: [\n")
    code, out, _ = pmk(capsys, maps, "list")
    assert code == 0
    assert "broken" in out and "clinic_F1.yaml BROKEN (" in out


@pytest.mark.slow
def test_entry_point_runs_as_a_process(maps: Path, gml: Path) -> None:
    env_cmd = [sys.executable, "-m", "pmk_nb.cli", "maps", "--dir", str(maps)]
    done = subprocess.run([*env_cmd, "import", str(gml)], capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    done = subprocess.run([*env_cmd, "import", str(gml)], capture_output=True, text=True, timeout=60)
    assert done.returncode == 2 and "already exists" in done.stderr
