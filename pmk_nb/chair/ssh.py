"""SSH connections to the chair with verified host keys (used by the map transfer and `pmk chair test`).

Host keys live in our own known_hosts file (``ChairProfile.known_hosts_path``). Unknown keys are
trusted on first use (recorded, fingerprint reported) or refused in strict mode (the dashboard's:
:class:`UnknownHostKey` carries the key it shows for confirmation, then :func:`trust_host_key`
records that key); a *changed* key is
always refused with the command that clears the old entry. Every network step has a timeout and
every failure becomes a TransferError naming user@host:port and what to check.
"""

from __future__ import annotations

import base64
import contextlib
import errno
import hashlib
import posixpath
import socket
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import paramiko
from paramiko.sftp import SFTP_OP_UNSUPPORTED

from pmk_nb.errors import PmkError, TransferError, UnknownHostKey
from pmk_nb.fileio import append_line
from pmk_nb.seams import StatusHookSFTPClient

if TYPE_CHECKING:
    from pmk_nb.chair.profiles import ChairProfile


@dataclass(frozen=True)
class HostKeyInfo:
    """The chair's SSH host key as checked for this connection."""

    host: str  # the known_hosts name: "host" or "[host]:port"
    key_type: str
    fingerprint: str  # "SHA256:..." like ``ssh-keygen -lf``
    newly_trusted: bool  # True when trust-on-first-use just recorded it
    known_hosts: Path


def fingerprint(key: paramiko.PKey) -> str:
    """OpenSSH-style SHA256 fingerprint, so users can compare with ``ssh-keygen -lf`` on the chair."""
    return "SHA256:" + base64.b64encode(hashlib.sha256(key.asbytes()).digest()).decode().rstrip("=")


def known_hosts_name(host: str, port: int) -> str:
    return host if port == 22 else f"[{host}]:{port}"


class VerifyingHostKeyPolicy(paramiko.MissingHostKeyPolicy):  # type: ignore[misc]  # paramiko has no type hints: subclassing it is the seam
    """Unknown keys: refused (strict) or recorded in our known_hosts (trust on first use).

    Changed keys never reach this policy: paramiko raises BadHostKeyException, which we turn into a
    refusal that tells the user how to re-trust the chair if the change is legitimate.
    """

    def __init__(self, known_hosts: Path, *, strict: bool = False) -> None:
        self.known_hosts = known_hosts
        self.strict = strict
        self.recorded: HostKeyInfo | None = None

    def missing_host_key(self, client: paramiko.SSHClient, hostname: str, key: paramiko.PKey) -> None:
        fp = fingerprint(key)
        if self.strict:
            raise UnknownHostKey(
                f"{hostname}: unknown SSH host key {key.get_name()} {fp} and strict host key checking is on; "
                f"check the fingerprint on the chair (ssh-keygen -lf /etc/ssh/ssh_host_*_key.pub), then add "
                f"the key to {self.known_hosts} or connect once with host_key_check='tofu'",
                host=hostname,
                key_type=key.get_name(),
                fingerprint=fp,
                key_base64=key.get_base64(),
                known_hosts=str(self.known_hosts),
            )
        append_known_host(self.known_hosts, hostname, key)
        client.get_host_keys().add(hostname, key.get_name(), key)
        self.recorded = HostKeyInfo(hostname, key.get_name(), fp, True, self.known_hosts)


def append_known_host(path: Path, hostname: str, key: paramiko.PKey) -> None:
    """Add one line to a known_hosts file atomically, keeping other entries (0600, like ssh's own)."""
    append_line(path, f"{hostname} {key.get_name()} {key.get_base64()}")


def trust_host_key(unknown: UnknownHostKey) -> None:
    """Record the key a user saw and confirmed (the dashboard's first-use step): exactly that key, so a
    different one presented at the next connection is refused as changed."""
    append_line(Path(unknown.known_hosts), f"{unknown.host} {unknown.key_type} {unknown.key_base64}")


class SftpUnsupported(PmkError, OSError):
    """The SFTP server answered SSH_FX_OP_UNSUPPORTED (e.g. no posix-rename extension).

    An OSError too (``errno``, ``strerror``), as paramiko's other status errors are.
    """

    def __init__(self, code: int, text: str) -> None:
        super().__init__(text)
        self.errno, self.strerror = code, text


