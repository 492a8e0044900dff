"""`pmk convert`: files written, names, messages, and nothing touched on bad input."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import yaml

from pmk_nb.cli import main
from pmk_nb.indoorgml import read_building
from pmk_nb.raster import rasterise_storey
from pmk_nb.rosmap import read_map
from tests.shared_data import INDOORGML_DATA

SAMPLES = INDOORGML_DATA
ONE_STOREY = SAMPLES / "pnu313_4F_2D_doors_subset.gml"
THREE_STOREYS = SAMPLES / "fjk_haus_v1_0_3.gml"


def snapshot(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir()) if p.is_file()}


def test_convert_one_storey(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    rc = main(["convert", str(ONE_STOREY), "--resolution", "0.05", "--out", str(tmp_path), "--no-progress"])
    assert rc == 0
    stem = ONE_STOREY.stem
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(
        [f"{stem}.yaml", f"{stem}.pgm", f"{stem}-visualization.png", f"{stem}.rooms.json"]
    )
    out = capsys.readouterr().out
    building = read_building(ONE_STOREY)
    storey = building.storeys[0].name
    expected = rasterise_storey(building, storey, 0.05)
    assert str(tmp_path / f"{stem}.yaml") in out
    assert f"{expected.width} x {expected.height} cells" in out
    assert f"unit {building.unit}" in out and building.unit_reason in out
    for reader in ("ros1", "nav2_jazzy"):
        back = read_map(tmp_path / f"{stem}.yaml", reader=reader)
        np.testing.assert_array_equal(back.data, expected.data)
        assert back.origin == expected.origin
    doc = yaml.safe_load((tmp_path / f"{stem}.yaml").read_text())
    assert doc["storey"] == storey and doc["source_sha256"] == building.sha256
    assert doc["mode"] == "trinary" and doc["negate"] == 0


def test_convert_several_storeys_png_and_selection(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    building = read_building(THREE_STOREYS)
    names = [s.name for s in building.storeys]
    assert len(names) > 1
    rc = main(
        [
            "convert",
            str(THREE_STOREYS),
            "-r",
            "0.1",
            "--out",
            str(tmp_path),
            "--name",
            "haus",
            "--format",
            "png",
            "--no-preview",
            "--no-progress",
        ]
    )
    assert rc == 0
    files = sorted(p.name for p in tmp_path.iterdir())
    assert files == sorted(
        [f"haus_{n}.yaml" for n in names] + [f"haus_{n}.png" for n in names] + [f"haus_{n}.rooms.json" for n in names]
    )
    for n in names:
        assert read_map(tmp_path / f"haus_{n}.yaml").meta["storey"] == n
    sel = tmp_path / "sel"
    rc = main(["convert", str(THREE_STOREYS), "-r", "0.1", "--out", str(sel), "--storey", names[-1], "--no-progress"])
    assert rc == 0
    assert sorted(p.name for p in sel.iterdir())[0].startswith(f"{THREE_STOREYS.stem}_{names[-1]}")
    assert len(list(sel.iterdir())) == 4
    assert capsys.readouterr().out.count("storey ") >= 4


def test_progress_bar_on_request(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["convert", str(ONE_STOREY), "-r", "0.1", "--out", str(tmp_path), "--progress"]) == 0
    err = capsys.readouterr().err
    assert "100.0%" in err and "[" in err
    assert main(["convert", str(ONE_STOREY), "-r", "0.1", "--out", str(tmp_path), "--no-progress"]) == 0
    assert capsys.readouterr().err == ""


def test_max_wall_gap_option(tmp_path: Path) -> None:
    clinic = Path(__file__).resolve().parents[2] / "sample_maps" / "clinic_floor.gml"
    for gap, expected in (("0.5", 100), ("0", -1)):
        out = tmp_path / gap
        argv = ["convert", str(clinic), "-r", "0.1", "--out", str(out), "--max-wall-gap", gap, "--no-progress"]
        assert main(argv) == 0
        grid = read_map(out / "clinic_floor.yaml")
        assert grid.value_at(12.0, 6.0) == expected  # the wall left out between exam room 1 and the corridor
        assert grid.meta["max_wall_gap"] == float(gap)


@pytest.fixture
def existing(tmp_path: Path) -> Path:
    """An output folder that already holds a map set named like the sample."""
    assert main(["convert", str(ONE_STOREY), "-r", "0.2", "--out", str(tmp_path), "--no-progress"]) == 0
    return tmp_path


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["-r", "0.00001"], "--resolution"),
        (["-r", "nan"], "resolution"),
        (["-r", "inf"], "resolution"),
        (["-r", "0.05", "--storey", "NOPE"], "NOPE"),
        (["-r", "0.05", "--wall-thickness", "-1"], "wall thickness"),
        (["-r", "0.05", "--max-wall-gap", "-0.5"], "max wall gap"),
        (["-r", "0.05", "--unit", "furlong"], "furlong"),
    ],
)
def test_bad_arguments_exit_2_and_touch_nothing(
    existing: Path, capsys: pytest.CaptureFixture[str], argv: list[str], message: str
) -> None:
    before = snapshot(existing)
    capsys.readouterr()
    rc = main(["convert", str(ONE_STOREY), "--out", str(existing), "--no-progress", *argv])
    assert rc == 2
    err = capsys.readouterr().err
    assert "pmk convert: error:" in err and message in err
    assert snapshot(existing) == before


def test_bad_files_exit_2_and_touch_nothing(
    existing: Path, tmp_path_factory: pytest.TempPathFactory, capsys: pytest.CaptureFixture[str]
) -> None:
    before = snapshot(existing)
    src = tmp_path_factory.mktemp("src")
    broken = src / ONE_STOREY.name  # same stem, so the same output names
    broken.write_text("<IndoorFeatures><unclosed>")
    assert main(["convert", str(broken), "-r", "0.05", "--out", str(existing), "--no-progress"]) == 2
    assert main(["convert", str(src / "missing.gml"), "-r", "0.05", "--out", str(existing)]) == 2
    err = capsys.readouterr().err
    assert str(broken) in err and "missing.gml" in err
    assert snapshot(existing) == before


@pytest.mark.slow
def test_real_process_exit_code(tmp_path: Path) -> None:
    pmk = Path(sys.executable).parent / "pmk"
    cmd = [str(pmk)] if pmk.exists() else [sys.executable, "-m", "pmk_nb.cli"]
    (tmp_path / "plans").mkdir()
    gml = tmp_path / "plans" / "in.gml"
    shutil.copy(ONE_STOREY, gml)
    ok = subprocess.run(
        [*cmd, "convert", str(gml), "-r", "0.1"], capture_output=True, text=True, timeout=120, cwd=tmp_path
    )
    assert ok.returncode == 0, ok.stderr
    # without --out the maps go to the current folder, never beside the plan
    assert (tmp_path / "in.yaml").exists() and (tmp_path / "in-visualization.png").exists()
    assert sorted(p.name for p in (tmp_path / "plans").iterdir()) == ["in.gml"]
    bad = subprocess.run([*cmd, "convert", str(gml), "-r", "-1"], capture_output=True, text=True, timeout=120)
    assert bad.returncode == 2 and "resolution" in bad.stderr
