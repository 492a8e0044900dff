"""SimConfig: everything a simulated chair is started with, as one value with every default declared once.

``SimChair(SimConfig(port=0, ros="ros2", ...))``: the chair keeps it whole (``SimChair.config``) and reads
every setting from it; no keyword copy of these fields exists beside it (issue 42), so a setting is added
here once. The checks (known ROS version and bridge, positive rates, SFTP login rules, reload services)
are :class:`~pmk_nb.sim.server.SimChair`'s, which raises :class:`~pmk_nb.sim.server.SimError`.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, fields
from pathlib import Path
from typing import TYPE_CHECKING

from pmk_nb.clock import MONOTONIC, WALL, Clock
from pmk_nb.defaults import DEFAULT_CHAIR_WIDTH
from pmk_nb.sim.bridge_modes import DEFAULT_BRIDGE, BridgeMode
from pmk_nb.sim.session import DEFAULT_CLIENT_QUEUE

if TYPE_CHECKING:
    from pmk_nb.grid import OccupancyGrid
    from pmk_nb.sim.chair import DriveLimits
    from pmk_nb.sim.messages import RosVersion


@dataclass(frozen=True)
class SimConfig:
    """A simulated chair's settings (see :class:`~pmk_nb.sim.server.SimChair` for what each does)."""

    map_yaml: Path | str | None = None  # the map to serve (None: ``grid``, else the generated demo floor)
    grid: OccupancyGrid | None = None
    host: str = "127.0.0.1"
    port: int = 0  # 0: a free port, chosen at start()
    ros: RosVersion = "ros1"  # message spelling: "ros1" or "ros2"
    odom_rate: float = 50.0  # Hz
    scan_rate: float = 20.0  # Hz
    rays: int = 720
    range_max: float = 10.0  # metres
    laser_blind: tuple[float, float] | None = None  # (start, end) angles the laser cannot see
    patrol: bool = False
    sftp_port: int | None = None  # None: no SFTP server
    sftp_user: str = "pmk"
    sftp_password: str | None = None  # None: a random one (password login on)
    sftp_authorized_key: str | Path | None = None
    sftp_password_login: bool = True
    maps_dir: Path | str | None = None  # None: a temporary folder, removed with the chair
    start_pose: tuple[float, float, float] | None = None  # None: an open spot of the map
    footprint_radius: float = DEFAULT_CHAIR_WIDTH / 2  # metres
    reload_services: Sequence[str] | None = None  # None: the ROS version's usual ones (sim.mapserver)
    limits: DriveLimits | None = None  # None: DriveLimits()
    seed: int = 0
    client_queue: int = DEFAULT_CLIENT_QUEUE  # topic messages buffered per client before the oldest drop
    nav_actions: bool = True  # False: goal topics only, no move_base / Nav2 action servers
    tls: tuple[Path | str, Path | str] | None = None  # (certfile, keyfile): serve wss://
    bridge: BridgeMode = DEFAULT_BRIDGE
    state_dir: Path | str | None = None  # where the SSH host key is kept across processes
    auth_secret: str | None = None  # rosauth's secret: every client's first op must be a granted ``auth``
    clock: Clock = MONOTONIC  # the physics and the loops' rates (a VirtualClock: steps only as it advances)
    wall_clock: Clock = WALL  # the messages' stamps


def field_names() -> tuple[str, ...]:
    """SimConfig's field names, in order."""
    return tuple(f.name for f in fields(SimConfig))
