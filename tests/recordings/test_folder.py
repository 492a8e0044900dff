"""The recordings folder (issue 40): the MCAP files a dashboard can replay, listed newest first, a name
sent by a page looked up again, and an upload checked before it is written, replacing nothing."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from pmk_nb.recordings import RecordingFileError, list_recordings, recording_in, save_upload
from pmk_nb.recordings import folder as folder_module

MCAP = b"\x89MCAP0\r\n" + b"rest of a recording"


def _put(path: Path, data: bytes, mtime: float) -> Path:
    path.write_bytes(data)
    os.utime(path, (mtime, mtime))
    return path


def test_the_folder_lists_its_mcap_files_newest_first_and_nothing_else(tmp_path: Path) -> None:
    assert list_recordings(tmp_path / "missing") == []  # no folder yet: nothing recorded
    _put(tmp_path / "old.mcap", MCAP, 1_000)
    _put(tmp_path / "new.MCAP", MCAP * 2, 2_000)
    _put(tmp_path / "notes.txt", b"x", 3_000)
    _put(tmp_path / ".partial.mcap", MCAP, 3_000)  # hidden: a file still being written
    (tmp_path / "dir.mcap").mkdir()
    (tmp_path / "link.mcap").symlink_to(tmp_path / "old.mcap")
    found = list_recordings(tmp_path)
    assert [r.name for r in found] == ["new.MCAP", "old.mcap"]
    assert found[0].size == 2 * len(MCAP) and found[0].label == f"new.MCAP ({2 * len(MCAP)} B)"


@pytest.mark.parametrize("name", ["../outside.mcap", "/etc/passwd", "notes.txt", "link.mcap", "gone.mcap", "", None, 3])
def test_a_name_from_the_page_must_be_a_listed_recording(tmp_path: Path, name: object) -> None:
    _put(tmp_path / "run.mcap", MCAP, 1_000)
    (tmp_path / "notes.txt").write_text("x")
    (tmp_path / "link.mcap").symlink_to(tmp_path / "run.mcap")
    (tmp_path.parent / "outside.mcap").write_bytes(MCAP)
    assert recording_in(tmp_path, "run.mcap") == tmp_path / "run.mcap"
    with pytest.raises(RecordingFileError) as got:
        recording_in(tmp_path, name)
    assert got.value.folder == str(tmp_path) and got.value.hint


def test_an_upload_is_stored_under_its_name_and_replaces_nothing(tmp_path: Path) -> None:
    folder = tmp_path / "recordings"
    first = save_upload(folder, "C:\\Users\\ana\\run.mcap", MCAP)  # a browser may send a Windows path
    assert first == folder / "run.mcap" and first.read_bytes() == MCAP
    second = save_upload(folder, "run.mcap", MCAP + b"other")
    assert second == folder / "run-2.mcap" and first.read_bytes() == MCAP  # the first one is kept
    assert save_upload(folder, "run.mcap", MCAP + b"other") == second  # the same bytes again: no third copy
    assert sorted(p.name for p in folder.iterdir()) == ["run-2.mcap", "run.mcap"]


@pytest.mark.parametrize(
    ("name", "data", "words"),
    [
        ("run.bag", MCAP, "does not end in .mcap"),
        (".hidden.mcap", MCAP, "not a usable file name"),
        ("bad\x07.mcap", MCAP, "not a usable file name"),
        ("empty.mcap", b"", "empty"),
        ("rosbag1.mcap", b"#ROSBAG V2.0\n" + b"\0" * 20, "MCAP magic"),
        ("big.mcap", MCAP + b"\0" * 64, "too large"),
    ],
)
def test_a_bad_upload_is_refused_with_its_reason_and_writes_nothing(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, name: str, data: bytes, words: str
) -> None:
    monkeypatch.setattr(folder_module, "UPLOAD_MAX_BYTES", 64)
    folder = tmp_path / "recordings"
    with pytest.raises(RecordingFileError) as got:
        save_upload(folder, name, data)
    assert words in got.value.reason and got.value.hint and got.value.name
    assert not folder.exists()
