"""Map catalogues (issue 27): publish a maps folder as STAC, serve it from a real static web server
(ETag, Range), validate it with stac-validator, read it back with pystac, list it and install from it.

Every refusal (tampered file, link out of the catalogue, redirect to another scheme, file over the
cap) must exit 2, raise its typed error and leave the maps folder exactly as it was.
"""

from __future__ import annotations

import datetime as dt
import json
import shutil
import urllib.error
import urllib.request
import warnings
from collections.abc import Iterator
from pathlib import Path

import pystac
import pytest

from pmk_nb.catalogue import geo
from pmk_nb.catalogue.hashes import file_sha256, multihash
from pmk_nb.catalogue.install import install
from pmk_nb.catalogue.publish import publish
from pmk_nb.catalogue.remote import read_catalogue
from pmk_nb.cli import main
from pmk_nb.errors import AssetMismatch, AssetOutsideCatalogue, AssetTooLarge, RedirectRefused
from pmk_nb.library import MapsFolder
from tests.stac_site import Site, schema_map, serve_static

SAMPLE = Path(__file__).resolve().parents[2] / "sample_maps" / "clinic_two_storeys.gml"


@pytest.fixture(scope="module")
def published(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A maps folder with the two-storey clinic converted at 0.1 m, published once (shared, read-only)."""
    base = tmp_path_factory.mktemp("catalogue")
    folder = MapsFolder(base / "maps")
    folder.import_file(SAMPLE, "clinic")
    folder.convert("clinic", 0.1)
    publish(folder, base / "site", title="Lab maps")
    return base


@pytest.fixture
def site(published: Path, tmp_path: Path) -> Iterator[Site]:
    """A private copy of the published site, served at /site/ (tests tamper with it; beside it lies
    what a catalogue must not reach)."""
    www = tmp_path / "www"
    shutil.copytree(published / "site", www / "site")
    with serve_static(www) as s:
        s.url += "site/"
        s.root = www / "site"
        yield s


def _files(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir())} if folder.exists() else {}


def _pmk(capsys: pytest.CaptureFixture[str], maps: Path, *argv: str) -> tuple[int, str, str]:
    code = main(["maps", "--dir", str(maps), *argv])
    out, err = capsys.readouterr()
    return code, out, err


@pytest.mark.slow
def test_published_catalogue_is_valid_stac_and_pystac_reads_it_back(site: Site, tmp_path: Path) -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        from stac_validator.validate import StacValidate

    smap = schema_map(tmp_path)
    validator = StacValidate(site.url + "catalog.json", recursive=True, schema_map=smap)
    assert validator.run(), validator.message
    kinds = sorted(m["asset_type"] for m in validator.message)
    assert kinds == ["CATALOG", "COLLECTION", "ITEM", "ITEM"], validator.message
    # the validator is not vacuous: an Item without its datetime fails it
    item_path = site.root / "clinic" / "clinic_F1" / "clinic_F1.json"
    doc = json.loads(item_path.read_text())
    del doc["properties"]["datetime"]
    broken = tmp_path / "broken.json"
    broken.write_text(json.dumps(doc))
    assert not StacValidate(str(broken), schema_map=smap).run()

    catalog = pystac.Catalog.from_file(site.url + "catalog.json")
    assert catalog.title == "Lab maps"
    (collection,) = list(catalog.get_children())
    assert isinstance(collection, pystac.Collection) and collection.id == "clinic"
    items = sorted(collection.get_items(), key=lambda i: i.id)
    assert [i.id for i in items] == ["clinic_F1", "clinic_F2"]
    for item in items:
        assert item.geometry is None  # the sample plan has no CRS
        assert set(item.assets) == {"indoorgml", "map-yaml", "map-image", "rooms", "preview", "thumbnail"}
        assert item.properties["pmk:resolution"] == 0.1 and item.properties["pmk:storey"] in ("F1", "F2")
        for asset in item.assets.values():
            local = site.root / "clinic" / item.id / asset.href.split("/")[-1]
            local = local if local.exists() else site.root / "clinic" / "clinic.gml"
            assert asset.extra_fields["file:size"] == local.stat().st_size
            assert asset.extra_fields["file:checksum"] == multihash(file_sha256(local))
    # every link and asset href in every document is relative: the folder can be copied anywhere
    for path in site.root.rglob("*.json"):
        if path.name.endswith(".rooms.json"):
            continue
        doc = json.loads(path.read_text())
        hrefs = [lk["href"] for lk in doc["links"]] + [a["href"] for a in doc.get("assets", {}).values()]
        assert all(h.startswith(("./", "../")) for h in hrefs), (path, hrefs)


def test_publish_again_rewrites_only_what_changed(tmp_path: Path) -> None:
    folder = MapsFolder(tmp_path / "maps")
    folder.import_file(SAMPLE, "clinic")
    folder.convert("clinic", 0.1)
    out = tmp_path / "site"
    t0, t1 = dt.datetime(2026, 1, 1, tzinfo=dt.UTC), dt.datetime(2026, 2, 1, tzinfo=dt.UTC)
    first = publish(folder, out, now=t0)
    assert len(first.written) == 15 and first.unchanged == 0  # catalog, collection, source + 2 x (5 files + item)
    again = publish(folder, out, now=t1)
    assert again.written == [] and again.unchanged == 15
    f1_before = (out / "clinic" / "clinic_F1" / "clinic_F1.json").read_bytes()
    rooms = tmp_path / "maps" / "clinic_F2.rooms.json"
    rooms.write_text(rooms.read_text().replace('"Corridor"', '"Main corridor"', 1))
    third = publish(folder, out, now=t1)
    names = sorted(p.relative_to(out).as_posix() for p in third.written)
    f2_files = ["clinic/clinic_F2/clinic_F2.json", "clinic/clinic_F2/clinic_F2.rooms.json"]
    assert names == [*f2_files, "clinic/collection.json"]
    assert (out / "clinic" / "clinic_F1" / "clinic_F1.json").read_bytes() == f1_before  # F1 keeps its date
    f2 = json.loads((out / "clinic" / "clinic_F2" / "clinic_F2.json").read_text())
    assert f2["properties"]["updated"] == "2026-02-01T00:00:00Z"
    assert f2["properties"]["created"] == "2026-01-01T00:00:00Z"


def test_list_and_get_install_every_file_byte_for_byte(
    site: Site, published: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    maps = tmp_path / "tablet"
    code, out, err = _pmk(capsys, maps, "catalogue", site.url, "--allow-local", "--json")
    assert code == 0, err
    listing = json.loads(out)
    (b,) = listing["buildings"]
    assert b["id"] == "clinic" and b["status"] == "new"
    assert [(s["storey"], s["resolution"], s["width"], s["height"]) for s in b["storeys"]] == [
        ("F1", 0.1, 304, 154),
        ("F2", 0.1, 304, 154),
    ]
    assert b["size"] > 100_000 and b["updated"].endswith("Z")

    code, out, err = _pmk(capsys, maps, "get", site.url + "catalog.json", "clinic", "--allow-local")
    assert code == 0, err
    source = _files(published / "maps")
    installed = _files(maps)
    assert installed.pop(".catalogue-installs.json")
    assert installed == source  # byte for byte: source, YAMLs, images, rooms files, previews
    assert any(r[2] == 200 for r in site.requests)
    # the server is a real static host: ranges and entity tags, as nginx or an object store serve them
    pgm = site.url + "clinic/clinic_F1/clinic_F1.pgm"
    with urllib.request.urlopen(urllib.request.Request(pgm, headers={"Range": "bytes=10-19"})) as resp:
        assert resp.status == 206 and resp.read() == source["clinic_F1.pgm"][10:20]
        etag = resp.headers["ETag"]
    with pytest.raises(urllib.error.HTTPError) as not_modified:
        urllib.request.urlopen(urllib.request.Request(pgm, headers={"If-None-Match": etag}))
    assert not_modified.value.code == 304

    code, out, err = _pmk(capsys, maps, "catalogue", site.url, "--allow-local")
    assert code == 0 and "clinic  2 storey(s)" in out and "[installed]" in out
    assert "storey F2: clinic_F2 304x154 cells at 0.1 m" in out
    rooms = site.root / "clinic" / "clinic_F2" / "clinic_F2.rooms.json"  # the lab publishes a new rooms file
    rooms.write_bytes(rooms.read_bytes().replace(b'"Corridor"', b'"Main corridor"', 1))
    item = site.root / "clinic" / "clinic_F2" / "clinic_F2.json"
    doc = json.loads(item.read_text())
    doc["assets"]["rooms"].update({"file:size": rooms.stat().st_size, "file:checksum": multihash(file_sha256(rooms))})
    item.write_text(json.dumps(doc))
    code, out, err = _pmk(capsys, maps, "catalogue", site.url, "--allow-local")
    assert code == 0 and "[changed]" in out, (out, err)
    code, out, err = _pmk(capsys, maps, "get", site.url, "clinic", "--allow-local")
    assert code == 0 and (maps / "clinic_F2.rooms.json").read_bytes() == rooms.read_bytes()
    assert "[installed]" in _pmk(capsys, maps, "catalogue", site.url, "--allow-local")[1]

    collection = site.root / "clinic" / "collection.json"  # the lab drops storey F2
    doc = json.loads(collection.read_text())
    doc["links"] = [lk for lk in doc["links"] if "clinic_F2" not in lk["href"]]
    collection.write_text(json.dumps(doc))
    code, out, err = _pmk(capsys, maps, "get", site.url, "clinic", "--allow-local")
    assert code == 0, err
    assert sorted(p.name for p in maps.iterdir() if "F2" in p.name) == []  # gone with it, F1 and the source stay
    assert (maps / "clinic_F1.yaml").is_file() and (maps / "clinic.gml").is_file()
    shutil.copy(published / "site" / "clinic" / "collection.json", collection)

    one = tmp_path / "one"
    code, out, err = _pmk(capsys, one, "get", site.url, "clinic", "--storey", "F2", "--allow-local")
    assert code == 0, err
    assert sorted(p.name for p in one.iterdir() if not p.name.startswith(".")) == [
        "clinic.gml",
        "clinic_F2-visualization.png",
        "clinic_F2.pgm",
        "clinic_F2.rooms.json",
        "clinic_F2.yaml",
    ]
    assert "[installed]" in _pmk(capsys, one, "catalogue", site.url, "--allow-local")[1]  # what it has is current
    code, out, err = _pmk(capsys, one, "get", site.url, "clinic", "--storey", "F1", "--allow-local")
    assert code == 0 and (one / "clinic_F1.yaml").is_file() and (one / "clinic_F2.yaml").is_file()
    record = json.loads((one / ".catalogue-installs.json").read_text())["installs"]["clinic"]
    assert {"clinic_F1.yaml", "clinic_F2.yaml", "clinic.gml"} <= set(record["files"])


def _refused(site: Site, maps: Path, capsys: pytest.CaptureFixture[str], *extra: str) -> str:
    """``pmk maps get`` must exit 2 and leave ``maps`` exactly as it was."""
    before = _files(maps)
    code, out, err = _pmk(capsys, maps, "get", site.url, "clinic", "--allow-local", "--overwrite", *extra)
    assert code == 2, (out, err)
    assert _files(maps) == before, "a refused install changed the maps folder"
    staging = [p for p in maps.iterdir() if p.is_dir()] if maps.exists() else []
    assert not staging, f"staging folders left behind: {staging}"
    return err


def test_tampered_file_is_refused_and_nothing_installed(
    site: Site, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    maps = tmp_path / "tablet"
    maps.mkdir()
    (maps / "clinic.gml").write_bytes(b"an older map the user keeps")
    pgm = site.root / "clinic" / "clinic_F2" / "clinic_F2.pgm"
    data = bytearray(pgm.read_bytes())
    data[-1] ^= 0xFF  # same size, one byte changed
    pgm.write_bytes(bytes(data))
    assert "differs from the catalogue" in _refused(site, maps, capsys)
    catalogue = read_catalogue(site.url, allow_local=True)
    with pytest.raises(AssetMismatch) as caught:
        install(catalogue, "clinic", MapsFolder(maps, allow_local=True), overwrite=True)
    assert caught.value.field == "checksum" and caught.value.asset == "map-image"
    pgm.write_bytes(bytes(data) + b"more")  # longer than declared: cut off at the declared size
    with pytest.raises(AssetMismatch) as caught:
        install(catalogue, "clinic", MapsFolder(maps, allow_local=True), overwrite=True)
    assert caught.value.field == "size" and caught.value.expected == len(data)


@pytest.mark.parametrize(
    "href", ["../../../outside.gml", "/clinic/clinic.gml", "http://example.org/clinic.gml", "%2e%2e/%2e%2e/../x.gml"]
)
def test_asset_outside_the_catalogue_is_refused(
    site: Site, tmp_path: Path, capsys: pytest.CaptureFixture[str], href: str
) -> None:
    (site.root.parent / "outside.gml").write_bytes(SAMPLE.read_bytes())  # reachable over HTTP, not in the catalogue
    item = site.root / "clinic" / "clinic_F1" / "clinic_F1.json"
    doc = json.loads(item.read_text())
    doc["assets"]["indoorgml"]["href"] = href
    item.write_text(json.dumps(doc))
    maps = tmp_path / "tablet"
    err = _refused(site, maps, capsys)
    assert "leaves the catalogue's folder" in err
    with pytest.raises(AssetOutsideCatalogue) as caught:
        read_catalogue(site.url, allow_local=True).building("clinic")
    assert caught.value.href == href and caught.value.root == site.url


def test_redirect_to_another_scheme_or_place_is_refused(
    site: Site, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    https = site.url.replace("http://", "https://") + "clinic/clinic_F1/clinic_F1.pgm"
    site.redirects["/site/clinic/clinic_F1/clinic_F1.pgm"] = https
    maps = tmp_path / "tablet"
    assert "redirects to" in _refused(site, maps, capsys)
    catalogue = read_catalogue(site.url, allow_local=True)
    with pytest.raises(RedirectRefused) as caught:
        install(catalogue, "clinic", MapsFolder(maps, allow_local=True))
    assert caught.value.target == https
    # same scheme, out of the folder
    site.redirects["/site/clinic/clinic_F1/clinic_F1.pgm"] = "/elsewhere/clinic_F1.pgm"
    (site.root.parent / "elsewhere").mkdir()
    shutil.copy(site.root / "clinic" / "clinic_F1" / "clinic_F1.pgm", site.root.parent / "elsewhere")
    with pytest.raises(RedirectRefused):
        install(catalogue, "clinic", MapsFolder(maps, allow_local=True))
    assert not maps.exists() or _files(maps) == {}


def test_file_over_the_size_cap_is_refused(site: Site, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    maps = tmp_path / "tablet"
    assert "more than the limit" in _refused(site, maps, capsys, "--max-mb", "0.03")
    catalogue = read_catalogue(site.url, allow_local=True)
    with pytest.raises(AssetTooLarge) as caught:
        install(catalogue, "clinic", MapsFolder(maps, allow_local=True), max_bytes=30_000)
    assert caught.value.asset in ("indoorgml", "map-image") and caught.value.size > caught.value.limit == 30_000
    assert not any(r[0].endswith((".pgm", ".gml")) for r in site.requests), "downloaded before checking the cap"


def test_georeferenced_plan_gets_a_footprint(tmp_path: Path) -> None:
    lon, lat = geo.utm_to_lonlat(500_000.0, 0.9996 * 4_984_944.378, 33, True)  # meridian arc to 45 N, WGS 84
    assert lon == pytest.approx(15.0, abs=1e-9) and lat == pytest.approx(45.0, abs=1e-6)
    lon, lat = geo.utm_to_lonlat(500_000.0, 10_000_000.0 - 0.9996 * 4_984_944.378, 33, False)
    assert lat == pytest.approx(-45.0, abs=1e-6)
    assert geo.utm_zone("urn:ogc:def:crs:EPSG::25832") == (32, True) and geo.utm_zone("EPSG:3857") is None
    plan = tmp_path / "geo.gml"
    plan.write_text(SAMPLE.read_text().replace("<gml:Polygon", '<gml:Polygon srsName="EPSG:32632"', 1))
    folder = MapsFolder(tmp_path / "maps")
    folder.import_file(plan, "geo")
    folder.convert("geo", 0.1, unit="cm")
    publish(folder, tmp_path / "site")
    item = json.loads((tmp_path / "site" / "geo" / "geo_F1" / "geo_F1.json").read_text())
    assert item["geometry"]["type"] == "Polygon" and len(item["bbox"]) == 4
    west, south, east, north = item["bbox"]
    assert -180 <= west < east <= 180 and -90 <= south < north <= 90
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        from stac_validator.validate import StacValidate
    item_file = tmp_path / "site" / "geo" / "geo_F1" / "geo_F1.json"
    assert StacValidate(str(item_file), schema_map=schema_map(tmp_path)).run()


def test_catalogue_tab_adds_a_url_searches_and_gets_a_building(site: Site, tmp_path: Path) -> None:
    """The Catalogue tab's kernel side: the URL kept in settings, statuses, search, Get, refusals shown."""
    from pmk_nb.ui.maps.catalogue import CataloguePanel
    from tests.helpers import app_context

    with app_context(tmp_path) as ctx:
        ctx.maps.allow_local = True
        panel = CataloguePanel(ctx, on_installed=lambda _r: None)
        panel.url.value = "ftp://nowhere/catalog.json"
        assert panel.add() is None and "http://" in panel.error.value
        panel.url.value = site.url
        panel.add().join(30)
        assert json.loads((tmp_path / "cfg" / "catalogues.json").read_text()) == {"catalogues": [site.url]}
        assert panel.catalogue is not None and panel.thumbnails["clinic"].startswith(b"\x89PNG")
        assert panel.statuses() == {"clinic": "new"} and len(panel.results.children) == 1
        panel.search.value = "nothing like it"
        assert "No building matches" in panel.results.children[0].value
        panel.search.value = "CLIN"
        assert len(panel.results.children) == 1
        panel.source.value = site.url
        assert panel.get("../etc") is None  # a page can send any name: only the catalogue's buildings
        panel.get("clinic").join(60)
        assert "Installed clinic" in panel.status.value and panel.statuses() == {"clinic": "installed"}
        assert ctx.maps.entry("clinic").status == "converted"
        (site.root / "clinic" / "clinic_F1" / "clinic_F1.rooms.json").write_bytes(b"{}")  # tampered on the server
        panel.get("clinic").join(60)
        assert "differs from the catalogue" in panel.status.value
        panel.remove()
        assert panel.sources.urls() == [] and panel.results.children == ()


def test_publish_keeps_named_buildings_drops_deleted_ones_and_encodes_spaces(tmp_path: Path) -> None:
    from tests.indoorgml_samples import two_rooms

    plan = tmp_path / "wing.gml"
    plan.write_bytes(two_rooms())
    folder = MapsFolder(tmp_path / "maps", allow_local=True)
    folder.convert(folder.import_file(plan, "east wing").name, 0.1)
    folder.import_file(SAMPLE, "clinic")
    folder.convert("clinic", 0.2)
    www = tmp_path / "www"
    publish(folder, www / "site")
    catalog = json.loads((www / "site" / "catalog.json").read_text())
    assert [lk["href"] for lk in catalog["links"] if lk["rel"] == "child"] == [
        "./clinic/collection.json",
        "./east%20wing/collection.json",
    ]
    with serve_static(www) as s:
        catalogue = read_catalogue(s.url + "site/", allow_local=True)
        assert [b.id for b in catalogue.buildings] == ["clinic", "east wing"]
        tablet = MapsFolder(tmp_path / "tablet", allow_local=True)
        result = install(catalogue, "east wing", tablet)
        assert sorted(result.files) == sorted(p.name for p in folder.root.iterdir() if p.name.startswith("east"))
        assert tablet.entry("east wing").status == "converted"
    folder.delete("east wing")
    kept = publish(folder, www / "site", ["clinic"])  # named: the others stay listed
    assert kept.removed == [] and (www / "site" / "east wing" / "collection.json").is_file()
    everything = publish(folder, www / "site")  # all: a building gone from the maps folder goes
    assert everything.removed == [www / "site" / "east wing"] and not (www / "site" / "east wing").exists()
    (www / "site" / "other").mkdir()  # a folder publish did not make is never deleted
    (www / "site" / "other" / "collection.json").write_text('{"type": "Collection", "assets": {}}')
    doc = json.loads((www / "site" / "catalog.json").read_text())
    doc["links"].append({"rel": "child", "href": "./other/collection.json"})
    (www / "site" / "catalog.json").write_text(json.dumps(doc))
    assert publish(folder, www / "site").removed == [] and (www / "site" / "other").is_dir()


def test_an_asset_on_another_host_needs_allow_host(
    site: Site, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    mirror = tmp_path / "mirror"
    mirror.mkdir()
    pgm = site.root / "clinic" / "clinic_F1" / "clinic_F1.pgm"
    shutil.copy(pgm, mirror)
    with serve_static(mirror) as other:
        host = other.url.split("/")[2]  # 127.0.0.1:PORT: another host than the catalogue's
        item = site.root / "clinic" / "clinic_F1" / "clinic_F1.json"
        doc = json.loads(item.read_text())
        doc["assets"]["map-image"]["href"] = other.url + "clinic_F1.pgm"
        item.write_text(json.dumps(doc))
        maps = tmp_path / "tablet"
        assert "leaves the catalogue's folder" in _refused(site, maps, capsys)
        code, _out, err = _pmk(capsys, maps, "get", site.url, "clinic", "--allow-local", "--allow-host", host)
        assert code == 0, err
        assert (maps / "clinic_F1.pgm").read_bytes() == pgm.read_bytes()
        assert [r[0] for r in other.requests] == ["/clinic_F1.pgm"]


def test_pmk_maps_publish_prints_what_it_wrote_and_refuses_an_unconverted_map(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    maps, site = tmp_path / "maps", tmp_path / "site"
    MapsFolder(maps).import_file(SAMPLE, "clinic")
    code, out, err = _pmk(capsys, maps, "publish", "--out", str(site))
    assert code == 2 and "nothing to publish" in err and not site.exists()
    code, out, err = _pmk(capsys, maps, "publish", "clinic", "--out", str(site))
    assert code == 2 and "not converted yet" in err and "pmk maps convert clinic" in err
    MapsFolder(maps).convert("clinic", 0.2)
    code, out, err = _pmk(capsys, maps, "publish", "--out", str(site), "--title", "Ward 3")
    assert code == 0, err
    assert "published clinic" in out and "15 file(s) written, 0 unchanged" in out
    assert "wrote clinic/collection.json" in out
    assert json.loads((site / "catalog.json").read_text())["title"] == "Ward 3"
    code, out, err = _pmk(capsys, maps, "publish", "--out", str(site))
    assert code == 0 and "0 file(s) written, 15 unchanged" in out
    assert json.loads((site / "catalog.json").read_text())["title"] == "Ward 3"  # kept when not given


def test_a_plan_read_from_a_local_origin_is_placed_where_it_stands(tmp_path: Path) -> None:
    """Issue 37 item 4: UTM coordinates are read from a local origin; the footprint adds it back. The
    plan's corner is 15 E 45 N (on zone 33's meridian); 44 x 91 m reach 0.00056 E and 0.00082 N."""
    from tests.indoorgml.test_crs import _plan

    plan = _plan(tmp_path, "1.0.3-cellSpaceGeometry", (500_000.0, 0.9996 * 4_984_944.378), "EPSG:32633")
    folder = MapsFolder(tmp_path / "maps")
    folder.import_file(plan, "utm")
    folder.convert("utm", 0.1)
    publish(folder, tmp_path / "site")
    item_file = tmp_path / "site" / "utm" / "utm" / "utm.json"
    west, south, east, north = json.loads(item_file.read_text())["bbox"]
    assert (west, south) == (pytest.approx(15.0, abs=1e-7), pytest.approx(45.0, abs=1e-7))
    assert (east - west, north - south) == (pytest.approx(0.00056, abs=1e-5), pytest.approx(0.00082, abs=1e-5))
