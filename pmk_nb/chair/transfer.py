"""Copy a map (YAML + image) to the chair over SFTP, atomically, with verified host keys.

The original MapTransferrer opened a JSch session with the saved user/password and dropped the two
files into ``~/ALMA_MAPS``. We keep that layout but: the host key is checked (see
:mod:`pmk_nb.chair.ssh`: trust on first use records it and reports its SHA256 fingerprint, a
*changed* key is always refused, strict mode refuses unknown keys too); both files are written
under hidden temporary names and then renamed into place, image first, so the map server never
sees a half-written file or a YAML pointing at a missing image; every network step has a timeout.
"""

from __future__ import annotations

import contextlib
import io
import posixpath
import re
import secrets
import socket
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import paramiko
import yaml

from pmk_nb.chair.ssh import (
    HostKeyInfo,
    SftpSession,
    SftpUnsupported,
    VerifyingHostKeyPolicy,
    fingerprint,
    known_hosts_name,
    open_sftp,
)
from pmk_nb.errors import MapFormatError, TransferError, UnsupportedOperation
from pmk_nb.progress import ProgressCallback, emit

if TYPE_CHECKING:
    from pmk_nb.chair.profiles import ChairProfile
    from pmk_nb.rosmap import MapFiles, MapYaml

__all__ = [
    "HostKeyInfo",
    "SshCheck",
    "UploadResult",
    "VerifyingHostKeyPolicy",
    "check_ssh",
    "fingerprint",
    "image_beside",
    "known_hosts_name",
    "open_sftp",
    "upload",
    "upload_map",
]

ByteCallback = Callable[[int, int], None]  # paramiko's (bytes sent of this file, its size)


@dataclass(frozen=True)
class UploadResult:
    remote_yaml: str
    remote_image: str
    bytes_sent: int
    host_key: HostKeyInfo
    elapsed: float
    remote_rooms: str | None = None  # the rooms file sent beside the map, if there was one


def rooms_beside(yaml_path: Path) -> Path | None:
    """The map's rooms file (``NAME.rooms.json``, see ``pmk_nb.access.sidecar``) when it is a plain
    file in the YAML's folder; it travels with the map (the chair's map server ignores it)."""
    path = yaml_path.with_name(yaml_path.stem + ".rooms.json")
    return path if path.is_file() and not path.is_symlink() else None


def image_beside(yaml_path: Path) -> tuple[MapYaml, Path]:
    """The map YAML and its image, which must sit in the YAML's own folder.

    Only that image is ever sent: a YAML naming an absolute path elsewhere, a ``..`` path or a
    symlink leading out of the folder would otherwise copy any local file to the chair.

    Raises:
        TransferError: (``path`` = the YAML) the YAML is unreadable, or its image is elsewhere or missing.
    """
    from pmk_nb.rosmap import read_map_yaml

    try:
        doc = read_map_yaml(yaml_path)
    except MapFormatError as err:
        raise TransferError(f"{yaml_path}: cannot read the map YAML ({err})", path=str(yaml_path)) from err
    image = doc.image
    if not doc.image_is_beside:
        raise TransferError(
            f"{yaml_path}: its image {image} is not in the YAML's folder; only an image beside the YAML "
            "(a plain file name, no '..', no symlink out of the folder) is sent to the chair",
            path=str(yaml_path),
        )
    if not image.is_file():
        raise TransferError(f"{yaml_path}: its image {image.name} does not exist ({image})", path=str(yaml_path))
    return doc, image


def _yaml_for_upload(yaml_path: Path) -> tuple[bytes, Path]:
    """The YAML bytes to send and its image; the image entry becomes the bare file name if needed
    (the chair has both files side by side)."""
    doc, image = image_beside(yaml_path)
    try:
        text = yaml_path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as err:
        raise TransferError(f"{yaml_path}: cannot read the map YAML ({err})", path=str(yaml_path)) from err
    new, count = re.subn(r"(?m)^image\s*:.*$", f"image: {image.name}", text, count=1)
    if count:
        return new.encode("utf-8"), image
    # flow-style YAML ({image: ..., ...}): write it out again from the parsed fields
    fields = doc.fields(image=image.name)
    return yaml.safe_dump(fields, sort_keys=False).encode("utf-8"), image


