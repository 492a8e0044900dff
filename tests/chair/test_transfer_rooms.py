"""The rooms file travels with the map: uploaded beside it when present, never a symlink's target."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

from pmk_nb.access import read_sidecar
from pmk_nb.chair.transfer import upload
from pmk_nb.library import convert_plan
from tests.chair.test_transfer_sim import on_chair, small_map
from tests.fixtures_sim import sim_profile

SAMPLE = Path(__file__).resolve().parents[2] / "sample_maps" / "clinic_floor.gml"


@pytest.fixture
def chair(sim_factory: Any, tmp_path: Path) -> Any:
    return sim_factory(sftp_port=0, maps_dir=tmp_path / "chair_maps")


def test_rooms_file_is_sent_beside_the_map(chair: Any, tmp_path: Path) -> None:
    files = convert_plan(SAMPLE, tmp_path / "maps", "clinic", 0.1).maps[0].files
    local_rooms = files.yaml.with_name("clinic.rooms.json")
    result = upload(files, sim_profile(chair, tmp_path), password=chair.sftp_password)
    assert on_chair(chair) == ["clinic.pgm", "clinic.rooms.json", "clinic.yaml"]
    remote = Path(chair.maps_dir) / "clinic.rooms.json"
    assert remote.read_bytes() == local_rooms.read_bytes()
    assert result.remote_rooms is not None and result.remote_rooms.endswith("/clinic.rooms.json")
    assert result.bytes_sent >= local_rooms.stat().st_size
    assert read_sidecar(Path(chair.maps_dir) / "clinic.yaml").storey == "0"  # readable on the chair side


def test_no_rooms_file_and_symlinked_rooms_file_send_nothing_more(chair: Any, tmp_path: Path) -> None:
    files = small_map(tmp_path / "maps", "plain")
    result = upload(files, sim_profile(chair, tmp_path), password=chair.sftp_password)
    assert result.remote_rooms is None and on_chair(chair) == ["plain.pgm", "plain.yaml"]
    secret = tmp_path / "secret.json"
    secret.write_text(json.dumps({"not": "for the chair"}))
    (tmp_path / "maps" / "plain.rooms.json").symlink_to(secret)
    result = upload(files, sim_profile(chair, tmp_path), password=chair.sftp_password)
    assert result.remote_rooms is None and "plain.rooms.json" not in on_chair(chair)
