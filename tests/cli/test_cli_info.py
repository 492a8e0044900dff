"""`pmk info` end to end through pmk_nb.cli.main."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from pmk_nb.cli import main

SAMPLE = Path(__file__).resolve().parents[2] / "sample_maps" / "clinic_two_storeys.gml"


def test_info_human(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["info", str(SAMPLE)]) == 0
    out = capsys.readouterr().out
    assert "IndoorGML version: alma" in out
    assert "units: cm" in out and "ALMA" in out
    assert "storeys: 2" in out
    assert "F1:  15 cells," in out and "F2:  15 cells," in out
    assert "30.00 x 15.00 m" in out
    assert "translation [2500.0, 1200.0] m, rotation 30.0 deg" in out


def test_info_json(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["info", str(SAMPLE), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["version"] == "alma" and data["unit"] == "cm"
    assert [s["name"] for s in data["storeys"]] == ["F1", "F2"]
    assert data["storeys"][0]["extent"]["size"] == [30.0, 15.0]
    assert data["doors"]["total"] == 12
    assert data["graph"] == {"states": 31, "transitions": 24}
    assert data["georeference"]["rotation"] == 30.0


def test_info_unit_override(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["info", str(SAMPLE), "--unit", "m", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["unit"] == "m" and data["storeys"][0]["extent"]["size"] == [3000.0, 1500.0]


def test_info_error_exit_code(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    bad = tmp_path / "broken.gml"
    bad.write_text("<IndoorFeatures><oops></IndoorFeatures>")
    assert main(["info", str(bad)]) == 2
    err = capsys.readouterr().err
    assert "pmk info: error:" in err and "broken.gml" in err and "line 1" in err
