"""`pmk check` as an independent witness of the written files, and `pmk convert` saying its verdict."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from pmk_nb.cli import main
from pmk_nb.rosmap import read_map
from pmk_nb.witness import FindingKind

pytestmark = pytest.mark.slow  # each test converts the clinic (a second or two)

SAMPLE = Path(__file__).resolve().parents[2] / "sample_maps" / "clinic_floor.gml"


@pytest.fixture
def converted(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> Path:
    """The clinic converted into tmp_path/maps from a copy of the plan in tmp_path."""
    plan = tmp_path / "clinic_floor.gml"
    shutil.copy(SAMPLE, plan)
    assert main(["convert", str(plan), "--out", str(tmp_path / "maps")]) == 0
    out = capsys.readouterr().out
    assert "witness, storey 0: the map agrees with the plan (15 cells, 22 touching pairs, 12 transitions)" in out
    return tmp_path / "maps" / "clinic_floor.yaml"


def _open_wall(yaml: Path) -> None:
    """Paint 1.2 m of the wall between the waiting room (R1) and exam room 1 (R2) free, in the PGM."""
    grid = read_map(yaml)
    image = np.array(Image.open(yaml.with_suffix(".pgm")))
    res, (ox, oy, _) = grid.resolution, grid.origin
    c0, c1 = round((9.8 - ox) / res), round((10.2 - ox) / res)
    r0, r1 = round((2.0 - oy) / res), round((3.2 - oy) / res)
    h = image.shape[0]
    image[h - r1 : h - r0, c0:c1] = 254
    Image.fromarray(image).save(yaml.with_suffix(".pgm"))


def _check(args: list[str], capsys: pytest.CaptureFixture[str]) -> tuple[int, dict]:
    code = main(["check", *args, "--json"])
    return code, json.loads(capsys.readouterr().out)


def test_a_right_map_is_ok_and_says_the_witness_agrees(converted: Path, capsys: pytest.CaptureFixture[str]) -> None:
    code, doc = _check([str(converted)], capsys)
    assert (code, doc["ok"], doc["witness"]["ran"]) == (0, True, True)
    assert doc["witness"]["storeys"][0]["findings"] == []


def test_a_leak_the_converters_files_hide_is_caught_with_cells_place_and_picture(
    converted: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The rooms file beside the map still says what the converter planned; only the witness, reading
    the image and the plan, sees the opening painted into the written map."""
    _open_wall(converted)
    picture = tmp_path / "leak.png"
    code, doc = _check([str(converted), "--picture", str(picture)], capsys)
    assert (code, doc["ok"]) == (1, False)
    [finding] = doc["witness"]["storeys"][0]["findings"]
    assert (finding["kind"], sorted(finding["cells"])) == (FindingKind.LEAK.value, ["R1", "R2"])
    assert sorted(finding["names"]) == ["Exam room 1", "Waiting room"]
    assert abs(finding["place"][0] - 10.0) < 0.3 and 1.9 < finding["place"][1] < 3.3
    assert doc["witness"]["pictures"] == [str(picture)]
    with Image.open(picture) as im:
        assert im.format == "PNG" and im.size == (607, 307)
        ring = np.asarray(im.convert("RGB"))
    assert np.any(np.all(ring == (220, 20, 60), axis=-1))  # the leak's ring is drawn


def test_the_text_report_numbers_each_finding(converted: Path, capsys: pytest.CaptureFixture[str]) -> None:
    _open_wall(converted)
    assert main(["check", str(converted)]) == 1
    out = capsys.readouterr().out
    assert "witness, storey 0: the map DISAGREES with the plan: 1 finding(s)" in out
    assert (
        "  1. leak: Waiting room and Exam room 1 at (" in out or "  1. leak: Exam room 1 and Waiting room at (" in out
    )
    assert out.rstrip().endswith("problems found")


def test_a_map_whose_plan_is_gone_is_never_ok(converted: Path, capsys: pytest.CaptureFixture[str]) -> None:
    plan = converted.parent.parent / "clinic_floor.gml"
    moved = converted.parent.parent / "elsewhere.gml"
    plan.rename(moved)
    code, doc = _check([str(converted)], capsys)
    assert (code, doc["ok"], doc["witness"]["ran"]) == (3, False, False)
    assert "--plan" in doc["witness"]["reason"]
    code, doc = _check([str(converted), "--plan", str(moved)], capsys)
    assert (code, doc["ok"]) == (0, True)


def test_a_changed_plan_is_refused_by_its_hash(converted: Path, capsys: pytest.CaptureFixture[str]) -> None:
    plan = converted.parent.parent / "clinic_floor.gml"
    plan.write_text(plan.read_text().replace("Waiting room", "Lobby"))
    assert main(["check", str(converted), "--json"]) == 2
    err = json.loads(capsys.readouterr().out)
    assert (err["ok"], err["error"]) == (False, "PlanChanged")


def test_checking_a_plan_runs_the_witness_on_each_storey(capsys: pytest.CaptureFixture[str]) -> None:
    code, doc = _check([str(SAMPLE)], capsys)
    assert code == 0
    assert [s["storey"] for s in doc["witness"]["storeys"]] == ["0"]
    assert doc["witness"]["storeys"][0]["counts"] == {"cells": 15, "touching pairs": 22, "transitions": 12}
