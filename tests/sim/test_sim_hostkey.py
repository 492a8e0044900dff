"""`pmk sim` keeps its SSH host key in its state folder (issue 29): a restarted simulator is the same chair.

Before, every start made a new key and the next `pmk send` refused the chair as a changed host key.
"""

from __future__ import annotations

import re
import signal
import stat
from pathlib import Path

import pytest

from pmk_nb.sim.hostkey import KEY_FILE, load_host_key
from tests.cli.test_sim_cli import start_cli


def _fingerprint(lines: list[str]) -> str:
    found = re.search(r"sftp host key: (SHA256:\S+)", "\n".join(lines))
    assert found, lines
    return found.group(1)


def _run_once(state: Path, maps: Path) -> str:
    proc, lines = start_cli("--sftp-port", "0", "--maps-dir", str(maps), "--state-dir", str(state))
    try:
        return _fingerprint(lines)
    finally:
        proc.send_signal(signal.SIGTERM)
        assert proc.wait(timeout=20) == 0


@pytest.mark.slow
def test_restarted_sim_process_keeps_its_host_key(tmp_path: Path) -> None:
    state = tmp_path / "state"
    first = _run_once(state, tmp_path / "maps")
    second = _run_once(state, tmp_path / "maps")
    assert first == second
    assert stat.S_IMODE((state / KEY_FILE).stat().st_mode) == 0o600
    other = _run_once(tmp_path / "other_state", tmp_path / "maps")
    assert other != first  # a different chair (state folder) has its own key


def test_without_a_state_folder_each_key_is_new(tmp_path: Path) -> None:
    kept = load_host_key(tmp_path)
    assert load_host_key(tmp_path).get_fingerprint("sha256") == kept.get_fingerprint("sha256")
    assert load_host_key(None).get_fingerprint("sha256") != load_host_key(None).get_fingerprint("sha256")