def _temp_name(remote_dir: str, name: str) -> str:
    return posixpath.join(remote_dir, f".{name}.part-{secrets.token_hex(4)}")


def _put_temp(session: SftpSession, data: io.BufferedIOBase, size: int, tmp: str, on_bytes: ByteCallback) -> None:
    """Write to the hidden temporary path ``tmp`` and check its size on the chair."""
    session.sftp.putfo(data, tmp, file_size=size, callback=on_bytes, confirm=False)
    got = session.sftp.stat(tmp).st_size
    if got != size:
        raise TransferError(f"{session.where}: {tmp}: wrote {got} of {size} bytes; the chair's disk may be full")


def _posix_rename(session: SftpSession, tmp: str, final: str) -> None:
    """Rename over ``final`` in one step (OpenSSH's posix-rename extension).

    Raises:
        UnsupportedOperation: (``operation="posix-rename"``) the server answered "unsupported".
    """
    try:
        session.sftp.posix_rename(tmp, final)
    except SftpUnsupported as err:
        raise UnsupportedOperation(
            f"{session.where}: the SFTP server has no posix-rename", operation="posix-rename"
        ) from err


def _commit(session: SftpSession, tmp: str, final: str) -> None:
    """Rename over the final name in one step (posix-rename); remove + rename on servers without it."""
    try:
        _posix_rename(session, tmp, final)
    except UnsupportedOperation:
        with contextlib.suppress(FileNotFoundError):  # no posix-rename extension: short window
            session.sftp.remove(final)
        session.sftp.rename(tmp, final)


def _remove_stale_parts(session: SftpSession, remote_dir: str, names: tuple[str, ...]) -> None:
    """Best effort: drop temp files an earlier, interrupted upload of these names left behind."""
    with contextlib.suppress(OSError):
        for entry in session.sftp.listdir(remote_dir):
            if any(entry.startswith(f".{name}.part-") for name in names):
                with contextlib.suppress(OSError):
                    session.sftp.remove(posixpath.join(remote_dir, entry))


def _upload_error(err: BaseException, session: SftpSession, remote_dir: str) -> TransferError:
    if isinstance(err, PermissionError):
        return TransferError(
            f"{session.where}: permission denied writing in {remote_dir}: choose a folder the user can "
            "write (remote_maps_dir) or fix its permissions on the chair"
        )
    if isinstance(err, TimeoutError | socket.timeout):
        return TransferError(f"{session.where}: the chair stopped answering during the upload; retry")
    transport = session.client.get_transport()
    lost = transport is None or not transport.is_active()
    if lost or isinstance(err, EOFError | paramiko.SSHException | ConnectionError):
        return TransferError(
            f"{session.where}: connection lost during the upload ({str(err) or type(err).__name__}); files already on "
            "the chair under the same name are unchanged: retry"
        )
    return TransferError(
        f"{session.where}: writing in {remote_dir} failed ({err}): the chair's disk may be full or the folder "
        "not writable; free some space and retry"
    )


def _bytes_progress(progress: ProgressCallback | None, done: int, total: int) -> None:
    emit(progress, "upload", done / max(total, 1), f"{done // 1024} / {total // 1024} KiB")