class StatusSFTPClient(StatusHookSFTPClient):
    """paramiko's SFTP client, except that an "operation unsupported" status raises SftpUnsupported.

    paramiko turns every status it has no errno for into a bare IOError carrying only the server's
    text; the status code is the reliable part, so it is read (:mod:`pmk_nb.seams.paramiko_seam`)
    before paramiko drops it.
    """

    hooked_codes = frozenset({SFTP_OP_UNSUPPORTED})

    def on_status(self, code: int, text: str) -> None:
        raise SftpUnsupported(errno.EOPNOTSUPP, text)


@dataclass
class SftpSession:
    """An open, host-key-verified SFTP connection; ``home`` is the login folder (for ``~``)."""

    client: paramiko.SSHClient
    sftp: paramiko.SFTPClient
    host_key: HostKeyInfo
    home: str
    where: str  # "user@host:port" for messages

    def resolve(self, remote_dir: str) -> str:
        """Expand ``~`` / relative paths against the remote home (SFTP has no shell to do it)."""
        if remote_dir == "~" or remote_dir.startswith("~/"):
            path = self.home + remote_dir[1:]
        elif remote_dir.startswith("~"):
            raise TransferError(f"{remote_dir}: '~user' paths are not supported; use ~/... or an absolute path")
        elif not remote_dir.startswith("/"):
            path = posixpath.join(self.home, remote_dir)
        else:
            path = remote_dir
        return posixpath.normpath(path)

    def makedirs(self, path: str) -> None:
        """``mkdir -p`` over SFTP."""
        current = "/"
        for part in [p for p in path.split("/") if p]:
            current = posixpath.join(current, part)
            try:
                attrs = self.sftp.stat(current)
            except FileNotFoundError:
                try:
                    self.sftp.mkdir(current)
                except PermissionError as err:
                    raise TransferError(
                        f"{self.where}: permission denied creating {current}: choose a remote maps folder "
                        f"the user can write (remote_maps_dir), or fix its permissions on the chair"
                    ) from err
                continue
            except PermissionError as err:
                raise TransferError(f"{self.where}: permission denied reading {current}") from err
            if attrs.st_mode is not None and not (attrs.st_mode & 0o170000) == 0o040000:
                raise TransferError(f"{self.where}: {current} exists and is not a folder; choose another maps folder")


def _load_key(profile: ChairProfile, passphrase: str | None) -> paramiko.PKey:
    path = Path(profile.key_file or "").expanduser()
    try:
        return paramiko.PKey.from_path(path, password=passphrase)
    except paramiko.PasswordRequiredException as err:
        raise TransferError(f"{path}: the private key is encrypted: give its passphrase as the password") from err
    except (paramiko.SSHException, ValueError) as err:
        raise TransferError(f"{path}: cannot load the private key ({err}); is it an OpenSSH private key?") from err
    except OSError as err:
        raise TransferError(f"{path}: cannot read the private key ({err.strerror})") from err


def _connect_error(err: BaseException, profile: ChairProfile, timeout: float, *, greeted: bool) -> TransferError:
    """The TransferError for a failed connect; ``greeted``: the server sent its SSH version line."""
    where = f"{profile.ssh_user}@{profile.host}:{profile.ssh_port}"
    method = "key file " + str(profile.key_file) if profile.auth == "key" else "password"
    if isinstance(err, paramiko.BadAuthenticationType):
        return TransferError(
            f"{where}: the server does not accept {profile.auth} authentication (it allows "
            f"{', '.join(err.allowed_types)}); change 'auth' in the chair profile"
        )
    if isinstance(err, paramiko.AuthenticationException):
        hint = (
            "check the user name and password"
            if profile.auth == "password"
            else ("check the user name and that the public key is in the chair's ~/.ssh/authorized_keys")
        )
        return TransferError(f"{where}: authentication with {method} failed: {hint}")
    if isinstance(err, paramiko.ssh_exception.NoValidConnectionsError):
        inner = next(iter(err.errors.values()), None)
        if isinstance(inner, ConnectionRefusedError) or inner is None:
            return TransferError(
                f"{where}: connection refused: no SSH server on port {profile.ssh_port}; check ssh_port "
                "and that sshd runs on the chair"
            )
        err = inner
    if isinstance(err, TimeoutError | socket.timeout):
        return TransferError(
            f"{where}: no answer within {timeout:g} s: check the chair is on, on the same network, and the address"
        )
    if isinstance(err, socket.gaierror):
        return TransferError(f"{where}: unknown host name {profile.host!r}: check the address in the chair profile")
    if isinstance(err, ConnectionRefusedError):
        return TransferError(f"{where}: connection refused: check ssh_port and that sshd runs on the chair")
    if isinstance(err, OSError) and err.errno in (errno.EHOSTUNREACH, errno.ENETUNREACH):
        return TransferError(f"{where}: host unreachable ({err.strerror}): join the chair's network and retry")
    if isinstance(err, paramiko.SSHException) and not greeted:
        return TransferError(
            f"{where}: no SSH greeting within {timeout:g} s: is port {profile.ssh_port} an SSH server? "
            "is the chair overloaded?"
        )
    if isinstance(err, paramiko.SSHException):
        return TransferError(f"{where}: SSH handshake failed ({err}): is this an SSH server? is ssh_port right?")
    return TransferError(f"{where}: connection failed ({type(err).__name__}: {err})")


