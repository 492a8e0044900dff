"""MapsFolder: names, import, listing (generated / stale / broken / orphan maps), delete, convert."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

from pmk_nb.errors import AlreadyExists, GridTooLarge, IndoorGMLError, LibraryError
from pmk_nb.grid import OccupancyGrid
from pmk_nb.library.folder import MapsFolder, check_name, default_maps_dir
from pmk_nb.progress import Progress
from pmk_nb.rosmap import read_map, write_map
from tests.indoorgml_samples import BROKEN_HTML, ENTITY_BOMB, HTML_PAGE, OTHER_XML, two_rooms


@pytest.fixture
def folder(tmp_path: Path) -> MapsFolder:
    return MapsFolder(tmp_path / "ALMA_MAPS")


@pytest.fixture
def gml(tmp_path: Path) -> Path:
    path = tmp_path / "clinic.gml"
    path.write_bytes(two_rooms())
    return path


def snapshot(root: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in root.iterdir()} if root.exists() else {}


def small_grid(**meta: object) -> OccupancyGrid:
    data = np.zeros((4, 6), dtype=np.int8)
    data[0, :] = 100
    data[3, 5] = -1
    return OccupancyGrid(data=data, resolution=0.5, origin=(1.0, 2.0, 0.0), meta=dict(meta))


# ---------------------------------------------------------------- folder location and names
def test_default_maps_dir_from_env(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    target = tmp_path / "custom" / "maps"
    monkeypatch.setenv("PMK_MAPS_DIR", str(target))
    assert default_maps_dir() == target
    assert target.is_dir()
    assert MapsFolder().root == target


def test_default_maps_dir_is_user_data_alma_maps(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    monkeypatch.delenv("PMK_MAPS_DIR", raising=False)
    monkeypatch.setenv("XDG_DATA_HOME", str(tmp_path / "data"))
    path = default_maps_dir()
    assert path == tmp_path / "data" / "pmk_nb" / "ALMA_MAPS"
    assert path.is_dir()


@pytest.mark.parametrize("name", ["clinic", "Floor 2 - east", "a_b.c", "Zürich-1", "x" * 100])
def test_valid_names(name: str) -> None:
    assert check_name(name) == name


def test_name_suffix_is_dropped() -> None:
    assert check_name("clinic.gml") == "clinic"


@pytest.mark.parametrize(
    ("name", "reason"),
    [
        ("", "required"),
        ("a/b", "path separator"),
        ("..\\x", "path separator"),
        (".hidden", "dot"),
        ("x" * 101, "at most 100"),
        ("a:b", "':'"),
        ("semi;colon", "';'"),
        (" padded", "space"),
    ],
)
def test_invalid_names(name: str, reason: str) -> None:
    with pytest.raises(LibraryError, match="map name") as info:
        check_name(name)
    assert reason in str(info.value)


# ---------------------------------------------------------------- import
def test_import_then_list(folder: MapsFolder, gml: Path) -> None:
    assert folder.list() == []  # the folder does not even exist yet
    entry = folder.import_file(gml)
    assert entry.name == "clinic"
    assert entry.source == folder.root / "clinic.gml"
    assert entry.source.read_bytes() == gml.read_bytes()
    assert entry.size == gml.stat().st_size
    assert entry.status == "not converted"
    assert folder.exists("clinic") and folder.exists("clinic.gml")
    assert [e.name for e in folder.list()] == ["clinic"]


def test_list_sorted_and_accepts_xml(folder: MapsFolder, tmp_path: Path) -> None:
    folder.root.mkdir(parents=True)
    for name in ("zeta.gml", "Alpha.xml", "mid.GML"):
        (folder.root / name).write_bytes(two_rooms())
    (folder.root / "notes.txt").write_text("not a map")
    (folder.root / ".beta.gml.part").write_bytes(b"partial")
    assert [e.name for e in folder.list()] == ["Alpha", "mid", "zeta"]


def test_import_with_name_and_overwrite(folder: MapsFolder, gml: Path, tmp_path: Path) -> None:
    folder.import_file(gml, "ward")
    other = tmp_path / "other.gml"
    other.write_bytes(two_rooms(("F1", "F2")))
    before = snapshot(folder.root)
    with pytest.raises(AlreadyExists, match="map 'ward' already exists; pass overwrite=True to replace it") as exists:
        folder.import_file(other, "ward")
    assert exists.value.name == "ward"
    assert snapshot(folder.root) == before
    entry = folder.import_file(other, "ward", overwrite=True)
    assert entry.source.read_bytes() == other.read_bytes()
    assert sorted(snapshot(folder.root)) == ["ward.gml"]


def test_import_over_hand_placed_xml_replaces_it(folder: MapsFolder, gml: Path) -> None:
    folder.root.mkdir(parents=True)
    (folder.root / "clinic.xml").write_bytes(two_rooms(("F9",)))
    with pytest.raises(LibraryError, match="already exists"):
        folder.import_file(gml)
    folder.import_file(gml, overwrite=True)
    assert sorted(snapshot(folder.root)) == ["clinic.gml"]


@pytest.mark.parametrize(
    ("content", "message"),
    [
        (b"", "empty"),
        (HTML_PAGE, "not IndoorGML.*web page"),
        (BROKEN_HTML, "not a well-formed XML file at line 1"),
        (ENTITY_BOMB, "declares XML entities"),
        (OTHER_XML, r"root element is <\{http://www.opengis.net/kml/2.2\}kml>"),
        (two_rooms()[:-40], "not a well-formed XML"),
    ],
)
def test_import_refuses_non_indoorgml(
    folder: MapsFolder, gml: Path, tmp_path: Path, content: bytes, message: str
) -> None:
    folder.import_file(gml, "keep")
    before = snapshot(folder.root)
    bad = tmp_path / "bad.gml"
    bad.write_bytes(content)
    with pytest.raises(LibraryError, match=message):
        folder.import_file(bad, "keep", overwrite=True)
    assert snapshot(folder.root) == before  # old map untouched, no temp file left


def test_import_missing_file_and_bad_name(folder: MapsFolder, tmp_path: Path, gml: Path) -> None:
    with pytest.raises(LibraryError, match="no such file"):
        folder.import_file(tmp_path / "nope.gml")
    with pytest.raises(LibraryError, match="path separator"):
        folder.import_file(gml, "../escape")
    assert not (tmp_path / "escape.gml").exists()


def test_import_source_is_readable_by_others(folder: MapsFolder, gml: Path) -> None:
    entry = folder.import_file(gml)
    assert entry.source.stat().st_mode & 0o044 == 0o044


# ---------------------------------------------------------------- listing generated maps
def test_list_reports_generated_maps_and_stale(folder: MapsFolder, gml: Path) -> None:
    entry = folder.import_file(gml)
    write_map(
        small_grid(map="clinic", storey="F1", source="clinic.gml", source_sha256=entry.sha256), folder.root, "clinic"
    )
    [e] = folder.list()
    [gm] = e.generated
    assert (gm.storey, gm.yaml.name, gm.image.name) == ("F1", "clinic.yaml", "clinic.pgm")
    assert gm.preview == folder.root / "clinic-visualization.png"
    assert (gm.width, gm.height, gm.resolution) == (6, 4, 0.5)
    assert not gm.stale and gm.ok and e.status == "converted"

    folder.import_file(_changed(gml), "clinic", overwrite=True)
    [e] = folder.list()
    assert e.generated[0].stale and e.status == "stale"


def _changed(gml: Path) -> Path:
    new = gml.with_name("clinic_v2.gml")
    new.write_bytes(two_rooms(width=9.0))
    return new


def test_list_matches_by_naming_and_keeps_orphans(folder: MapsFolder, gml: Path) -> None:
    folder.import_file(gml, "ward")
    folder.import_file(gml, "ward_east")
    write_map(small_grid(), folder.root, "ward_F2")  # no extras: matched by name
    write_map(small_grid(), folder.root, "ward_east_F1")  # longest source name wins
    write_map(small_grid(), folder.root, "hand_made")  # belongs to no source
    entries = {e.name: e for e in folder.list()}
    assert [(g.storey, g.yaml.name) for g in entries["ward"].generated] == [("F2", "ward_F2.yaml")]
    assert [(g.storey, g.yaml.name) for g in entries["ward_east"].generated] == [("F1", "ward_east_F1.yaml")]
    assert [g.yaml.name for g in folder.orphans()] == ["hand_made.yaml"]


def test_corrupt_yaml_is_listed_as_broken(folder: MapsFolder, gml: Path) -> None:
    entry = folder.import_file(gml)
    meta = {"map": "clinic", "source": "clinic.gml", "source_sha256": entry.sha256}
    write_map(small_grid(storey="F1", **meta), folder.root, "clinic_F1")
    write_map(small_grid(storey="F2", **meta), folder.root, "clinic_F2")
    write_map(small_grid(storey="F3", **meta), folder.root, "clinic_F3")
    (folder.root / "clinic_F1.yaml").write_text("image: [unclosed\n")
    (folder.root / "clinic_F3.pgm").unlink()
    [e] = folder.list()
    by_stem = {g.yaml.stem: g for g in e.generated}
    assert "not valid YAML" in by_stem["clinic_F1"].broken
    assert by_stem["clinic_F1"].storey == "F1"  # from the file name
    assert "missing" in by_stem["clinic_F3"].broken
    assert by_stem["clinic_F2"].ok and by_stem["clinic_F2"].width == 6
    assert e.status == "broken"


def test_entry_unknown_names_the_known_maps(folder: MapsFolder, gml: Path) -> None:
    folder.import_file(gml)
    with pytest.raises(LibraryError, match=r"no map named 'ward' in .*\(maps: clinic\)"):
        folder.entry("ward")
    with pytest.raises(LibraryError, match="invalid map name"):
        folder.entry("../clinic")


# ---------------------------------------------------------------- delete
def test_delete_removes_source_and_generated_only(folder: MapsFolder, gml: Path) -> None:
    folder.import_file(gml, "a")
    folder.import_file(gml, "b")
    write_map(small_grid(map="a", storey="F1", source="a.gml"), folder.root, "a")
    write_map(small_grid(map="b", storey="F1", source="b.gml"), folder.root, "b")
    folder.delete("a")
    assert sorted(snapshot(folder.root)) == ["b-visualization.png", "b.gml", "b.pgm", "b.yaml"]
    with pytest.raises(LibraryError, match="no map named 'a'"):
        folder.delete("a")


# ---------------------------------------------------------------- convert (real reader + rasteriser)
def test_convert_one_storey_writes_the_original_file_set(folder: MapsFolder, gml: Path) -> None:
    folder.import_file(gml)
    steps: list[Progress] = []
    [gm] = folder.convert("clinic", 0.05, progress=steps.append)
    assert sorted(snapshot(folder.root)) == [
        "clinic-visualization.png",
        "clinic.gml",
        "clinic.pgm",
        "clinic.rooms.json",
        "clinic.yaml",
    ]
    assert gm.yaml == folder.root / "clinic.yaml" and gm.storey == "F1" and gm.resolution == 0.05
    grid = read_map(gm.yaml)
    assert grid.meta["map"] == "clinic" and grid.meta["source"] == "clinic.gml"
    assert grid.value_at(2.0, 1.5) == 0  # inside room A
    assert (grid.width, grid.height) == (gm.width, gm.height)
    assert steps[-1] == Progress("done", 1.0)
    fractions = [p.fraction for p in steps]
    assert fractions == sorted(fractions)  # type: ignore[type-var]
    order = ["read", "rasterise", "write", "done"]
    assert [p.step for p in steps] == sorted((p.step for p in steps), key=order.index)
    assert folder.list()[0].status == "converted"


def test_convert_multi_storey_then_reconvert_replaces_the_set(folder: MapsFolder, tmp_path: Path) -> None:
    src = tmp_path / "tower.gml"
    src.write_bytes(two_rooms(("F1", "F2", "F3")))
    folder.import_file(src)
    maps = folder.convert("tower", 0.1)
    assert [g.yaml.name for g in maps] == ["tower_F1.yaml", "tower_F2.yaml", "tower_F3.yaml"]
    # only F2, now as PNG: F2's old PGM goes, F1 and F3 are kept as they were
    f1_before = (folder.root / "tower_F1.pgm").read_bytes()
    [f2] = folder.convert("tower", 0.2, storeys=["F2"], image_format="png")
    assert f2.image.name == "tower_F2.png" and not (folder.root / "tower_F2.pgm").exists()
    assert (folder.root / "tower_F1.pgm").read_bytes() == f1_before
    # the source loses F3: a new conversion removes the F3 files after writing the new set
    src.write_bytes(two_rooms(("F1", "F2")))
    folder.import_file(src, overwrite=True)
    assert {g.storey for g in folder.entry("tower").generated if g.stale} == {"F1", "F2", "F3"}
    folder.convert("tower", 0.1)
    assert sorted(p for p in snapshot(folder.root) if "F3" in p) == []
    assert [g.storey for g in folder.entry("tower").generated] == ["F1", "F2"]
    assert folder.entry("tower").status == "converted"
    assert not [p for p in folder.root.iterdir() if p.name.startswith(".")]  # no staging left


def test_convert_errors_are_library_errors_and_leave_files(folder: MapsFolder, gml: Path) -> None:
    folder.import_file(gml)
    folder.convert("clinic", 0.05)
    before = snapshot(folder.root)
    with pytest.raises(LibraryError, match="no storey named 'F7'") as info:
        folder.convert("clinic", 0.05, storeys=["F7"])
    assert isinstance(info.value.__cause__, IndoorGMLError)
    with pytest.raises(LibraryError, match="cannot convert map 'clinic'") as info:
        folder.convert("clinic", 1e-5)  # far too many cells
    assert isinstance(info.value.__cause__, GridTooLarge) and info.value.name == "clinic"
    assert info.value.__cause__.suggested_resolution > 1e-5
    with pytest.raises(LibraryError, match="positive"):
        folder.convert("clinic", -1.0)
    with pytest.raises(LibraryError, match="'pgm' or 'png'"):
        folder.convert("clinic", 0.05, image_format="jpg")
    with pytest.raises(LibraryError, match="max wall gap"):
        folder.convert("clinic", 0.05, max_wall_gap=-0.2)
    assert snapshot(folder.root) == before


def test_convert_passes_max_wall_gap(folder: MapsFolder, tmp_path: Path) -> None:
    src = Path(__file__).resolve().parents[2] / "sample_maps" / "clinic_floor.gml"
    folder.import_file(src, "alma")
    [gm] = folder.convert("alma", 0.1)
    assert read_map(gm.yaml).value_at(12.0, 6.0) == 100  # the wall the file leaves out as a gap
    [gm] = folder.convert("alma", 0.1, max_wall_gap=0.0)
    assert read_map(gm.yaml).value_at(12.0, 6.0) == -1


def test_convert_of_invalid_building_chains_reader_error(folder: MapsFolder) -> None:
    folder.root.mkdir(parents=True)
    empty = folder.root / "empty.gml"
    empty.write_bytes(b'<IndoorFeatures xmlns="http://www.opengis.net/indoorgml/1.0/core"/>')
    with pytest.raises(LibraryError, match="cannot convert map 'empty'") as info:
        folder.convert("empty", 0.05)
    assert isinstance(info.value.__cause__, IndoorGMLError)
    assert str(info.value.__cause__) in str(info.value)
    assert sorted(os.listdir(folder.root)) == ["empty.gml"]


def test_storey_file_names_are_safe_and_unique() -> None:
    from pmk_nb.library.naming import storey_map_names as storey_file_stem

    assert storey_file_stem("clinic", ["0"]) == {"0": "clinic"}
    stems = storey_file_stem("c", ["F1", "F 1", "a/b", "2-3", "../x"])
    assert stems == {"F1": "c_F1", "F 1": "c_F_1", "a/b": "c_a_b", "2-3": "c_2-3", "../x": "c_x"}
    assert len(set(storey_file_stem("c", ["F_1", "F 1", "F/1"]).values())) == 3


def test_hand_placed_maps_matched_by_name_are_never_deleted(folder: MapsFolder, gml: Path) -> None:
    folder.import_file(gml)
    write_map(small_grid(), folder.root, "clinic_backup")  # no extras: matched by name only
    folder.convert("clinic", 0.1)
    assert (folder.root / "clinic_backup.yaml").is_file()
    assert [g.yaml.name for g in folder.entry("clinic").generated] == ["clinic.yaml", "clinic_backup.yaml"]
    folder.delete("clinic")
    assert sorted(snapshot(folder.root)) == [
        "clinic_backup-visualization.png",
        "clinic_backup.pgm",
        "clinic_backup.yaml",
    ]
    assert [g.yaml.name for g in folder.orphans()] == ["clinic_backup.yaml"]
