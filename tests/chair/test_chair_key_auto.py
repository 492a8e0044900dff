"""`pmk chair add --key auto` (issue 29: passwords were never remembered): one password login installs
a key made in the settings folder; every later call logs in with the key, no password, no keyring.

Against the real OpenSSH test server and the simulated map server, as tests/cli/test_cli_send.py.
"""

from __future__ import annotations

import json
import stat
import uuid
from pathlib import Path
from typing import Any

import pytest

from pmk_nb.library import MapsFolder
from tests.cli.test_cli_send import Pmk, house, pmk
from tests.fixtures_sim import room_grid
from tests.fixtures_ssh import SshdServer

__all__ = ["house", "pmk"]


def _drop_key(server: SshdServer, comment: str) -> None:
    """Remove this test's key from the test user's authorized_keys (the home outlives the session)."""
    path = server.home / ".ssh" / "authorized_keys"
    if path.is_file():
        kept = [line for line in path.read_text().splitlines() if not line.endswith(comment)]
        path.write_text("".join(line + "\n" for line in kept))


@pytest.mark.slow
def test_key_auto_then_send_without_a_password(
    pmk: Pmk, house: MapsFolder, sim_factory: Any, sshd_server: SshdServer, remote_maps_dir: str, tmp_path: Path
) -> None:
    name = f"key-{uuid.uuid4().hex[:8]}"
    sim = sim_factory(grid=room_grid(), reload_services=("map_update",), maps_dir=sshd_server.home)
    try:
        added = pmk(
            "chair",
            "add",
            name,
            "--host",
            "127.0.0.1",
            "--port",
            str(sim.port),
            "--ssh-user",
            sshd_server.user,
            "--ssh-port",
            str(sshd_server.port),
            "--remote-maps-dir",
            remote_maps_dir,
            "--known-hosts",
            str(tmp_path / "known_hosts"),
            "--key",
            "auto",
            "--password-stdin",
            stdin=sshd_server.password + "\n",
        )
        assert added.returncode == 0, added.stdout + added.stderr
        assert "installed on the chair" in added.stdout
        key = tmp_path / "cfg" / "keys" / f"{name}_ed25519"
        assert stat.S_IMODE(key.stat().st_mode) == 0o600
        profile = json.loads(pmk("chair", "show", name).stdout)
        assert (profile["auth"], profile["key_file"]) == ("key", str(key))
        assert sshd_server.password not in (tmp_path / "cfg" / "profiles.json").read_text()
        authorized = (sshd_server.home / ".ssh" / "authorized_keys").read_text()
        assert key.with_name(key.name + ".pub").read_text().split()[1] in authorized

        sent = pmk("send", "house", "--storey", "F2")  # no --password-stdin, no terminal: the key alone
        assert sent.returncode == 0, sent.stdout + sent.stderr
        assert "/map_update (mapupdate)" in sent.stdout

        again = pmk(
            "chair", "add", name, "--key", "auto", "--password-stdin", stdin=sshd_server.password + "\n"
        )  # the same key, not added twice
        assert again.returncode == 0 and "already on the chair" in again.stdout, again.stdout + again.stderr
        lines = (sshd_server.home / ".ssh" / "authorized_keys").read_text().splitlines()
        assert sum(line.endswith(f"pmk-{name}") for line in lines) == 1
    finally:
        _drop_key(sshd_server, f"pmk-{name}")