def upload(
    files: MapFiles,
    profile: ChairProfile,
    *,
    password: str | None = None,
    progress: ProgressCallback | None = None,
    timeout: float = 15.0,
) -> UploadResult:
    """Upload a map's YAML and image into ``profile.remote_maps_dir`` (created if missing).

    ``progress`` gets ``Progress("upload", bytes sent / total, "120 / 480 KiB")``; the image sent is
    always the one beside the YAML (see :func:`image_beside`).

    Raises:
        TransferError: with the host and what to do (auth, refused, timeout, host key, permissions...).
    """
    started = time.monotonic()
    yaml_bytes, image = _yaml_for_upload(Path(files.yaml))
    image_size = image.stat().st_size
    rooms = rooms_beside(Path(files.yaml))
    rooms_bytes = rooms.read_bytes() if rooms is not None else b""
    total = image_size + len(yaml_bytes) + len(rooms_bytes)
    with open_sftp(profile, password=password, timeout=timeout) as session:
        remote_dir = session.resolve(profile.remote_maps_dir)
        session.makedirs(remote_dir)
        done = 0

        def on_bytes(sent: int, _size: int) -> None:
            _bytes_progress(progress, done + sent, total)

        remote_image = posixpath.join(remote_dir, image.name)
        remote_yaml = posixpath.join(remote_dir, Path(files.yaml).name)
        temps = [_temp_name(remote_dir, image.name), _temp_name(remote_dir, Path(files.yaml).name)]
        remote_rooms = posixpath.join(remote_dir, rooms.name) if rooms is not None else None
        if rooms is not None:
            temps.append(_temp_name(remote_dir, rooms.name))
        try:
            # both files to temp names first, then two renames: image, then YAML (the YAML never
            # points at a missing image, and the window where old YAML + new image coexist is tiny)
            with image.open("rb") as fh:
                _put_temp(session, fh, image_size, temps[0], on_bytes)
            done = image_size
            _put_temp(session, io.BytesIO(yaml_bytes), len(yaml_bytes), temps[1], on_bytes)
            if remote_rooms is not None:  # committed before the YAML, like the image
                done += len(yaml_bytes)
                _put_temp(session, io.BytesIO(rooms_bytes), len(rooms_bytes), temps[2], on_bytes)
                _commit(session, temps[2], remote_rooms)
            _commit(session, temps[0], remote_image)
            _commit(session, temps[1], remote_yaml)
        except BaseException as err:
            for tmp in temps:
                with contextlib.suppress(Exception):
                    session.sftp.remove(tmp)
            if isinstance(err, OSError | EOFError | paramiko.SSHException) and not isinstance(err, TransferError):
                raise _upload_error(err, session, remote_dir) from err
            raise
        names = (image.name, Path(files.yaml).name) + ((rooms.name,) if rooms is not None else ())
        _remove_stale_parts(session, remote_dir, names)
        _bytes_progress(progress, total, total)
        elapsed = time.monotonic() - started
        return UploadResult(remote_yaml, remote_image, total, session.host_key, elapsed, remote_rooms)


def upload_map(
    files: MapFiles,
    profile: ChairProfile,
    *,
    password: str | None = None,
    progress: ProgressCallback | None = None,
    timeout: float = 15.0,
) -> str:
    """Like ``upload`` but returns only the absolute remote YAML path (what the reload service needs)."""
    return upload(files, profile, password=password, progress=progress, timeout=timeout).remote_yaml


@dataclass(frozen=True)
class SshCheck:
    host_key: HostKeyInfo
    remote_dir: str
    exists: bool


def check_ssh(profile: ChairProfile, *, password: str | None = None, timeout: float = 10.0) -> SshCheck:
    """Log in and look at the remote maps folder, without changing anything (``pmk chair test``)."""
    with open_sftp(profile, password=password, timeout=timeout) as session:
        remote_dir = session.resolve(profile.remote_maps_dir)
        try:
            session.sftp.stat(remote_dir)
            exists = True
        except FileNotFoundError:
            exists = False
        except OSError as err:
            raise TransferError(f"{session.where}: cannot look at {remote_dir} ({err})") from err
        return SshCheck(session.host_key, remote_dir, exists)
