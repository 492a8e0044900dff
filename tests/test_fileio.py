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
