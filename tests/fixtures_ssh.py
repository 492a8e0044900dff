"""A real OpenSSH server on 127.0.0.1 for the SFTP tests (no mocks of the transfer's far end).

``sshd_server`` (session) starts ``/usr/sbin/sshd -D -e`` as root with its own host key, a test user
``pmktest`` (password and key auth) and an ephemeral port. When sshd is missing or cannot start the
fixture *fails* with the reason: the Makefile installs Debian's openssh-server.
``remote_maps_dir`` gives each test its own folder under the test user's home and removes it after.
"""

from __future__ import annotations

import base64
import contextlib
import hashlib
import os
import pwd
import shutil
import signal
import socket
import subprocess
import tempfile
import time
import uuid
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import pytest

from pmk_nb.chair import ChairProfile

SSHD = "/usr/sbin/sshd"
TEST_USER = "pmktest"
# Fixed, not random: two pytest sessions running at once must not change each other's password.
TEST_PASSWORD = "pmk-test-Secret-42"


@dataclass
class SshdServer:
    host: str
    port: int
    user: str
    password: str
    home: Path
    client_key: Path  # private key accepted for ``user``
    host_key_pub: Path
    host_key_fingerprint: str  # "SHA256:..." as OpenSSH prints it
    pid: int
    workdir: Path
    log: Path

    def known_hosts_line(self) -> str:
        key_type, key_b64 = self.host_key_pub.read_text().split()[:2]
        return f"[{self.host}]:{self.port} {key_type} {key_b64}\n"

    def session_pids(self) -> list[int]:
        """All per-connection sshd processes (descendants of the listener): kill them to cut connections."""
        parents: dict[int, int] = {}
        for stat in Path("/proc").glob("[0-9]*/stat"):
            try:
                parents[int(stat.parent.name)] = int(stat.read_text().rsplit(")", 1)[1].split()[1])
            except (OSError, ValueError, IndexError):
                continue
        found: list[int] = []
        frontier = [self.pid]
        while frontier:
            parent = frontier.pop()
            children = [pid for pid, ppid in parents.items() if ppid == parent]
            found.extend(children)
            frontier.extend(children)
        return found

    def log_text(self) -> str:
        return self.log.read_text(errors="replace") if self.log.exists() else ""


class SshdUnavailable(RuntimeError):
    """sshd is missing or would not start; the message says why."""


def _fingerprint(pub_line: str) -> str:
    blob = base64.b64decode(pub_line.split()[1])
    return "SHA256:" + base64.b64encode(hashlib.sha256(blob).digest()).decode().rstrip("=")


def _ensure_user() -> Path:
    """Create the test user once (idempotent) and (re)set its password; we are root on a test box."""
    if os.geteuid() != 0:
        raise SshdUnavailable("the OpenSSH fixture must run as root (it creates the test user and runs sshd)")
    try:
        entry = pwd.getpwnam(TEST_USER)
    except KeyError:
        proc = subprocess.run(
            ["useradd", "--create-home", "--shell", "/bin/sh", TEST_USER], capture_output=True, text=True
        )
        if proc.returncode not in (0, 9):  # 9: created meanwhile by a parallel session
            raise SshdUnavailable(f"useradd {TEST_USER} failed: {proc.stderr.strip()}") from None
        entry = pwd.getpwnam(TEST_USER)
    proc = subprocess.run(["chpasswd"], input=f"{TEST_USER}:{TEST_PASSWORD}\n", capture_output=True, text=True)
    if proc.returncode != 0:
        raise SshdUnavailable(f"chpasswd for {TEST_USER} failed: {proc.stderr.strip()}")
    home = Path(entry.pw_dir)
    home.mkdir(parents=True, exist_ok=True)
    os.chown(home, entry.pw_uid, entry.pw_gid)
    return home


def _free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return int(sock.getsockname()[1])


def _wait_banner(port: int, proc: subprocess.Popen[bytes], deadline: float) -> bool:
    while time.monotonic() < deadline and proc.poll() is None:
        try:
            with socket.create_connection(("127.0.0.1", port), timeout=1.0) as sock:
                sock.settimeout(2.0)
                if sock.recv(64).startswith(b"SSH-2.0-"):
                    return True
        except OSError:
            time.sleep(0.05)
    return False


