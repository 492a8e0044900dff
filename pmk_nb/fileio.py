"""Atomic file writes: the one helper every module uses, so a crash never leaves half a file.

Everything is written to a temporary file in the destination folder, flushed to disk, then
renamed over the target (a rename within one folder is atomic on POSIX). On failure the temporary
files are removed and the ``OSError`` propagates; callers turn it into their own error type.
"""

from __future__ import annotations

import contextlib
import os
import shutil
import stat
import tempfile
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from typing import BinaryIO

#: Writes one file's content into an open binary file.
Writer = Callable[[BinaryIO], None]
#: What a file is made of: bytes, text (UTF-8), a :data:`Writer` that streams it, or a finished file
#: (moved into place by :func:`replace_all`).
Content = bytes | str | Writer | Path

__all__ = ["Content", "Writer", "append_line", "atomic_open", "atomic_write", "private_dir", "replace_all"]

#: Permission bits a private file or folder must not have (group and others).
_SHARED_BITS = 0o077


def _write(fh: BinaryIO, content: Content) -> None:
    if isinstance(content, Path):  # a finished file on another file system
        with content.open("rb") as inp:
            shutil.copyfileobj(inp, fh, 1 << 20)
    elif isinstance(content, bytes):
        fh.write(content)
    elif isinstance(content, str):
        fh.write(content.encode("utf-8"))
    else:
        content(fh)


@contextlib.contextmanager
def atomic_open(path: str | os.PathLike[str], *, mode: int = 0o644, durable: bool = True) -> Iterator[BinaryIO]:
    """A binary file that replaces ``path`` only when the ``with`` block ends without an error.

    ``mode`` is applied before the rename (``mkstemp`` would leave 0600): 0o644 for maps shared with
    a map server user, 0o600 for secrets and settings. ``durable=False`` skips the fsync: for live
    state other processes read now and nobody needs after a power cut (the drive claim, written on
    every Stop: an fsync on a busy disk would hold the chair's zero).
    """
    target = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent)
    try:
        os.chmod(tmp, mode)
        with os.fdopen(fd, "wb") as fh:
            yield fh
            fh.flush()
            if durable:
                os.fsync(fh.fileno())
        os.replace(tmp, target)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


def private_dir(path: str | os.PathLike[str], *, tighten: bool = False) -> Path:
    """Create ``path`` (and missing parents) 0700; with ``tighten``, also make an existing one 0700.

    The settings folder holds profiles, the PIN's record and the trusted host keys: other users of
    the machine need not even list it (issue 30: it was created 0755). ``tighten`` is for the
    settings folder itself (a lax one from an older version: its files' 0600 hides their content,
    not their names, and a group-writable folder lets someone swap files in). It changes only a
    folder this user owns that is not a shared sticky folder (/tmp): never a parent such as ~ or /etc.
    """
    folder = Path(path)
    missing = [p for p in (folder, *folder.parents) if not p.exists()]
    for part in reversed(missing):  # mkdir(parents=True) would give the parents the umask's mode
        with contextlib.suppress(FileExistsError):
            part.mkdir(mode=0o700)
    info = folder.stat()
    shared = info.st_mode & stat.S_ISVTX
    if tighten and info.st_uid == os.getuid() and not shared and info.st_mode & _SHARED_BITS:
        os.chmod(folder, 0o700)
    return folder


def atomic_write(
    path: str | os.PathLike[str], content: Content, *, mode: int = 0o644, mkdir: bool = False, durable: bool = True
) -> None:
    """Replace ``path`` with ``content`` atomically (``mkdir`` creates missing parent folders first;
    ``durable``: as :func:`atomic_open`).

    A private file (``mode`` without group/other bits: settings, secrets) gets a private folder
    (:func:`private_dir`); other files get the umask's.
    """
    target = Path(path)
    if mkdir and not mode & _SHARED_BITS:
        private_dir(target.parent)
    elif mkdir:
        target.parent.mkdir(parents=True, exist_ok=True)
    with atomic_open(target, mode=mode, durable=durable) as fh:
        _write(fh, content)


def append_line(path: str | os.PathLike[str], line: str) -> None:
    """Add one line to a small private list (known_hosts, known_certs) atomically, keeping the others (0600)."""
    target = Path(path)
    old = target.read_text(encoding="utf-8") if target.exists() else ""
    if old and not old.endswith("\n"):
        old += "\n"
    atomic_write(target, old + line + "\n", mode=0o600, mkdir=True)


def replace_all(folder: str | os.PathLike[str], contents: Sequence[tuple[str, Content]], *, mode: int = 0o644) -> None:
    """Write every ``(file name, content)`` to a temporary file first, then rename all in order.

    A failure while writing leaves every existing file untouched; the renames come last and in the
    given order (put the file that refers to the others, e.g. a map YAML, last). A content that is a
    :class:`~pathlib.Path` is a finished file (e.g. staged in a hidden folder beside): it is flushed
    to disk and renamed into place, not copied (a 100 M-cell map is 100 MB), unless it lies on
    another file system, where it is copied to a temporary file like any content. The caller's file
    is moved only in the rename phase, so a failure before it leaves it where it was.

    Raises:
        IsADirectoryError: when a folder has one of the names.
        OSError: when a file cannot be written.
    """
    root = Path(folder)
    for name, _ in contents:
        if (root / name).is_dir():
            raise IsADirectoryError(21, "a folder has that name", str(root / name))
    temps: list[tuple[str, Path]] = []  # temporary files of ours, removed on failure
    moves: list[tuple[str | Path, Path]] = []  # (file, target) in the given order
    try:
        for name, content in contents:
            if isinstance(content, Path) and _same_device(content, root):
                _settle(content, mode)
                moves.append((content, root / name))
                continue
            fd, tmp = tempfile.mkstemp(prefix=f".{name}.", suffix=".tmp", dir=root)
            temps.append((tmp, root / name))
            moves.append((tmp, root / name))
            os.chmod(tmp, mode)
            with os.fdopen(fd, "wb") as fh:
                _write(fh, content)
                fh.flush()
                os.fsync(fh.fileno())
        for src, final in moves:
            os.replace(src, final)
    except BaseException:
        for tmp, _ in temps:
            with contextlib.suppress(OSError):
                os.unlink(tmp)
        raise


def _same_device(path: Path, folder: Path) -> bool:
    """Whether ``path`` can be renamed into ``folder`` (one file system)."""
    return os.stat(path).st_dev == os.stat(folder).st_dev


def _settle(path: Path, mode: int) -> None:
    """Give a finished file its mode and flush it to disk, as a written temporary file is."""
    os.chmod(path, mode)
    fd = os.open(path, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)
