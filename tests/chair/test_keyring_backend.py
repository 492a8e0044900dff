"""`keyring` is a dependency (issue 29, item 6) and works on a box with no desktop keyring: the plain-file
backend when chosen explicitly, stored by one process and read back by the next; never chosen silently.

Real `keyring` + `keyrings.alt` in fresh interpreters with no D-Bus session, a private data folder.
"""

from __future__ import annotations

import json
import os
import stat
import subprocess
import sys
from pathlib import Path

import pytest

from pmk_nb.chair.secrets import PLAIN_FILE_BACKEND

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = """
import json, sys
from pmk_nb.chair.secrets import PasswordCache, SshAccount
cache = PasswordCache()
account = SshAccount("pmk", "192.0.2.7", 22)
if sys.argv[1] == "store":
    cache.store(account, "s3cret-Chair")
print(json.dumps({"persists": cache.persists, "where": cache.where, "read": cache.lookup(account)}))
"""


def _run(tmp_path: Path, action: str, *, chosen: bool) -> dict[str, object]:
    env = {k: v for k, v in os.environ.items() if k not in ("DBUS_SESSION_BUS_ADDRESS", "PYTHON_KEYRING_BACKEND")}
    env.update(PYTHONPATH=str(ROOT), XDG_DATA_HOME=str(tmp_path / "data"), XDG_CONFIG_HOME=str(tmp_path / "config"))
    if chosen:
        env["PYTHON_KEYRING_BACKEND"] = PLAIN_FILE_BACKEND
    done = subprocess.run(
        [sys.executable, "-c", SCRIPT, action], env=env, capture_output=True, text=True, timeout=60, check=True
    )
    return json.loads(done.stdout)


def test_chosen_plain_file_keyring_stores_and_a_new_process_reads_back(tmp_path: Path) -> None:
    stored = _run(tmp_path, "store", chosen=True)
    assert stored["persists"] is True and "PlaintextKeyring" in str(stored["where"])
    read = _run(tmp_path, "read", chosen=True)  # another process: the password lasted
    assert read["read"] == "s3cret-Chair"
    (ring,) = (tmp_path / "data").rglob("keyring_pass.cfg")
    assert stat.S_IMODE(ring.stat().st_mode) == 0o600


@pytest.mark.slow
def test_plain_file_keyring_is_never_used_unless_chosen(tmp_path: Path) -> None:
    stored = _run(tmp_path, "store", chosen=False)
    assert stored["persists"] is False and "--key auto" in str(stored["where"])
    assert _run(tmp_path, "read", chosen=False)["read"] is None
    assert not list((tmp_path / "data").rglob("keyring_pass.cfg"))
