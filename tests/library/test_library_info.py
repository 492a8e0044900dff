"""MapsFolder.storeys: storeys known before conversion, cached per source file (path + mtime + size)."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from pmk_nb.errors import LibraryError
from pmk_nb.indoorgml import read_building, summarize
from pmk_nb.library.folder import MapsFolder
from pmk_nb.library.info import StoreyInfo
from tests.indoorgml_samples import HTML_PAGE, two_rooms

SAMPLES = Path(__file__).resolve().parents[2] / "sample_maps"


@pytest.fixture
def folder(tmp_path: Path) -> MapsFolder:
    maps = MapsFolder(tmp_path / "ALMA_MAPS")
    for name in ("clinic_floor", "clinic_two_storeys"):
        maps.import_file(SAMPLES / f"{name}.gml")
    return maps


@pytest.mark.parametrize("name", ["clinic_floor", "clinic_two_storeys"])
def test_storeys_of_the_clinic_samples_before_conversion(folder: MapsFolder, name: str) -> None:
    assert folder.entry(name).status == "not converted"
    storeys = folder.storeys(name)
    expected = summarize(read_building(SAMPLES / f"{name}.gml"))["storeys"]
    assert [s.name for s in storeys] == [e["name"] for e in expected]
    assert [(s.cells, s.doors) for s in storeys] == [(e["cells"], e["doors"]) for e in expected]
    for s, e in zip(storeys, expected, strict=True):
        assert s.extent == (*e["extent"]["min"], *e["extent"]["max"])
        assert s.size == tuple(e["extent"]["size"])
        assert s.cells > 0 and s.doors > 0
    assert len(storeys) == (2 if name == "clinic_two_storeys" else 1)
    assert not list(folder.root.glob("*.yaml"))  # reading storeys converts nothing


def test_two_storey_names_and_description(folder: MapsFolder) -> None:
    f1, f2 = folder.storeys("clinic_two_storeys")
    assert (f1.name, f2.name) == ("F1", "F2")
    assert f1.describe().startswith("F1: 15 cells, 6 doors, 30.0 × 15.0 m")


def test_second_call_is_a_cache_hit(folder: MapsFolder) -> None:
    assert folder.cached_storeys("clinic_two_storeys") is None
    first = folder.storeys("clinic_two_storeys")
    assert folder.storey_reads == 1
    assert folder.storeys("clinic_two_storeys") == first
    assert folder.cached_storeys("clinic_two_storeys") == first
    assert folder.storey_reads == 1  # not read again
    folder.storeys("clinic_floor")
    assert folder.storey_reads == 2  # each source is its own cache entry
    # the cache belongs to the instance, not the module
    other = MapsFolder(folder.root)
    assert other.cached_storeys("clinic_two_storeys") is None


def test_cache_is_invalidated_when_the_file_changes(folder: MapsFolder) -> None:
    source = folder.entry("clinic_two_storeys").source
    assert len(folder.storeys("clinic_two_storeys")) == 2
    st = source.stat()
    os.utime(source, ns=(st.st_atime_ns, st.st_mtime_ns + 1_000_000_000))  # same bytes, new mtime
    assert folder.cached_storeys("clinic_two_storeys") is None
    assert len(folder.storeys("clinic_two_storeys")) == 2
    assert folder.storey_reads == 2
    folder.import_file(
        _write(folder.root.parent / "three.gml", two_rooms(("A", "B", "C"))), name="clinic_two_storeys", overwrite=True
    )
    assert [s.name for s in folder.storeys("clinic_two_storeys")] == ["A", "B", "C"]
    assert folder.storey_reads == 3


def test_convert_fills_the_cache(folder: MapsFolder) -> None:
    folder.convert("clinic_two_storeys", 0.2)
    assert folder.storey_reads == 0
    assert [s.name for s in folder.cached_storeys("clinic_two_storeys") or []] == ["F1", "F2"]
    assert [s.name for s in folder.storeys("clinic_two_storeys")] == ["F1", "F2"]
    assert folder.storey_reads == 0


def test_bad_file_is_a_library_error(folder: MapsFolder) -> None:
    (folder.root / "broken.gml").write_bytes(HTML_PAGE)  # dropped in by hand, never checked
    with pytest.raises(LibraryError, match=r"storeys of map 'broken' \(broken\.gml\)"):
        folder.storeys("broken")
    assert folder.cached_storeys("broken") is None
    truncated = (SAMPLES / "clinic_two_storeys.gml").read_bytes()[:2000]
    (folder.root / "cut.gml").write_bytes(truncated)
    with pytest.raises(LibraryError, match=r"cut\.gml"):
        folder.storeys("cut")
    with pytest.raises(LibraryError, match="no map named 'nope'"):
        folder.storeys("nope")


def test_deleted_map_is_forgotten(folder: MapsFolder) -> None:
    folder.storeys("clinic_floor")
    folder.delete("clinic_floor")
    assert folder.cached_storeys("clinic_floor") is None
    with pytest.raises(LibraryError, match="no map named 'clinic_floor'"):
        folder.storeys("clinic_floor")


def test_storey_without_cells_has_no_extent() -> None:
    empty = StoreyInfo(name="roof", cells=0, doors=0, extent=None)
    assert empty.size is None and "no extent" in empty.describe()


def _write(path: Path, data: bytes) -> Path:
    path.write_bytes(data)
    return path
