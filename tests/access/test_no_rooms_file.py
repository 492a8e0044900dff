"""A map without a rooms file (issue 40, item 8): a SLAM map is not told to convert a building plan again."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from pmk_nb.access.sidecar import NoRoomsFile, read_sidecar
from pmk_nb.cli import main
from pmk_nb.rosmap import write_map
from tests.fixtures_sim import room_grid

SLAM_YAML = "image: lab.pgm\nresolution: 0.050000\norigin: [-10.0, -10.0, 0.0]\nnegate: 0\n"
SLAM_YAML += "occupied_thresh: 0.65\nfree_thresh: 0.196\n"  # as map_saver writes it: no generator


def _slam_map(folder: Path) -> Path:
    """A map as a chair's SLAM saved it: YAML + PGM, nothing of ours."""
    (folder / "lab.pgm").write_bytes(b"P5\n4 3\n255\n" + bytes([254] * 12))
    yaml = folder / "lab.yaml"
    yaml.write_text(SLAM_YAML)
    return yaml


def test_a_slam_map_is_told_to_check_the_plan_not_to_convert_it_again(tmp_path: Path) -> None:
    with pytest.raises(NoRoomsFile) as caught:
        read_sidecar(_slam_map(tmp_path))
    assert caught.value.converted is False
    assert "Convert the building plan again" not in str(caught.value)
    assert "not converted from a building plan" in caught.value.hint


def test_a_converted_map_without_its_rooms_file_is_told_to_convert_again(tmp_path: Path) -> None:
    files = write_map(room_grid(), tmp_path, "ward", preview=False)
    with pytest.raises(NoRoomsFile) as caught:
        read_sidecar(files.yaml)
    assert caught.value.converted is True and "Convert the building plan again" in caught.value.hint


def test_pmk_check_on_a_slam_map_says_so_as_json(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["check", str(_slam_map(tmp_path)), "--json", "--chair-width", "0.7"]) == 2
    doc = json.loads(capsys.readouterr().out)
    assert doc["error"] == "NoRoomsFile" and doc["fields"]["converted"] is False
    assert "pmk check PLAN.gml" in doc["hint"]
