"""`--json` for the commands a script drives against a chair (issue 29): chair test and send, end to end.

Real processes, the real OpenSSH test server and the simulated map server, as tests/cli/test_cli_send.py.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

from pmk_nb.library import MapsFolder
from tests.cli.test_cli_send import Pmk, add_profile, house, pmk
from tests.fixtures_sim import room_grid
from tests.fixtures_ssh import SshdServer

__all__ = ["house", "pmk"]


@pytest.mark.slow
def test_chair_test_and_send_print_json(
    pmk: Pmk, house: MapsFolder, sim_factory: Any, sshd_server: SshdServer, remote_maps_dir: str, tmp_path: Path
) -> None:
    sim = sim_factory(grid=room_grid(), reload_services=("map_update",), maps_dir=sshd_server.home)
    add_profile(pmk, sim, sshd_server, remote_maps_dir, tmp_path)

    tested = pmk("chair", "test", "--json", "--password-stdin", stdin=sshd_server.password + "\n")
    assert tested.returncode == 0, tested.stdout + tested.stderr
    doc = json.loads(tested.stdout)
    assert doc["ok"] is True and doc["profile"] == "bench-chair"
    assert [(p["part"], p["ok"], p["error"]) for p in doc["parts"]] == [("rosbridge", True, None), ("ssh", True, None)]
    assert sshd_server.host_key_fingerprint in doc["parts"][1]["detail"]

    bad = pmk("chair", "test", "--json", "--password-stdin", stdin="wrong\n")
    failed = json.loads(bad.stdout)
    assert bad.returncode == 1 and failed["ok"] is False
    assert failed["parts"][1]["ok"] is False and failed["parts"][1]["error"]

    sent = pmk("send", "house", "--storey", "F2", "--json", "--password-stdin", stdin=sshd_server.password + "\n")
    assert sent.returncode == 0, sent.stdout + sent.stderr
    report = json.loads(sent.stdout)  # stdout is the one JSON document: no progress lines
    f2 = next(g for g in house.entry("house").generated if g.storey == "F2")
    assert report["ok"] is True and report["service_kind"] == "mapupdate"
    assert (report["width"], report["height"]) == (f2.width, f2.height) and report["elapsed_s"] > 0

    missing = pmk("send", "nope", "--json", "--password-stdin", stdin="x\n")
    error = json.loads(missing.stdout)
    assert missing.returncode == 2 and error["ok"] is False and error["error"] == "LibraryError"
    assert error["command"] == "send" and "nope" in error["message"]
