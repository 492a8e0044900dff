"""Catalogue refusals that must not spill over (issue 40, item 8): one bad building hides no clean one, a
refused `get` leaves no empty folder, `publish` after `pmk convert --out` says to import the plan."""

from __future__ import annotations

import json
import shutil
from collections.abc import Iterator
from pathlib import Path

import pytest

from pmk_nb.catalogue.install import install
from pmk_nb.catalogue.publish import PlanMissing, publish
from pmk_nb.catalogue.remote import read_catalogue
from pmk_nb.cli import main
from pmk_nb.errors import AssetMismatch, AssetOutsideCatalogue
from pmk_nb.library import MapsFolder
from tests.stac_site import Site, serve_static

SAMPLE = Path(__file__).resolve().parents[2] / "sample_maps" / "clinic_two_storeys.gml"


@pytest.fixture(scope="module")
def two_buildings(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A site publishing two buildings, clinic and ward (the same plan at 0.2 m)."""
    base = tmp_path_factory.mktemp("two")
    folder = MapsFolder(base / "maps")
    for name in ("clinic", "ward"):
        folder.import_file(SAMPLE, name)
        folder.convert(name, 0.2)
    publish(folder, base / "site", title="Lab maps")
    return base / "site"


@pytest.fixture
def site(two_buildings: Path, tmp_path: Path) -> Iterator[Site]:
    www = tmp_path / "www"
    shutil.copytree(two_buildings, www / "site")
    with serve_static(www) as s:
        s.url += "site/"
        s.root = www / "site"
        yield s


def _maps(maps: Path, capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    code = main(["maps", "--maps-dir", str(maps), *argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_one_bad_building_leaves_the_clean_ones_listed(
    site: Site, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    item = site.root / "ward" / "ward_F1" / "ward_F1.json"
    doc = json.loads(item.read_text())
    doc["assets"]["map-image"]["href"] = "../../../elsewhere.pgm"
    item.write_text(json.dumps(doc))

    catalogue = read_catalogue(site.url, allow_local=True)
    assert [b.id for b in catalogue.buildings] == ["clinic"]
    [refused] = catalogue.refused
    assert refused.id == "ward" and isinstance(refused.error, AssetOutsideCatalogue)
    with pytest.raises(AssetOutsideCatalogue):  # the bad one still cannot be installed
        catalogue.building("ward")

    code, out, _ = _maps(tmp_path / "tablet", capsys, "catalogue", site.url, "--allow-local", "--json")
    doc = json.loads(out)
    assert code == 0 and [b["id"] for b in doc["buildings"]] == ["clinic"]
    assert [(r["id"], r["error"]) for r in doc["refused"]] == [("ward", "AssetOutsideCatalogue")]
    code, out, _ = _maps(tmp_path / "tablet", capsys, "get", site.url, "clinic", "--allow-local")
    assert code == 0 and (tmp_path / "tablet" / "clinic_F1.yaml").is_file()


def test_a_refused_get_leaves_no_empty_folder(site: Site, tmp_path: Path) -> None:
    pgm = site.root / "clinic" / "clinic_F2" / "clinic_F2.pgm"
    data = bytearray(pgm.read_bytes())
    data[-1] ^= 0xFF
    pgm.write_bytes(bytes(data))
    maps = tmp_path / "new" / "tablet"
    with pytest.raises(AssetMismatch):
        install(read_catalogue(site.url, allow_local=True), "clinic", MapsFolder(maps, allow_local=True))
    assert not (tmp_path / "new").exists()


def test_publish_after_pmk_convert_out_says_to_import_the_plan(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    maps, site = tmp_path / "maps", tmp_path / "site"
    assert main(["convert", str(SAMPLE), "-r", "0.2", "--out", str(maps), "--no-progress"]) == 0
    capsys.readouterr()
    code, out, _ = _maps(maps, capsys, "publish", "--out", str(site), "--json")
    doc = json.loads(out)
    assert code == 2 and doc["error"] == "PlanMissing" and "pmk maps import" in doc["hint"]
    assert sorted(doc["fields"]["maps"]) == ["clinic_two_storeys_F1.yaml", "clinic_two_storeys_F2.yaml"]
    with pytest.raises(PlanMissing):
        publish(MapsFolder(maps), site)

    MapsFolder(maps).import_file(SAMPLE)  # the plan joins its maps, by name
    assert publish(MapsFolder(maps), site).buildings == ["clinic_two_storeys"]
