"""`pmk chair ...` and `pmk send` end to end: real processes, OpenSSH upload, simulated map server."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from pmk_nb.chair.link import ChairLink
from pmk_nb.library import MapsFolder
from tests.fixtures_sim import room_grid
from tests.fixtures_ssh import SshdServer
from tests.indoorgml_samples import two_rooms

Pmk = Callable[..., subprocess.CompletedProcess[str]]


@pytest.fixture
def pmk(tmp_path: Path) -> Pmk:
    env = {**os.environ, "PMK_CONFIG_DIR": str(tmp_path / "cfg"), "PMK_MAPS_DIR": str(tmp_path / "maps")}

    def run(*args: str, stdin: str = "") -> subprocess.CompletedProcess[str]:
        return subprocess.run(
            [sys.executable, "-m", "pmk_nb.cli", *args],
            input=stdin,
            capture_output=True,
            text=True,
            env=env,
            timeout=120,
            cwd=Path(__file__).resolve().parents[2],
        )

    return run


@pytest.fixture
def house(tmp_path: Path) -> MapsFolder:
    """A two-storey building converted in the maps folder the CLI uses (PMK_MAPS_DIR)."""
    source = tmp_path / "house.gml"
    source.write_bytes(two_rooms(("F1", "F2"), width=9.0))
    folder = MapsFolder(tmp_path / "maps")
    folder.import_file(source, "house")
    folder.convert("house", 0.05)
    return folder


def add_profile(pmk: Pmk, sim: Any, server: SshdServer, remote_dir: str, tmp_path: Path) -> None:
    done = pmk(
        "chair",
        "add",
        "bench-chair",
        "--host",
        "127.0.0.1",
        "--port",
        str(sim.port),
        "--ssh-user",
        server.user,
        "--ssh-port",
        str(server.port),
        "--remote-maps-dir",
        remote_dir,
        "--known-hosts",
        str(tmp_path / "known_hosts"),
    )
    assert done.returncode == 0, done.stderr
    assert "saved chair profile 'bench-chair'" in done.stdout


@pytest.mark.slow
def test_send_storey_with_password_from_stdin(
    pmk: Pmk,
    house: MapsFolder,
    sim_factory: Any,
    sshd_server: SshdServer,
    remote_maps_dir: str,
    link_factory: Callable[[Any], ChairLink],
    tmp_path: Path,
) -> None:
    # the sim's map server reads only its maps folder (issue 30): the sshd user's home, where the upload lands
    sim = sim_factory(grid=room_grid(), reload_services=("map_update",), maps_dir=sshd_server.home)
    add_profile(pmk, sim, sshd_server, remote_maps_dir, tmp_path)

    several = pmk("send", "house", "--chair", "bench-chair", "--password-stdin", stdin=sshd_server.password + "\n")
    assert several.returncode == 2
    assert "several storeys (F1, F2): choose one with --storey" in several.stderr

    sent = pmk("send", "house", "--storey", "F2", "--password-stdin", stdin=sshd_server.password + "\n")
    assert sent.returncode == 0, sent.stderr + sent.stdout
    for step in ("upload", "detect", "reload", "confirm"):
        assert f"[{step:7}]" in sent.stdout
    assert "/map_update (mapupdate)" in sent.stdout
    assert "trusted the chair's SSH host key " + sshd_server.host_key_fingerprint in sent.stdout
    f2 = next(g for g in house.entry("house").generated if g.storey == "F2")
    remote = sshd_server.home / remote_maps_dir.removeprefix("~/")
    assert (remote / "house_F2.pgm").read_bytes() == f2.image.read_bytes()
    info = link_factory(sim).map_info(timeout=5.0)
    assert (info.width, info.height) == (f2.width, f2.height)
    assert sshd_server.password not in (tmp_path / "cfg" / "profiles.json").read_text()


@pytest.mark.slow
def test_chair_profiles_commands_and_send_errors(
    pmk: Pmk, house: MapsFolder, sim_factory: Any, sshd_server: SshdServer, remote_maps_dir: str, tmp_path: Path
) -> None:
    sim = sim_factory(grid=room_grid())
    add_profile(pmk, sim, sshd_server, remote_maps_dir, tmp_path)
    key = pmk("chair", "add", "keyed", "--host", "127.0.0.1", "--auth", "key", "--key-file", str(tmp_path / "none"))
    assert key.returncode == 2 and "key_file: invalid value" in key.stderr

    listed = pmk("chair", "list")
    assert listed.returncode == 0 and listed.stdout.startswith("* bench-chair ")
    shown = pmk("chair", "show", "bench-chair")
    assert json.loads(shown.stdout)["ssh_port"] == sshd_server.port

    tested = pmk("chair", "test", "--password-stdin", stdin=sshd_server.password + "\n")
    assert tested.returncode == 0, tested.stdout + tested.stderr
    assert f"rosbridge ws://127.0.0.1:{sim.port}: ok" in tested.stdout
    assert "will be created on first send" in tested.stdout

    bad = pmk("chair", "test", "--password-stdin", stdin="wrong\n")
    assert bad.returncode == 1 and "authentication with password failed" in bad.stdout

    missing = pmk("send", "nope", "--password-stdin", stdin="x\n")
    assert missing.returncode == 2 and "no map named 'nope'" in missing.stderr

    wrong = pmk("send", "house", "--storey", "F1", "--password-stdin", stdin="wrong\n")
    assert wrong.returncode == 2
    assert "upload: " in wrong.stderr and "authentication with password failed" in wrong.stderr

    gone = pmk("chair", "delete", "bench-chair")
    assert gone.returncode == 0
    assert pmk("chair", "list").stdout.startswith("no chair profiles")
    assert "no chair profile yet" in pmk("send", "house").stderr