def _write_config(work: Path, port: int, authorized: Path, host_key: Path) -> Path:
    config = work / "sshd_config"
    config.write_text(
        "\n".join(
            [
                f"Port {port}",
                "ListenAddress 127.0.0.1",
                f"HostKey {host_key}",
                f"PidFile {work / 'sshd.pid'}",
                f"AuthorizedKeysFile {authorized} .ssh/authorized_keys",  # the second: pmk chair add --key auto
                "UsePAM no",
                "StrictModes no",
                "PasswordAuthentication yes",
                "KbdInteractiveAuthentication no",
                "PubkeyAuthentication yes",
                "PermitRootLogin no",
                f"AllowUsers {TEST_USER}",
                "UseDNS no",
                "MaxStartups 64:30:128",
                "MaxAuthTries 6",
                "LogLevel VERBOSE",
                "Subsystem sftp internal-sftp",
                "",
            ]
        )
    )
    return config


@contextlib.contextmanager
def running_sshd() -> Iterator[SshdServer]:
    """Start a private sshd (outside pytest too: the deploy benchmark uses it); stop it on exit."""
    if not Path(SSHD).is_file():
        raise SshdUnavailable(f"{SSHD} not found: install the Debian package openssh-server (make test does it)")
    home = _ensure_user()
    Path("/run/sshd").mkdir(mode=0o755, parents=True, exist_ok=True)  # privilege separation dir
    # Not under pytest's tmp dir: that is 0700 root, and sshd reads authorized_keys as the test user.
    work = Path(tempfile.mkdtemp(prefix="pmk-sshd-"))
    work.chmod(0o755)
    try:
        host_key = work / "ssh_host_ed25519_key"
        client_key = work / "client_ed25519"
        for key, comment in ((host_key, "pmk-test-host"), (client_key, "pmk-test-client")):
            subprocess.run(
                ["ssh-keygen", "-q", "-t", "ed25519", "-N", "", "-C", comment, "-f", str(key)],
                check=True,
                capture_output=True,
            )
        authorized = work / "authorized_keys"
        shutil.copy(client_key.with_suffix(".pub"), authorized)
        authorized.chmod(0o644)
        log = work / "sshd.log"
        proc: subprocess.Popen[bytes] | None = None
        for _attempt in range(3):  # the free port may be taken between probing and binding
            port = _free_port()
            config = _write_config(work, port, authorized, host_key)
            with log.open("ab") as log_fh:
                proc = subprocess.Popen([SSHD, "-D", "-e", "-f", str(config)], stdout=log_fh, stderr=log_fh)
            if _wait_banner(port, proc, time.monotonic() + 10.0):
                break
            if proc.poll() is None:
                proc.kill()
            proc.wait(timeout=5)
            proc = None
        if proc is None:
            raise SshdUnavailable(
                f"sshd did not start on 127.0.0.1; its log:\n{log.read_text(errors='replace')[-2000:]}"
            )
        pub = host_key.with_suffix(".pub")
        server = SshdServer(
            host="127.0.0.1",
            port=port,
            user=TEST_USER,
            password=TEST_PASSWORD,
            home=home,
            client_key=client_key,
            host_key_pub=pub,
            host_key_fingerprint=_fingerprint(pub.read_text()),
            pid=proc.pid,
            workdir=work,
            log=log,
        )
        try:
            yield server
        finally:
            proc.send_signal(signal.SIGTERM)
            try:
                proc.wait(timeout=5)
            except subprocess.TimeoutExpired:
                proc.kill()
                proc.wait(timeout=5)
    finally:
        shutil.rmtree(work, ignore_errors=True)


@pytest.fixture(scope="session")
def sshd_server() -> Iterator[SshdServer]:
    """Fails (never skips) when OpenSSH cannot run: the SFTP tests need the real server."""
    with contextlib.ExitStack() as stack:
        try:
            server = stack.enter_context(running_sshd())
        except SshdUnavailable as err:
            pytest.fail(str(err))
        yield server


@pytest.fixture
def remote_maps_dir(sshd_server: SshdServer) -> Iterator[str]:
    """A fresh ``~/pmk-tests/<id>/ALMA_MAPS`` (not created: the upload must create it)."""
    run_id = uuid.uuid4().hex[:12]
    yield f"~/pmk-tests/{run_id}/ALMA_MAPS"
    shutil.rmtree(sshd_server.home / "pmk-tests" / run_id, ignore_errors=True)


def profile_for(server: SshdServer, tmp_path: Path, remote_dir: str, **kw: object) -> ChairProfile:
    """A validated key-auth chair profile for this sshd; ``kw`` overrides any field."""
    values: dict[str, object] = dict(
        name="test",
        host=server.host,
        ssh_port=server.port,
        ssh_user=server.user,
        auth="key",
        key_file=str(server.client_key),
        known_hosts=str(tmp_path / "known_hosts"),
        remote_maps_dir=remote_dir,
    )
    values.update(kw)
    profile = ChairProfile(**values)  # type: ignore[arg-type]
    profile.validate()
    return profile
