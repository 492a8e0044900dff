"""The chair's SFTP endpoint (asyncssh): maps uploaded to ``~/ALMA_MAPS`` land in the sim's maps_dir.

Paths are mapped through :class:`pmk_nb.sim.paths.ChairFS`, the same mapping the map server uses,
so ``put(x.yaml, "ALMA_MAPS/x.yaml")`` followed by a reload of ``~/ALMA_MAPS/x.yaml`` (or
``/home/<user>/ALMA_MAPS/x.yaml``) loads that file. Everything outside ``~/ALMA_MAPS`` lives in a
private scratch folder.

Confinement: the endpoint refuses to create symlinks (they let a client build a relative path that
escapes), and every path a client names is checked by its real path (symlinks followed; for a new
file, its parent folder) against the two roots, maps_dir and the scratch folder. A symlink someone
put on disk inside a root that points outside is therefore refused too. A rename is confined on
both sides and neither side may be a root itself (issue 38: ``rename("ALMA_MAPS", "../moved")``
moved the maps folder into the scratch home); nor may rmdir remove one. What is not covered: a
local user swapping a folder for a symlink between that check and the open (clients cannot).
Auth: the configured user with its password (unless password login is off), or with any of the
authorized public keys if given (an OpenSSH public key line, or a file of them like authorized_keys).
The ed25519 host key is generated once per SimChair and kept across restarts; with a state folder
(`pmk sim --state-dir`, :mod:`pmk_nb.sim.hostkey`) it is kept across processes too.
"""

from __future__ import annotations

import os
import shutil
import tempfile
from pathlib import Path
from typing import TYPE_CHECKING, Protocol

import asyncssh

from pmk_nb.sim.hostkey import load_host_key
from pmk_nb.sim.paths import holds_a_root, inside_roots

if TYPE_CHECKING:
    from pmk_nb.sim.config import SimConfig
    from pmk_nb.sim.paths import ChairFS


class ChairSFTPServer(asyncssh.SFTPServer):
    """SFTP server whose file system is ChairFS: ALMA_MAPS -> maps_dir, the rest -> scratch; no symlinks."""

    def __init__(self, chan: asyncssh.SSHServerChannel[bytes], fs: ChairFS, scratch: Path) -> None:
        super().__init__(chan)
        self._fs = fs
        self._scratch = scratch
        self._roots = (fs.maps_dir, scratch)  # both already resolved

    def map_path(self, path: bytes) -> bytes:
        """Host path for a client path; every asyncssh file operation goes through here."""
        virtual = self._fs.virtual(os.fsdecode(path))
        host = self._fs.in_maps(virtual)
        if host is None:
            host = self._scratch / virtual.lstrip("/")
        if not inside_roots(host, self._roots):
            raise asyncssh.SFTPPermissionDenied(f"{virtual}: leads outside the chair's folders")
        return os.fsencode(host)

    def rename(self, oldpath: bytes, newpath: bytes) -> None:
        """Both sides inside the chair's folders, neither a root (the maps folder stays where it is)."""
        self._not_a_root(oldpath)
        self._not_a_root(newpath)
        super().rename(oldpath, newpath)

    def posix_rename(self, oldpath: bytes, newpath: bytes) -> None:
        """As :meth:`rename`; an empty maps folder must not be replaced by another folder either."""
        self._not_a_root(oldpath)
        self._not_a_root(newpath)
        super().posix_rename(oldpath, newpath)

    def rmdir(self, path: bytes) -> None:
        """An empty maps folder is not removed: the map server and uploads need it."""
        self._not_a_root(path)
        super().rmdir(path)

    def _not_a_root(self, path: bytes) -> None:
        host = Path(os.fsdecode(self.map_path(path)))
        if holds_a_root(host, self._roots):
            virtual = self._fs.virtual(os.fsdecode(path))
            raise asyncssh.SFTPPermissionDenied(f"{virtual}: the chair's own folder cannot be moved or removed")

    def symlink(self, oldpath: bytes, newpath: bytes) -> None:
        """Refused: a link made through another link can point anywhere (the chair needs none)."""
        raise asyncssh.SFTPPermissionDenied("symbolic links cannot be created on this chair")

    def reverse_map_path(self, path: bytes) -> bytes:
        host = Path(os.fsdecode(path)).resolve()
        virtual = self._fs.to_virtual(host)
        if virtual is None:
            try:
                rel = host.relative_to(self._scratch).as_posix()
            except ValueError:
                raise asyncssh.SFTPNoSuchFile("File not found") from None
            virtual = "/" if rel == "." else "/" + rel
        return os.fsencode(virtual)


