"""The one convert pipeline: `pmk convert`, the maps folder (Maps screen) and convert_plan make the same
files, report progress in one shape and leave the output folder as it was when anything fails."""

from __future__ import annotations

from pathlib import Path

import pytest

from pmk_nb.cli import main
from pmk_nb.errors import GridTooLarge, MapFormatError
from pmk_nb.library.convert import ConvertOptions, convert_plan
from pmk_nb.library.folder import MapsFolder
from pmk_nb.progress import Progress
from tests.indoorgml_samples import two_rooms


@pytest.fixture
def tower(tmp_path: Path) -> Path:
    src = tmp_path / "src" / "tower.gml"
    src.parent.mkdir()
    src.write_bytes(two_rooms(("F1", "F2")))
    return src


def snapshot(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir())}


def test_cli_and_maps_folder_write_the_same_maps(tower: Path, tmp_path: Path) -> None:
    cli_out = tmp_path / "cli"
    assert main(["convert", str(tower), "-r", "0.1", "--out", str(cli_out), "--no-progress"]) == 0
    folder = MapsFolder(tmp_path / "maps")
    folder.import_file(tower)
    maps = folder.convert("tower", 0.1)
    assert sorted(g.yaml.name for g in maps) == ["tower_F1.yaml", "tower_F2.yaml"]
    for gm in maps:
        assert gm.image.read_bytes() == (cli_out / gm.image.name).read_bytes()
        assert gm.preview is not None and gm.preview.read_bytes() == (cli_out / gm.preview.name).read_bytes()


def test_progress_is_one_shape_in_order(tower: Path, tmp_path: Path) -> None:
    seen: list[Progress] = []
    result = convert_plan(tower, tmp_path / "out", "tower", 0.1, progress=seen.append)
    assert all(isinstance(p, Progress) for p in seen)
    steps = list(dict.fromkeys(p.step for p in seen))
    assert steps == ["read", "rasterise", "write", "done"]
    fractions = [p.fraction for p in seen]
    assert fractions == sorted(fractions) and fractions[-1] == 1.0  # type: ignore[type-var]
    assert {p.message for p in seen if p.step == "rasterise"} >= {"storey F1", "storey F2"}
    assert [m.storey for m in result.maps] == ["F1", "F2"]
    assert result.stems == {"F1": "tower_F1", "F2": "tower_F2"}


def test_a_failed_write_leaves_the_folder_as_it_was(
    tower: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    out = tmp_path / "out"
    convert_plan(tower, out, "tower", 0.2)
    before = snapshot(out)

    def disk_full(*_args: object, **_kw: object) -> None:
        raise OSError(28, "No space left on device")

    monkeypatch.setattr("pmk_nb.library.convert.replace_all", disk_full)
    with pytest.raises(MapFormatError, match="No space left") as info:
        convert_plan(tower, out, "tower", 0.1)
    assert info.value.path == str(out)
    assert snapshot(out) == before  # old maps untouched, no staging folder left behind


def test_an_oversize_storey_fails_before_anything_is_written(tower: Path, tmp_path: Path) -> None:
    out = tmp_path / "out"
    with pytest.raises(GridTooLarge) as info:
        convert_plan(tower, out, "tower", 0.001, ConvertOptions(max_cells=1_000_000))
    assert info.value.limit == 1_000_000 and info.value.suggested_resolution > 0.001
    assert list(out.iterdir()) == []
