"""The chair's SFTP endpoint (asyncssh): maps uploaded to ``~/ALMA_MAPS`` land in the sim's maps_dir.

Paths are mapped through :class:`pmk_nb.sim.paths.ChairFS`, the same mapping the map server uses,
so ``put(x.yaml, "ALMA_MAPS/x.yaml")`` followed by a reload of ``~/ALMA_MAPS/x.yaml`` (or
``/home/<user>/ALMA_MAPS/x.yaml``) loads that file. Everything outside ``~/ALMA_MAPS`` lives in a
private scratch folder, so a client can never reach the rest of the host file system.
Auth: the configured user with its password, or with the authorized public key if one is given.
The ed25519 host key is generated once per SimChair and kept across restarts.
"""

from __future__ import annotations

import os
import shutil
import tempfile
from pathlib import Path
from typing import TYPE_CHECKING, Any

import asyncssh

if TYPE_CHECKING:
    from pmk_nb.sim.paths import ChairFS
    from pmk_nb.sim.server import SimChair


class ChairSFTPServer(asyncssh.SFTPServer):
    """SFTP server whose file system is ChairFS: ALMA_MAPS -> maps_dir, the rest -> scratch."""

    def __init__(self, chan: asyncssh.SSHServerChannel, fs: ChairFS, scratch: Path) -> None:
        super().__init__(chan)
        self._fs = fs
        self._scratch = scratch

    def map_path(self, path: bytes) -> bytes:
        virtual = self._fs.virtual(os.fsdecode(path))
        host = self._fs.in_maps(virtual)
        if host is None:
            host = self._scratch / virtual.lstrip("/")
        return os.fsencode(host)

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
    def __init__(self, user: str, password: str, keys: list[asyncssh.SSHKey]) -> None:
        self._user, self._password, self._keys = user, password, keys

    def begin_auth(self, username: str) -> bool:
        return True

    def password_auth_supported(self) -> bool:
        return True

    def validate_password(self, username: str, password: str) -> bool:
        return username == self._user and password == self._password

    def public_key_auth_supported(self) -> bool:
        return bool(self._keys)

    def validate_public_key(self, username: str, key: asyncssh.SSHKey) -> bool:
        data = key.public_data
        return username == self._user and any(k.public_data == data for k in self._keys)


def _load_keys(spec: str | Path | None) -> list[asyncssh.SSHKey]:
    if spec is None:
        return []
    text = str(spec)
    if not text.lstrip().startswith(("ssh-", "ecdsa-")):
        text = Path(spec).read_text(encoding="utf-8")
    return [asyncssh.import_public_key(line) for line in text.splitlines() if line.strip()]


class SftpEndpoint:
    """A running asyncssh listener plus its scratch folder."""

    def __init__(self, acceptor: Any, scratch: Path) -> None:
        self._acceptor = acceptor
        self._scratch = scratch

    def close(self) -> None:
        self._acceptor.close()

    async def wait_closed(self) -> None:
        await self._acceptor.wait_closed()
        shutil.rmtree(self._scratch, ignore_errors=True)


async def start_sftp(sim: SimChair) -> SftpEndpoint:
    """Listen on ``sim.host``:``sim``'s SFTP port and fill in the sim's port and fingerprint."""
    host_key = sim._sftp_host_key
    if host_key is None:
        host_key = asyncssh.generate_private_key("ssh-ed25519", comment="pmk-sim")
        sim._sftp_host_key = host_key  # kept so a restarted sim presents the same key
    keys = _load_keys(sim.sftp_authorized_key)
    scratch = Path(tempfile.mkdtemp(prefix="pmk-sim-home-")).resolve()
    (scratch / sim.fs.home.lstrip("/") / "ALMA_MAPS").mkdir(parents=True)
    fs = sim.fs

    def sftp_factory(chan: asyncssh.SSHServerChannel) -> ChairSFTPServer:
        return ChairSFTPServer(chan, fs, scratch)

    port = sim.sftp_port if sim.sftp_port is not None else int(sim._sftp_port_wanted or 0)
    acceptor = await asyncssh.listen(
        sim.host,
        port,
        server_factory=lambda: _Auth(sim.sftp_user, sim.sftp_password, keys),
        server_host_keys=[host_key],
        sftp_factory=sftp_factory,
        allow_scp=False,
        reuse_address=True,
    )
    sim.sftp_port = int(acceptor.get_port())
    sim.sftp_host_key_fingerprint = host_key.get_fingerprint("sha256")
    sim.sftp_host_key = host_key.export_public_key("openssh").decode("ascii").strip()
    return SftpEndpoint(acceptor, scratch)
