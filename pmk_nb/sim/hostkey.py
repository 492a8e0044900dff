"""The simulator's SSH host key, kept in its state folder so that a restarted `pmk sim` is the same chair.

Issue 29: a new key at every start made the next `pmk send` refuse the chair as a changed host key
(known_hosts had the old one). A real chair keeps /etc/ssh/ssh_host_ed25519_key; the simulator keeps
``STATE/ssh_host_ed25519_key`` (0600). Two simulators starting at once on the same folder agree on one
key: creation happens under an exclusive lock.
"""

from __future__ import annotations

import fcntl
import os
from pathlib import Path

import asyncssh

from pmk_nb.fileio import atomic_write, private_dir

KEY_FILE = "ssh_host_ed25519_key"


def default_state_dir() -> Path:
    """``$PMK_SIM_STATE_DIR``, else ``<user state dir>/pmk_nb/sim``: where `pmk sim` keeps its identity."""
    env = os.environ.get("PMK_SIM_STATE_DIR", "").strip()
    if env:
        return Path(env).expanduser()
    import platformdirs

    return Path(platformdirs.user_state_dir("pmk_nb")) / "sim"


def load_host_key(state_dir: Path | None) -> asyncssh.SSHKey:
    """The host key in ``state_dir`` (made there on first use); a throwaway key when ``state_dir`` is None."""
    if state_dir is None:
        return asyncssh.generate_private_key("ssh-ed25519", comment="pmk-sim")
    private_dir(state_dir)
    path = state_dir / KEY_FILE
    with open(state_dir / (KEY_FILE + ".lock"), "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if path.is_file():
            return asyncssh.read_private_key(path)
        key = asyncssh.generate_private_key("ssh-ed25519", comment="pmk-sim")
        atomic_write(path, key.export_private_key("openssh"), mode=0o600)
        atomic_write(path.with_name(KEY_FILE + ".pub"), key.export_public_key("openssh"), mode=0o644)
        return key
