"""Shared pytest fixtures (sim): started simulated chairs, real roslibpy clients, small test maps.

- ``sim_factory(**fields)`` -> a started :class:`pmk_nb.sim.SimChair` whose :class:`~pmk_nb.sim.SimConfig`
  has these fields, on an ephemeral port, with its own maps folder under ``tmp_path`` unless ``maps_dir`` is
  given; stopped at teardown.
- ``sim_chair`` -> ``sim_factory()``: the default ROS 1 chair on the built-in demo floor.
- ``ros_factory(sim_or_port)`` -> a connected roslibpy client (asyncio transport), closed at teardown.
- ``room_grid(...)`` / ``write_test_map(...)``: a tiny walled room (optionally with an inner wall)
  and its map_server files, for reload and laser tests.
"""

from __future__ import annotations

import base64
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from pmk_nb.chair import ChairProfile
from pmk_nb.grid import FREE, OCCUPIED, OccupancyGrid
from pmk_nb.sim import SimChair, SimConfig

ROSLIBPY_TRANSPORT = "asyncio"  # twisted and asyncio cannot both be used in one process


def room_grid(
    width_m: float = 6.0,
    height_m: float = 4.0,
    resolution: float = 0.05,
    *,
    wall_x: float | None = None,
    door: tuple[float, float] | None = None,
    origin: tuple[float, float] = (0.0, 0.0),
) -> OccupancyGrid:
    """A free rectangle with a one-cell occupied border.

    ``wall_x`` adds a 2-cell wall across the room at that x, with an opening between ``door`` =
    (y0, y1) if given.
    """
    w, h = round(width_m / resolution), round(height_m / resolution)
    data = np.full((h, w), FREE, dtype=np.int8)
    data[0, :] = data[-1, :] = data[:, 0] = data[:, -1] = OCCUPIED
    if wall_x is not None:
        col = int((wall_x - origin[0]) / resolution)
        data[:, col : col + 2] = OCCUPIED
        if door is not None:
            data[
                round((door[0] - origin[1]) / resolution) : round((door[1] - origin[1]) / resolution), col : col + 2
            ] = FREE
    return OccupancyGrid(data=data, resolution=resolution, origin=(origin[0], origin[1], 0.0))


def write_test_map(grid: OccupancyGrid, directory: Path, name: str) -> Path:
    """Write ``grid`` as NAME.yaml + NAME.pgm (the safe trinary encoding); returns the YAML path."""
    from pmk_nb.rosmap import write_map

    return write_map(grid, directory, name, preview=False).yaml


def paramiko_sftp(sim: SimChair, **auth: Any) -> tuple[Any, Any]:
    """A paramiko SSH client + SFTP session to ``sim``'s endpoint, pinned to its host key (RejectPolicy)."""
    import paramiko

    client = paramiko.SSHClient()
    key_type, key_b64 = sim.sftp_host_key.split()[:2]
    host_key = paramiko.Ed25519Key(data=base64.b64decode(key_b64))
    client.get_host_keys().add(f"[127.0.0.1]:{sim.sftp_port}", key_type, host_key)
    client.set_missing_host_key_policy(paramiko.RejectPolicy())
    client.connect(
        "127.0.0.1",
        sim.sftp_port,
        username=sim.config.sftp_user,
        allow_agent=False,
        look_for_keys=False,
        timeout=10,
        **auth,
    )
    return client, client.open_sftp()


def wait_until(predicate: Callable[[], bool], timeout: float = 5.0, interval: float = 0.02) -> bool:
    """Poll ``predicate`` until true or ``timeout``; returns its last value (bounded loop)."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if predicate():
            return True
        time.sleep(interval)
    return bool(predicate())


@pytest.fixture
def sim_factory(tmp_path: Path) -> Iterator[Callable[..., SimChair]]:
    made: list[SimChair] = []

    def make(**settings: Any) -> SimChair:
        """A started chair whose SimConfig has these fields (its maps folder under tmp_path by default)."""
        settings.setdefault("maps_dir", tmp_path / f"chair{len(made)}_ALMA_MAPS")
        sim = SimChair(SimConfig(**settings))
        made.append(sim)
        return sim.start()

    yield make
    for sim in made:
        sim.stop()


@pytest.fixture
def sim_chair(sim_factory: Callable[..., SimChair]) -> SimChair:
    return sim_factory()


@pytest.fixture
def ros_factory() -> Iterator[Callable[..., Any]]:
    import roslibpy

    clients: list[Any] = []

    def connect(target: SimChair | int, timeout: float = 5.0) -> roslibpy.Ros:
        port = target.port if isinstance(target, SimChair) else int(target)
        ros = roslibpy.Ros("127.0.0.1", port, transport=ROSLIBPY_TRANSPORT)
        clients.append(ros)
        ros.run(timeout)
        return ros

    yield connect
    for ros in clients:
        ros.factory._stop = True  # no background reconnect attempts after the test (roslibpy has no API)
        try:
            if ros.is_connected:
                ros.close()
        except Exception:
            pass


@pytest.fixture
def link_factory() -> Iterator[Callable[[Any], Any]]:
    """``make(sim)`` -> a connected :class:`pmk_nb.chair.link.client.ChairLink` to that sim, closed at teardown."""
    from pmk_nb.chair.link import ChairLink

    links: list[ChairLink] = []

    def make(sim: Any) -> ChairLink:
        link = ChairLink("127.0.0.1", sim.port)
        link.connect(timeout=10.0)
        links.append(link)
        return link

    yield make
    for link in links:
        link.close()


def sim_profile(sim: Any, tmp_path: Path, **kw: Any) -> ChairProfile:
    """A validated password-auth chair profile for the simulator (rosbridge + SFTP); ``kw`` overrides."""
    values: dict[str, Any] = dict(
        name="sim",
        host="127.0.0.1",
        port=sim.port,
        ssh_user=sim.config.sftp_user,
        ssh_port=sim.sftp_port,
        auth="password",
        known_hosts=str(tmp_path / "known_hosts"),
        remote_maps_dir="~/ALMA_MAPS",
    )
    values.update(kw)
    profile = ChairProfile(**values)
    profile.validate()
    return profile
