"""Deploy end to end: real SFTP (the simulator's endpoint or OpenSSH) + the simulated map server,
reached through the real ChairLink (roslibpy)."""

from __future__ import annotations

import asyncio
import shutil
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from pmk_nb.chair.deploy import STEPS, deploy
from pmk_nb.chair.link.client import ChairLink
from pmk_nb.errors import DeployError
from pmk_nb.grid import OccupancyGrid
from pmk_nb.progress import Progress
from pmk_nb.rosmap import write_map
from tests.fixtures_sim import sim_profile
from tests.fixtures_ssh import SshdServer, profile_for


def grid_of(width: int, height: int, seed: int, origin: tuple[float, float] = (-1.5, -2.0)) -> OccupancyGrid:
    """A walled room (0.1 m cells) with a few seeded obstacles and an unknown corner."""
    rng = np.random.default_rng(seed)
    data = np.zeros((height, width), dtype=np.int8)
    data[0, :] = data[-1, :] = data[:, 0] = data[:, -1] = 100
    data[: height // 5, : width // 5] = -1
    for _ in range(4):
        r, c = int(rng.integers(2, height - 4)), int(rng.integers(2, width - 4))
        data[r : r + 2, c : c + 2] = 100
    return OccupancyGrid(data=data, resolution=0.1, origin=(origin[0], origin[1], 0.0))


def assert_publishes(link: ChairLink, grid: OccupancyGrid) -> None:
    info = link.map_info(timeout=5.0)
    assert (info.width, info.height) == (grid.width, grid.height)
    assert info.resolution == pytest.approx(grid.resolution)
    published = link.fetch_map(timeout=10.0)
    assert np.array_equal(published.data, grid.data)


@pytest.mark.parametrize(
    ("sim_ros", "services", "expected"),
    [
        ("ros1", ("change_map",), ("/change_map", "ros1")),
        ("ros2", ("load_map",), ("/map_server/load_map", "nav2")),
        ("ros1", ("map_update",), ("/map_update", "mapupdate")),
    ],
)
def test_deploy_each_reload_kind_over_sim_sftp(
    sim_factory: Any,
    link_factory: Callable[[Any], ChairLink],
    tmp_path: Path,
    sim_ros: str,
    services: tuple[str, ...],
    expected: tuple[str, str],
) -> None:
    sim = sim_factory(
        grid=grid_of(60, 40, seed=1),
        ros=sim_ros,
        reload_services=services,
        sftp_port=0,
        maps_dir=tmp_path / "chair_maps",
    )
    new = grid_of(90, 70, seed=2, origin=(-3.0, 1.25))
    files = write_map(new, tmp_path / "local", "hall")
    link = link_factory(sim)
    events: list[Progress] = []
    report = deploy(files, sim_profile(sim, tmp_path), password=sim.sftp_password, link=link, progress=events.append)

    assert (report.service.name, report.service.kind) == expected
    assert report.remote_yaml == f"/home/{sim.config.sftp_user}/ALMA_MAPS/hall.yaml"
    assert (tmp_path / "chair_maps" / "hall.pgm").read_bytes() == files.image.read_bytes()
    assert (report.map_info.width, report.map_info.height) == (90, 70)
    assert report.map_info.origin[:2] == pytest.approx((-3.0, 1.25))
    assert report.host_key.fingerprint == sim.sftp_host_key_fingerprint
    assert set(report.timings) == set(STEPS)
    assert_publishes(link, new)
    # progress: every step in order, overall fraction never goes back, ends at 1
    steps_seen = list(dict.fromkeys(p.step for p in events))
    assert steps_seen == list(STEPS)
    fractions = [p.fraction for p in events]
    assert None not in fractions
    assert fractions == sorted(fractions) and fractions[-1] == 1.0
    assert any(p.step == "upload" and 0.0 < p.fraction < 0.7 for p in events)  # byte progress inside the upload


def test_failing_reload_keeps_previous_map(
    sim_factory: Any, link_factory: Callable[[Any], ChairLink], tmp_path: Path
) -> None:
    old = grid_of(50, 50, seed=3)
    sim = sim_factory(
        grid=old, ros="ros2", reload_services=("load_map",), sftp_port=0, maps_dir=tmp_path / "chair_maps"
    )
    files = write_map(grid_of(80, 30, seed=4), tmp_path / "local", "broken")
    files.image.write_bytes(b"P5\n80 30\n255\n" + b"\x00" * 100)  # truncated: the map server must refuse it
    link = link_factory(sim)
    with pytest.raises(DeployError) as info:
        deploy(files, sim_profile(sim, tmp_path), password=sim.sftp_password, link=link)
    err = info.value
    assert err.step == "reload" and err.keeps_old_map is True
    assert str(err).count("keeps its previous map") == 1
    assert "code 2" in str(err)  # Nav2 INVALID_MAP_DATA
    assert err.__cause__ is not None
    assert_publishes(link, old)


def test_no_reload_service_fails_at_detect(
    sim_factory: Any, link_factory: Callable[[Any], ChairLink], tmp_path: Path
) -> None:
    old = grid_of(40, 40, seed=5)
    sim = sim_factory(grid=old, reload_services=(), sftp_port=0, maps_dir=tmp_path / "chair_maps")
    files = write_map(grid_of(30, 30, seed=6), tmp_path / "local", "m")
    link = link_factory(sim)
    with pytest.raises(DeployError, match="no map reload service") as info:
        deploy(files, sim_profile(sim, tmp_path), password=sim.sftp_password, link=link)
    assert info.value.step == "detect" and info.value.keeps_old_map is True
    assert (tmp_path / "chair_maps" / "m.yaml").exists()  # uploaded, just not loaded
    assert_publishes(link, old)


def test_wrong_password_fails_at_upload(
    sim_factory: Any, link_factory: Callable[[Any], ChairLink], tmp_path: Path
) -> None:
    sim = sim_factory(grid=grid_of(20, 20, seed=7), sftp_port=0, maps_dir=tmp_path / "chair_maps")
    files = write_map(grid_of(30, 30, seed=8), tmp_path / "local", "m")
    with pytest.raises(DeployError, match="authentication with password failed") as info:
        deploy(files, sim_profile(sim, tmp_path), password="wrong", link=link_factory(sim))
    assert info.value.step == "upload" and info.value.keeps_old_map is True
    assert not (tmp_path / "chair_maps" / "m.yaml").exists()


class SplitLink:
    """Reload on one chair, read the map from another: a chair whose reload service belongs to a
    different map server than the one publishing /map (misconfigured namespaces)."""

    def __init__(self, reloads: ChairLink, publishes: ChairLink) -> None:
        self.reloads, self.publishes = reloads, publishes
        self.discovery = reloads.discovery

    def reload_map(self, *args: Any, **kw: Any) -> None:
        self.reloads.reload_map(*args, **kw)

    def map_info(self, timeout: float = 5.0) -> Any:
        return self.publishes.map_info(timeout)


@pytest.mark.slow
def test_confirm_step_catches_a_map_that_did_not_change(
    sim_factory: Any, link_factory: Callable[[Any], ChairLink], tmp_path: Path
) -> None:
    maps = tmp_path / "chair_maps"
    reloading = sim_factory(grid=grid_of(20, 20, seed=9), sftp_port=0, maps_dir=maps)
    publishing = sim_factory(grid=grid_of(20, 20, seed=9), maps_dir=maps)
    files = write_map(grid_of(33, 44, seed=10), tmp_path / "local", "m")
    link = SplitLink(link_factory(reloading), link_factory(publishing))
    with pytest.raises(DeployError, match="still publishes 20x20") as info:
        deploy(
            files, sim_profile(reloading, tmp_path), password=reloading.sftp_password, link=link, confirm_timeout=1.5
        )
    assert info.value.step == "confirm" and info.value.keeps_old_map is None


def test_same_size_map_is_confirmed_by_its_cells(
    sim_factory: Any, link_factory: Callable[[Any], ChairLink], tmp_path: Path
) -> None:
    first = grid_of(64, 48, seed=11)
    sim = sim_factory(grid=first, sftp_port=0, maps_dir=tmp_path / "chair_maps")
    second = grid_of(64, 48, seed=12)  # same metadata, other cells
    files = write_map(second, tmp_path / "local", "same")
    link = link_factory(sim)
    report = deploy(files, sim_profile(sim, tmp_path), password=sim.sftp_password, link=link)
    assert "confirmed by cells" in report.notes
    assert_publishes(link, second)


@pytest.mark.slow
def test_openssh_upload_then_sim_reload(
    sshd_server: SshdServer,
    remote_maps_dir: str,
    sim_factory: Any,
    link_factory: Callable[[Any], ChairLink],
    tmp_path: Path,
) -> None:
    """The real sshd writes into the test user's home; the simulator's map server loads that path (its
    maps folder is that home: a map server reads only its folder, issue 30)."""
    sim = sim_factory(grid=grid_of(30, 30, seed=13), reload_services=("change_map",), maps_dir=sshd_server.home)
    new = grid_of(75, 55, seed=14, origin=(0.5, 0.25))
    files = write_map(new, tmp_path / "local", "real")
    profile = profile_for(sshd_server, tmp_path, remote_maps_dir, name="real", host="127.0.0.1", port=sim.port)
    link = link_factory(sim)
    report = deploy(files, profile, link=link)
    assert report.remote_yaml.startswith(str(sshd_server.home) + "/pmk-tests/")
    assert report.host_key.fingerprint == sshd_server.host_key_fingerprint
    assert_publishes(link, new)
    shutil.rmtree(Path(report.remote_yaml).parent, ignore_errors=True)


def test_profile_naming_a_missing_service_fails_at_detect(
    sim_factory: Any, link_factory: Callable[[Any], ChairLink], tmp_path: Path
) -> None:
    sim = sim_factory(grid=grid_of(20, 20, seed=15), sftp_port=0, maps_dir=tmp_path / "chair_maps")
    files = write_map(grid_of(25, 25, seed=16), tmp_path / "local", "m")
    profile = sim_profile(sim, tmp_path, reload_service="/robot/load_map")
    with pytest.raises(DeployError, match="has no service /robot/load_map") as info:
        deploy(files, profile, password=sim.sftp_password, link=link_factory(sim))
    assert info.value.step == "detect" and info.value.keeps_old_map is True
    assert "uploaded to" in str(info.value) and str(info.value).count("keeps its previous map") == 1


def answer_late(sim: Any, monkeypatch: pytest.MonkeyPatch, delay: float = 2.0) -> None:
    """The chair acts on the reload but its answer comes ``delay`` s late: past the dashboard's reload
    timeout however slow the test machine (a 1 ms timeout alone lost the race on a loaded machine)."""
    load = sim.mapserver.load

    async def late(path: str) -> Any:
        result = await load(path)
        await asyncio.sleep(delay)
        return result

    monkeypatch.setattr(sim.mapserver, "load", late)


@pytest.mark.slow
def test_lost_reload_answer_is_followed_by_a_check_of_the_map(
    sim_factory: Any, link_factory: Callable[[Any], ChairLink], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Issue 9, fault 2: the answer is lost (timeout) but the chair loaded the map: say so, succeed."""
    sim = sim_factory(grid=grid_of(20, 20, seed=17), sftp_port=0, maps_dir=tmp_path / "chair_maps")
    answer_late(sim, monkeypatch)
    files = write_map(grid_of(900, 900, seed=18), tmp_path / "local", "big")
    link = link_factory(sim)
    report = deploy(files, sim_profile(sim, tmp_path), password=sim.sftp_password, link=link, reload_timeout=0.5)
    assert any("answer was lost" in note for note in report.notes), report.notes
    assert (report.map_info.width, report.map_info.height) == (900, 900)


@pytest.mark.slow
def test_lost_reload_answer_does_not_claim_the_old_map_stays(
    sim_factory: Any, link_factory: Callable[[Any], ChairLink], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    sim = sim_factory(grid=grid_of(20, 20, seed=17), sftp_port=0, maps_dir=tmp_path / "chair_maps")
    answer_late(sim, monkeypatch)
    files = write_map(grid_of(900, 900, seed=18), tmp_path / "local", "big")
    files.image.write_bytes(files.image.read_bytes()[:-1000])  # header fine, cells missing: not loadable
    with pytest.raises(DeployError) as info:
        deploy(
            files,
            sim_profile(sim, tmp_path),
            password=sim.sftp_password,
            link=link_factory(sim),
            reload_timeout=0.5,
            confirm_timeout=1.5,
        )
    err = info.value
    assert err.step == "reload" and err.keeps_old_map is None
    assert "Checked afterwards" in str(err) and "still publishes 20x20" in str(err)
    assert "keeps its previous map" not in str(err)