@contextlib.contextmanager
def open_sftp(profile: ChairProfile, *, password: str | None = None, timeout: float = 15.0) -> Iterator[SftpSession]:
    """Connect, verify the host key per ``profile.host_key_check``, authenticate, open SFTP."""
    if profile.auth == "password" and password is None:
        raise TransferError(f"{profile.ssh_user}@{profile.host}: a password is needed (auth is 'password')")
    if not profile.ssh_user:
        raise TransferError(f"chair profile {profile.name!r}: ssh_user is empty: set the chair's login name")
    pkey = _load_key(profile, password) if profile.auth == "key" else None
    known = profile.known_hosts_path
    policy = VerifyingHostKeyPolicy(known, strict=profile.host_key_check == "strict")
    client = paramiko.SSHClient()
    try:
        if known.exists():
            client.get_host_keys().load(str(known))
    except (OSError, paramiko.SSHException) as err:
        raise TransferError(f"{known}: cannot read the known_hosts file ({err}); fix or delete it") from err
    client.set_missing_host_key_policy(policy)
    name = known_hosts_name(profile.host, profile.ssh_port)
    try:
        client.connect(
            profile.host,
            port=profile.ssh_port,
            username=profile.ssh_user,
            password=password if profile.auth == "password" else None,
            pkey=pkey,
            timeout=timeout,
            banner_timeout=timeout,
            auth_timeout=timeout,
            channel_timeout=timeout,
            allow_agent=False,
            look_for_keys=False,
        )
    except TransferError:
        client.close()
        raise
    except paramiko.BadHostKeyException as err:
        client.close()
        raise TransferError(
            f"{name}: the SSH host key CHANGED (now {err.key.get_name()} {fingerprint(err.key)}, expected "
            f"{fingerprint(err.expected_key)}); refusing to connect. If the chair was reinstalled, check the "
            f"new fingerprint on it, then run: ssh-keygen -R '{name}' -f {known}"
        ) from err
    except (OSError, EOFError, paramiko.SSHException) as err:
        # when negotiation outlives ``timeout`` paramiko goes on and fails with a vague SSHException,
        # while the transport thread is about to record the real cause (banner timeout...)
        transport = client.get_transport()
        if transport is not None and transport.is_alive() and not transport.initial_kex_done:
            transport.join(1.0)  # let the thread finish and record why
        cause = getattr(transport, "saved_exception", None) or err
        greeted = transport is not None and bool(transport.remote_version)
        client.close()
        raise _connect_error(cause, profile, timeout, greeted=greeted) from err
    where = f"{profile.ssh_user}@{profile.host}:{profile.ssh_port}"
    try:
        server_key = client.get_transport().get_remote_server_key()
        host_key = policy.recorded or HostKeyInfo(name, server_key.get_name(), fingerprint(server_key), False, known)
        sftp = StatusSFTPClient.from_transport(client.get_transport())
        if sftp is None:
            raise paramiko.SSHException("the chair refused to open an SFTP channel")
        sftp.get_channel().settimeout(timeout)
        home = sftp.normalize(".")
    except (OSError, EOFError, paramiko.SSHException) as err:
        client.close()
        raise TransferError(f"{where}: cannot start SFTP ({err}): is the sftp subsystem enabled on the chair?") from err
    try:
        yield SftpSession(client, sftp, host_key, home, where)
    finally:
        with contextlib.suppress(Exception):  # the connection may already be dead: keep the real error
            sftp.close()
        client.close()