class _Auth(asyncssh.SSHServer):
    def __init__(self, user: str, password: str | None, keys: list[asyncssh.SSHKey]) -> None:
        self._user, self._password, self._keys = user, password, keys

    def begin_auth(self, username: str) -> bool:
        return True

    def password_auth_supported(self) -> bool:
        return self._password is not None

    def validate_password(self, username: str, password: str) -> bool:
        return self._password is not None and username == self._user and password == self._password

    def public_key_auth_supported(self) -> bool:
        return bool(self._keys)

    def validate_public_key(self, username: str, key: asyncssh.SSHKey) -> bool:
        data = key.public_data
        return username == self._user and any(k.public_data == data for k in self._keys)


def load_authorized_keys(spec: str | Path | None) -> list[asyncssh.SSHKey]:
    """Public keys from an OpenSSH key line or a file of them (blank and ``#`` lines skipped).

    Raises ValueError naming the file and line, so a bad ``--sftp-authorized-key`` fails at start.
    """
    if spec is None:
        return []
    text, where = str(spec), "key"
    if not text.lstrip().startswith(("ssh-", "ecdsa-", "sk-")):
        where = str(spec)
        try:
            text = Path(spec).read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError) as err:
            raise ValueError(f"cannot read authorized key file {spec}: {err}") from err
    keys = []
    for number, line in enumerate(text.splitlines(), 1):
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        try:
            keys.append(asyncssh.import_public_key(line.strip()))
        except (asyncssh.KeyImportError, ValueError) as err:
            raise ValueError(
                f"{where} line {number}: not an OpenSSH public key ({err}); give the .pub file, not the private key"
            ) from err
    if not keys:
        raise ValueError(f"{where}: no public key found (expected lines like 'ssh-ed25519 AAAA... comment')")
    return keys


class SftpHost(Protocol):
    """The chair an endpoint serves (:class:`~pmk_nb.sim.server.SimChair` is one): its settings, folders and
    login are read; the key, port and fingerprint are filled in. Declared here so the endpoint needs nothing
    of the server that starts it."""

    config: SimConfig
    fs: ChairFS
    sftp_password: str | None  # None: password login refused
    sftp_keys: list[asyncssh.SSHKey]
    sftp_server_key: asyncssh.SSHKey | None
    sftp_port: int | None
    sftp_host_key_fingerprint: str | None
    sftp_host_key: str | None


class SftpEndpoint:
    """A running asyncssh listener plus its scratch folder."""

    def __init__(self, acceptor: asyncssh.SSHAcceptor, scratch: Path) -> None:
        self._acceptor = acceptor
        self._scratch = scratch

    def close(self) -> None:
        self._acceptor.close()

    async def wait_closed(self) -> None:
        await self._acceptor.wait_closed()
        shutil.rmtree(self._scratch, ignore_errors=True)


async def start_sftp(sim: SftpHost) -> SftpEndpoint:
    """Listen on the configured host and SFTP port; fill in the sim's port and fingerprint."""
    cfg = sim.config
    host_key = sim.sftp_server_key
    if host_key is None:  # the state folder's key (issue 29), kept so a restarted sim presents the same key
        host_key = load_host_key(Path(cfg.state_dir).expanduser() if cfg.state_dir is not None else None)
        sim.sftp_server_key = host_key
    keys = sim.sftp_keys
    scratch = Path(tempfile.mkdtemp(prefix="pmk-sim-home-")).resolve()
    (scratch / sim.fs.home.lstrip("/") / "ALMA_MAPS").mkdir(parents=True)
    fs = sim.fs

    def sftp_factory(chan: asyncssh.SSHServerChannel[bytes]) -> ChairSFTPServer:
        return ChairSFTPServer(chan, fs, scratch)

    port = sim.sftp_port if sim.sftp_port is not None else int(cfg.sftp_port or 0)
    acceptor = await asyncssh.listen(
        cfg.host,
        port,
        server_factory=lambda: _Auth(cfg.sftp_user, sim.sftp_password, keys),
        server_host_keys=[host_key],
        sftp_factory=sftp_factory,
        allow_scp=False,
        reuse_address=True,
    )
    sim.sftp_port = int(acceptor.get_port())
    sim.sftp_host_key_fingerprint = host_key.get_fingerprint("sha256")
    sim.sftp_host_key = host_key.export_public_key("openssh").decode("ascii").strip()
    return SftpEndpoint(acceptor, scratch)
