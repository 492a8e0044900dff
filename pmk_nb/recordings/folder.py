"""The recordings folder: the MCAP files a dashboard can replay, and an uploaded file stored among them.

Any MCAP counts (ours, ``ros2 bag record -s mcap``'s, Foxglove's): the folder is listed, never
trusted: a name chosen on the page is looked up again here (a plain name of a file in the folder,
nothing else), and an upload is checked (name, size, MCAP magic) before it is written, atomically,
under a name that replaces nothing.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

from pmk_nb.fileio import atomic_write
from pmk_nb.recordings.errors import RecordingFileError

MCAP_MAGIC = b"\x89MCAP0\r\n"  # the MCAP specification's magic: first (and last) eight bytes of a file
SUFFIX = ".mcap"
UPLOAD_MAX_BYTES = 200 * 2**20  # beside the maps import's cap: larger files are copied into the folder
NAME_MAX = 200


@dataclass(frozen=True)
class RecordingFile:
    """One MCAP file of the folder, for a picker."""

    path: Path
    size: int
    modified: float

    @property
    def name(self) -> str:
        return self.path.name

    @property
    def label(self) -> str:
        """The picker's words: name and size."""
        return f"{self.name} ({_size_text(self.size)})"


def _size_text(size: int) -> str:
    for unit, scale in (("GB", 2**30), ("MB", 2**20), ("KB", 2**10)):
        if size >= scale:
            return f"{size / scale:.1f} {unit}"
    return f"{size} B"


def _is_recording_name(name: str) -> bool:
    return name.lower().endswith(SUFFIX) and not name.startswith(".")


def list_recordings(folder: str | os.PathLike[str]) -> list[RecordingFile]:
    """The folder's MCAP files, newest first (none when the folder does not exist yet)."""
    found: list[RecordingFile] = []
    try:
        entries = list(os.scandir(folder))
    except FileNotFoundError:
        return []
    for entry in entries:
        if not _is_recording_name(entry.name) or not entry.is_file(follow_symlinks=False):
            continue
        info = entry.stat(follow_symlinks=False)
        found.append(RecordingFile(Path(entry.path), info.st_size, info.st_mtime))
    return sorted(found, key=lambda r: (-r.modified, r.name))


def recording_in(folder: str | os.PathLike[str], name: object) -> Path:
    """The file ``name`` (as a page sent it) in ``folder``.

    Raises:
        RecordingFileError: not a plain name of an MCAP file in the folder (a path, ``..``, a missing file).
    """
    where = str(folder)
    if not isinstance(name, str) or not name:
        raise RecordingFileError(name=repr(name), folder=where, reason="no recording chosen", hint="Choose one.")
    known = {r.name: r.path for r in list_recordings(folder)}
    if name not in known:
        raise RecordingFileError(
            name=name,
            folder=where,
            reason=f"no such recording in {where}",
            hint="Refresh the list: it may have been moved or deleted.",
        )
    return known[name]


def _clean_name(name: str, where: str) -> str:
    base = name.replace("\\", "/").rsplit("/", 1)[-1].strip()
    if not base or base.startswith(".") or len(base) > NAME_MAX or any(ord(c) < 32 for c in base):
        raise RecordingFileError(
            name=name, folder=where, reason="not a usable file name", hint="Rename the file, e.g. run-1.mcap."
        )
    if not base.lower().endswith(SUFFIX):
        raise RecordingFileError(
            name=name,
            folder=where,
            reason="not an MCAP file (the name does not end in .mcap)",
            hint="Choose a .mcap recording (ros2 bag record -s mcap, Foxglove, or this dashboard's).",
        )
    return base


def _free_name(folder: Path, base: str, data: bytes) -> tuple[Path, bool]:
    """A path for ``base`` that replaces nothing: ``run.mcap``, ``run-2.mcap``... (True: the same bytes are
    already there under that name)."""
    stem, suffix = base[: -len(SUFFIX)], base[-len(SUFFIX) :]
    for n in range(1, 1000):
        path = folder / (base if n == 1 else f"{stem}-{n}{suffix}")
        if not path.exists():
            return path, False
        if path.is_file() and path.stat().st_size == len(data) and path.read_bytes() == data:
            return path, True
    raise RecordingFileError(name=base, folder=str(folder), reason="too many files of that name", hint="Rename it.")


def save_upload(folder: str | os.PathLike[str], name: str, data: bytes) -> Path:
    """Store an uploaded recording in ``folder`` (created if missing) and return where it went.

    Raises:
        RecordingFileError: a name that is not a ``.mcap`` file name, an empty or too large file, bytes
            that do not start as an MCAP file does. Nothing is written then.
    """
    where = str(folder)
    base = _clean_name(name, where)
    if not data:
        raise RecordingFileError(
            name=base, folder=where, reason="the file is empty", hint="Choose the recording again."
        )
    if len(data) > UPLOAD_MAX_BYTES:
        raise RecordingFileError(
            name=base,
            folder=where,
            reason=f"larger than {UPLOAD_MAX_BYTES // 2**20} MB, too large to send through the page",
            hint=f"Copy it into {where} instead; it then appears in the list.",
        )
    if not data.startswith(MCAP_MAGIC):
        raise RecordingFileError(
            name=base,
            folder=where,
            reason="not an MCAP file (it does not start with the MCAP magic bytes)",
            hint="A ROS 1 .bag or a ros2 bag in SQLite (.db3) must be converted to MCAP first.",
        )
    target_dir = Path(folder)
    path, same = _free_name(target_dir, base, data)
    if not same:
        atomic_write(path, data, mkdir=True)
    return path
