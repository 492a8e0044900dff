"""Upload edge cases against the simulator's SFTP endpoint (asyncssh, in process): only the image
beside the YAML is ever sent, servers without posix-rename still get an atomic-enough commit."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import asyncssh
import numpy as np
import pytest
import yaml

from pmk_nb.chair.transfer import upload
from pmk_nb.errors import TransferError
from pmk_nb.grid import OccupancyGrid
from pmk_nb.rosmap import MapFiles, write_map
from pmk_nb.sim.sftp import ChairSFTPServer
from tests.fixtures_sim import sim_profile


def small_map(folder: Path, name: str, width: int = 30, seed: int = 0) -> MapFiles:
    rng = np.random.default_rng(seed)
    data = rng.choice(np.array([-1, 0, 100], dtype=np.int8), size=(20, width))
    return write_map(OccupancyGrid(data=data, resolution=0.05, origin=(0.0, 0.0, 0.0)), folder, name, preview=False)


def point_image_at(files: MapFiles, image: str) -> None:
    doc = yaml.safe_load(files.yaml.read_text())
    doc["image"] = image
    files.yaml.write_text(yaml.safe_dump(doc))


@pytest.fixture
def chair(sim_factory: Any, tmp_path: Path) -> Any:
    return sim_factory(sftp_port=0, maps_dir=tmp_path / "chair_maps")


@pytest.fixture
def secret(tmp_path: Path) -> Path:
    """A private local file outside the maps folder, which must never reach the chair."""
    path = tmp_path / "private" / "id_ed25519"
    path.parent.mkdir()
    path.write_text("-----BEGIN OPENSSH PRIVATE KEY-----\nnot for the chair\n")
    return path


def on_chair(sim: Any) -> list[str]:
    return sorted(p.name for p in Path(sim.maps_dir).iterdir())


@pytest.mark.parametrize("form", ["absolute", "dotdot"])
def test_yaml_naming_a_file_elsewhere_is_refused(chair: Any, tmp_path: Path, secret: Path, form: str) -> None:
    files = small_map(tmp_path / "maps", "evil")
    before = on_chair(chair)
    image = str(secret) if form == "absolute" else f"../private/{secret.name}"
    point_image_at(files, image)
    with pytest.raises(TransferError, match="not in the YAML's folder") as info:
        upload(files, sim_profile(chair, tmp_path), password=chair.sftp_password)
    assert info.value.path == str(files.yaml)
    assert str(files.yaml) in str(info.value) and secret.name in str(info.value)
    assert on_chair(chair) == before  # nothing sent
    assert not (tmp_path / "known_hosts").exists()  # refused before connecting


def test_symlink_out_of_the_folder_is_refused(chair: Any, tmp_path: Path, secret: Path) -> None:
    files = small_map(tmp_path / "maps", "linked")
    files.image.unlink()
    files.image.symlink_to(secret)  # same name, beside the YAML, but the content lives elsewhere
    with pytest.raises(TransferError, match="not in the YAML's folder"):
        upload(files, sim_profile(chair, tmp_path), password=chair.sftp_password)
    assert "linked.yaml" not in on_chair(chair)


def test_absolute_path_to_the_image_beside_is_sent_as_a_bare_name(chair: Any, tmp_path: Path) -> None:
    files = small_map(tmp_path / "maps", "abs")
    point_image_at(files, str(files.image.resolve()))
    result = upload(files, sim_profile(chair, tmp_path), password=chair.sftp_password)
    sent = Path(chair.maps_dir) / "abs.yaml"
    assert yaml.safe_load(sent.read_text())["image"] == "abs.pgm"
    assert (Path(chair.maps_dir) / "abs.pgm").read_bytes() == files.image.read_bytes()
    assert result.bytes_sent == files.image.stat().st_size + len(sent.read_bytes())


def test_server_without_posix_rename_falls_back_and_replaces(
    chair: Any, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    asked: list[bytes] = []

    def no_posix_rename(self: Any, oldpath: bytes, newpath: bytes) -> None:
        asked.append(newpath)
        raise asyncssh.SFTPOpUnsupported("posix-rename not supported")

    monkeypatch.setattr(ChairSFTPServer, "posix_rename", no_posix_rename)
    profile = sim_profile(chair, tmp_path)
    first = small_map(tmp_path / "one", "hall", width=30, seed=1)
    upload(first, profile, password=chair.sftp_password)
    second = small_map(tmp_path / "two", "hall", width=45, seed=2)  # same names: replaced
    upload(second, profile, password=chair.sftp_password)
    assert len(asked) == 4  # image + YAML, twice: the extension was tried each time
    assert (Path(chair.maps_dir) / "hall.pgm").read_bytes() == second.image.read_bytes()
    assert on_chair(chair) == ["hall.pgm", "hall.yaml"]  # no temporary files left
    # the known_hosts entry was written once, privately
    assert (tmp_path / "known_hosts").read_text().count("\n") == 1
    assert os.stat(tmp_path / "known_hosts").st_mode & 0o777 == 0o600


def test_other_rename_failures_are_not_mistaken_for_unsupported(
    chair: Any, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    def refuse(self: Any, oldpath: bytes, newpath: bytes) -> None:
        raise asyncssh.SFTPPermissionDenied("read-only map folder")

    monkeypatch.setattr(ChairSFTPServer, "posix_rename", refuse)
    files = small_map(tmp_path / "maps", "ro")
    with pytest.raises(TransferError, match="permission denied"):
        upload(files, sim_profile(chair, tmp_path), password=chair.sftp_password)
    assert "ro.yaml" not in on_chair(chair)
