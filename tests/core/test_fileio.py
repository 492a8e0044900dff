"""pmk_nb.fileio.replace_all with finished files: moved into place (not copied), all or nothing."""

from __future__ import annotations

import os
import stat
from pathlib import Path

import pytest

from pmk_nb import fileio
from pmk_nb.fileio import replace_all


def _staged(tmp_path: Path, name: str, data: bytes) -> Path:
    folder = tmp_path / ".staging"
    folder.mkdir(exist_ok=True)
    path = folder / name
    path.write_bytes(data)
    os.chmod(path, 0o600)
    return path


def test_a_finished_file_is_renamed_into_place_not_copied(tmp_path: Path) -> None:
    image = _staged(tmp_path, "m.pgm", b"P5 new")
    inode = image.stat().st_ino
    (tmp_path / "m.pgm").write_bytes(b"P5 old")
    replace_all(tmp_path, [("m.pgm", image), ("m.yaml", "image: m.pgm\n")])
    out = tmp_path / "m.pgm"
    assert out.read_bytes() == b"P5 new" and out.stat().st_ino == inode  # the same file, moved
    assert not image.exists()
    assert stat.S_IMODE(out.stat().st_mode) == 0o644  # the mode asked for, as written files get
    assert (tmp_path / "m.yaml").read_text() == "image: m.pgm\n"


def test_a_failed_write_moves_nothing_and_keeps_the_old_set(tmp_path: Path) -> None:
    image = _staged(tmp_path, "m.pgm", b"P5 new")
    (tmp_path / "m.pgm").write_bytes(b"P5 old")

    def full(_fh: object) -> None:
        raise OSError(28, "No space left on device")

    with pytest.raises(OSError, match="No space"):
        replace_all(tmp_path, [("m.pgm", image), ("m.yaml", full)])
    assert (tmp_path / "m.pgm").read_bytes() == b"P5 old"  # the old file until the new set is complete
    assert image.read_bytes() == b"P5 new"  # the caller's staged file is still where it was
    assert sorted(p.name for p in tmp_path.iterdir()) == [".staging", "m.pgm"]  # no temporary left


def test_a_file_on_another_file_system_is_copied(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    image = _staged(tmp_path, "m.pgm", b"P5 new")
    monkeypatch.setattr(fileio, "_same_device", lambda _p, _f: False)  # as if /tmp were another disk
    replace_all(tmp_path, [("m.pgm", image)])
    assert (tmp_path / "m.pgm").read_bytes() == b"P5 new" and image.exists()
    assert (tmp_path / "m.pgm").stat().st_ino != image.stat().st_ino


def test_the_settings_folder_is_private(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Issue 30: the settings folder was created 0755; now 0700, and an old lax one is tightened."""
    previous = os.umask(0o022)
    try:
        _settings_folder_is_private(tmp_path, monkeypatch)
    finally:
        os.umask(previous)


def _settings_folder_is_private(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from pmk_nb.chair import ChairProfile, ProfileStore

    fresh = tmp_path / "new" / "pmk_nb"
    monkeypatch.setenv("PMK_CONFIG_DIR", str(fresh))
    ProfileStore().save(ChairProfile(name="lab", host="127.0.0.1"))
    assert stat.S_IMODE(fresh.stat().st_mode) == 0o700
    assert stat.S_IMODE(fresh.parent.stat().st_mode) == 0o700  # a missing parent too
    old = tmp_path / "old"
    old.mkdir()
    os.chmod(old, 0o755)
    ProfileStore(old / "profiles.json").save(ChairProfile(name="lab", host="127.0.0.1"))
    assert stat.S_IMODE(old.stat().st_mode) == 0o700  # the settings folder of an older version: tightened
    shared_tmp = tmp_path / "tmp"
    shared_tmp.mkdir()
    os.chmod(shared_tmp, 0o1777)
    beside = tmp_path / "home"
    beside.mkdir()
    os.chmod(beside, 0o755)
    fileio.atomic_write(shared_tmp / "known_hosts", "", mode=0o600, mkdir=True)  # a file's existing folder:
    fileio.atomic_write(beside / "known_hosts", "", mode=0o600, mkdir=True)  # never changed
    assert stat.S_IMODE(beside.stat().st_mode) == 0o755 and stat.S_IMODE(shared_tmp.stat().st_mode) == 0o1777
    fileio.private_dir(shared_tmp, tighten=True)  # nor a shared sticky folder, even when asked
    assert stat.S_IMODE(shared_tmp.stat().st_mode) == 0o1777
    shared = tmp_path / "maps"
    fileio.atomic_write(shared / "m.yaml", "", mkdir=True)  # a shared file keeps a shared folder
    assert stat.S_IMODE(shared.stat().st_mode) == 0o755


def test_live_state_is_replaced_atomically_without_an_fsync(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The drive claim is written on every Stop: no fsync may hold the chair's zero; settings keep theirs."""
    synced: list[int] = []
    monkeypatch.setattr(fileio.os, "fsync", lambda fd: synced.append(fd))
    fileio.atomic_write(tmp_path / "claim.json", b"live", mode=0o600, durable=False)
    assert synced == [] and (tmp_path / "claim.json").read_bytes() == b"live"
    assert os.stat(tmp_path / "claim.json").st_mode & 0o777 == 0o600
    fileio.atomic_write(tmp_path / "settings.json", b"kept")
    assert len(synced) == 1
    assert sorted(p.name for p in tmp_path.iterdir()) == ["claim.json", "settings.json"]  # no temporary left
